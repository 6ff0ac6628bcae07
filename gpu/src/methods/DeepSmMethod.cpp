// deep-sm: deep shadow maps (Lokovic & Veach 2000) in the pcss method's frame and lookup
// (methods/PcssShadow.h with DeepSmOptions): per texel of each face's map from the light's
// centre, the transmittance along depth from S x S rays through the texel (partial coverage,
// alpha and translucency; geometry/shadow/DeepShadowMap.h), built on the CPU when the light or
// the casters change; each frame, pcss's blocker search and filtering over the light read the
// texels' transmittance at the receiver instead of a depth comparison.
#include "engine/Method.h"
#include "engine/MethodOptions.h"
#include "methods/PcssShadow.h"

namespace gpu {

namespace {

class DeepSmMethod final : public VisibilityMethod {
public:
    explicit DeepSmMethod(const MethodResources& r) : mShadow(r, deepSmOptions(r.parameters)) {}

    void execute(const FrameContext& ctx) override { mShadow.execute(ctx); }
    bool executeMultiplied(const FrameContext& ctx) override {
        mShadow.execute(ctx, true); // the lookup writes every pixel once
        return true;
    }

private:
    PcssShadow mShadow;
};

} // namespace

std::unique_ptr<VisibilityMethod> createDeepSmMethod(const MethodResources& r) {
    return std::make_unique<DeepSmMethod>(r);
}

} // namespace gpu

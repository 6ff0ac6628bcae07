// pcss: percentage-closer soft shadows (Fernando 2005), the shadow-map baseline: the shadow
// maps and lookup of methods/PcssShadow.h over every pixel.
#include "engine/Method.h"
#include "engine/MethodOptions.h"
#include "methods/PcssShadow.h"

namespace gpu {

namespace {

class PcssMethod final : public VisibilityMethod {
public:
    explicit PcssMethod(const MethodResources& r) : mShadow(r, pcssOptions(r.parameters)) {}

    void execute(const FrameContext& ctx) override { mShadow.execute(ctx); }
    bool executeMultiplied(const FrameContext& ctx) override {
        mShadow.execute(ctx, true); // the lookup writes every pixel once
        return true;
    }

private:
    PcssShadow mShadow;
};

} // namespace

std::unique_ptr<VisibilityMethod> createPcssMethod(const MethodResources& r) {
    return std::make_unique<PcssMethod>(r);
}

} // namespace gpu

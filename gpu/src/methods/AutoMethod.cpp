// auto (the contract's default): per casting object the path geometry/shadow/AutoChoice.h decides —
// penumbra wedges (`wedges-bitmask` with its defaults — potential silhouettes, the ratio
// estimator — unless the `wedges` parameter picks another wedge method), occlusion textures
// (asked for by the scene JSON), sample maps or pcss (the alpha path of alpha-tested objects:
// sample maps for an object in front of the light, pcss around it; pcss or occlusion textures
// for all with alpha=pcss|occlusion) — run each on its own casters and composed in one frame as
// V = V_wedges · V_occlusion · V_pcss · V_sample-maps (the sets of occluders treated as
// independent). A caster's
// path is decided the first frame it is seen and then kept, so that a moving light never flips
// it. The same composition serves a method asked for by name that occludes with whole
// triangles (hard, reference, the wedge methods) on a scene with alpha-tested objects
// (createAlphaComposite): that method shadows the opaque objects, auto's alpha path the
// alpha-tested ones, and each object's choice says so.
#include "engine/DebugViews.h"
#include "engine/Method.h"
#include "methods/MethodUtil.h"
#include "engine/MethodOptions.h"
#include "passes/FullscreenPass.h"
#include "engine/ShaderBindings.h"

#include <geometry/scene/AlphaMask.h>
#include <geometry/shadow/AutoChoice.h>
#include <geometry/shadow/SampleMapFrame.h>
#include <geometry/core/Error.h>

#include <optional>

namespace gpu {

namespace {

std::unique_ptr<VisibilityMethod> createByName(const MethodResources& r, std::string_view name,
                                              const std::vector<ParameterValue>& given = {}) {
    const MethodInfo& info = findMethod(name);
    const std::vector<ParameterValue> parameters = resolveParameters(info, given);
    return info.create(MethodResources{r.shaders, r.scene, parameters});
}

// The parameters that turn off a path's own-plane (horizon) term, for a composition whose wedge
// path counts the plane already.
std::vector<ParameterValue> withoutOwnPlane(geometry::ShadowPath path) {
    switch (path) {
    case geometry::ShadowPath::Pcss:
    case geometry::ShadowPath::Occlusion:
        return {{"horizon", "off"}};
    case geometry::ShadowPath::SampleMaps:
        return {{"plane", "off"}};
    case geometry::ShadowPath::Wedges:
        break;
    }
    return {};
}

// "grate (MASK 0.50), flame (BLEND as MASK 0.50)": the alpha-tested materials the mesh uses.
std::string alphaTestedMaterials(const geometry::MeshData& mesh) {
    std::vector<bool> used(mesh.materials.size(), false);
    for (const std::uint32_t m : mesh.triangleMaterial)
        if (m < used.size()) used[m] = true;
    std::string text;
    for (std::size_t m = 0; m < mesh.materials.size(); ++m) {
        const geometry::Material& material = mesh.materials[m];
        if (!used[m] || !geometry::isAlphaMasked(material)) continue;
        char cutoff[48];
        std::snprintf(cutoff, sizeof(cutoff), "%s %.2f",
                      material.alphaMode == geometry::AlphaMode::Blend ? "BLEND as MASK" : "MASK",
                      geometry::effectiveAlphaCutoff(material));
        text += (text.empty() ? "" : ", ") +
                (material.name.empty() ? "material " + std::to_string(m) : material.name) + " (" +
                cutoff + ")";
    }
    return text;
}

class AutoMethod final : public VisibilityMethod {
public:
    explicit AutoMethod(const MethodResources& r)
        : mResources{r.shaders, r.scene, {}}, mWedgeMethodName(autoOptions(r.parameters).wedgeMethod),
          mAlphaPath(alphaPath(autoOptions(r.parameters).alphaMethod)),
          mProduct(r.shaders, "auto-compose") {
        mWedges = createByName(r, mWedgeMethodName);
    }

    // The composition for `primary` (asked for by name, with its parameters) on a scene with
    // alpha-tested objects: `primary` for every opaque object, auto's alpha path (its default)
    // for the rest.
    AutoMethod(const MethodResources& r, const MethodInfo& primary)
        : mResources{r.shaders, r.scene, {}}, mWedgeMethodName(primary.name),
          mAlphaPath(alphaPath(autoOptions({}).alphaMethod)),
          mProduct(r.shaders, "auto-compose"), mPrimaryAsked(true) {
        mWedges = primary.create(r);
    }

    void resize(int width, int height) override {
        mWidth = width;
        mHeight = height;
        mWedges->resize(width, height);
        for (auto& variant : mPathMethods)
            for (auto& m : variant)
                if (m) m->resize(width, height);
        mProduct.resize(width, height);
    }

    std::size_t targetBytesPerPixel() const override {
        // The saved V (R32F) and the methods'; shadow maps and occlusion textures do not scale with
        // the image.
        std::size_t bytes = VisibilityProduct::kBytesPerPixel + mWedges->targetBytesPerPixel();
        for (const auto& variant : mPathMethods)
            for (const auto& m : variant)
                if (m) bytes += m->targetBytesPerPixel();
        return bytes;
    }

    void execute(const FrameContext& ctx) override {
        decide(ctx);
        // The casters of each path, in the order they are composed: wedges, occlusion, pcss,
        // sample maps.
        std::vector<std::uint32_t> casters[kPaths];
        for (const std::uint32_t c : ctx.casterSubset)
            casters[static_cast<int>(mChoices[c].path)].push_back(c);
        for (const std::uint32_t c : ctx.casterSubset)
            ctx.stats.objectChoices.push_back(
                {ctx.casters.sceneObject(c),
                 mPrimaryAsked && mChoices[c].path == geometry::ShadowPath::Wedges
                     ? mWedgeMethodName
                     : geometry::toString(mChoices[c].path),
                 mChoices[c].reason});
        const auto count = [&](geometry::ShadowPath p) {
            return static_cast<double>(casters[static_cast<int>(p)].size());
        };
        ctx.addCounter(mPrimaryAsked ? "opaque_objects" : "auto_wedge_objects",
                       count(geometry::ShadowPath::Wedges));
        ctx.addCounter(mPrimaryAsked ? "alpha_tested_objects_by_occlusion" : "auto_occlusion_objects",
                       count(geometry::ShadowPath::Occlusion));
        ctx.addCounter(mPrimaryAsked ? "alpha_tested_objects_by_pcss" : "auto_pcss_objects",
                       count(geometry::ShadowPath::Pcss));
        ctx.addCounter(mPrimaryAsked ? "alpha_tested_objects_by_sample_maps"
                                     : "auto_sample_maps_objects",
                       count(geometry::ShadowPath::SampleMaps));

        mWedgeCasters = casters[static_cast<int>(geometry::ShadowPath::Wedges)];
        // V = the product of the paths' V: the first path writes V, each later one is run on
        // a cleared target and multiplied with what came before.
        // The receiver's own plane is counted once: by the wedge path where it counts it for
        // every receiver (wedges-bitmask's potential silhouettes; reference), else by each path.
        const bool planeCounted = !casters[0].empty() && mWedges->countsOwnPlane();
        ctx.addCounter("own_plane_by_wedge_path", planeCounted ? 1.0 : 0.0);
        bool first = true;
        for (int p = 0; p < kPaths; ++p) {
            if (casters[p].empty() && !(p == 0 && ctx.casterSubset.empty())) continue;
            VisibilityMethod& method =
                p == 0 ? *mWedges
                       : pathMethod(ctx, static_cast<geometry::ShadowPath>(p), !planeCounted);
            const FrameContext sub = subContext(ctx, casters[p]);
            if (first) {
                method.execute(sub);
            } else if (!method.executeMultiplied(sub)) {
                mProduct.beforeFactor(ctx);
                method.execute(sub);
                mProduct.afterFactor(ctx);
            }
            first = false;
        }
    }

    // Wedge views are the wedge method's, on the casters it served this frame.
    bool drawDebug(DebugView view, const FrameContext& ctx, DebugViews& debug) override {
        if (!mPrimaryAsked && view != DebugView::WedgeWireframe && view != DebugView::GroupParts)
            return false;
        if (mWedgeCasters.empty()) {
            debug.note = std::string(debugViewInfo(view).name) + ": " +
                         (mPrimaryAsked ? "every caster is alpha-tested and took the alpha "
                                          "path (no " + mWedgeMethodName + " casters)"
                                        : std::string("auto gave every caster to the alpha "
                                                      "path (no wedges)")) +
                         "; showing the shaded image";
            return false;
        }
        return mWedges->drawDebug(view, subContext(ctx, mWedgeCasters), debug);
    }

private:
    static FrameContext subContext(const FrameContext& ctx,
                                   const std::vector<std::uint32_t>& casters) {
        FrameContext sub = ctx;
        sub.casterSubset = casters;
        return sub;
    }

    // Each caster's path, the first frame it is seen (its silhouette density is measured from
    // that frame's light centre).
    void decide(const FrameContext& ctx) {
        if (mChoices.size() == ctx.casters.size()) return;
        mChoices.clear();
        for (std::size_t c = 0; c < ctx.casters.size(); ++c) {
            const geometry::SceneObject& object = ctx.scene.objects[ctx.casters.sceneObject(c)];
            geometry::CasterFacts facts;
            facts.requested = object.method;
            facts.alphaMasked = geometry::hasAlphaMask(object.mesh);
            if (facts.alphaMasked) {
                facts.alphaMaterials = alphaTestedMaterials(object.mesh);
                facts.sampleMapsHold = geometry::sampleMapsHold(ctx.light, object.mesh.bounds());
            }
            facts.alphaPath = mAlphaPath;
            facts.topology = ctx.casters.topology(c).stats();
            facts.silhouetteEdges = ctx.casters.frame(c).edges.size();
            if (mPrimaryAsked) {
                // Only the alpha test decides: the scene JSON's "method" is auto's to read.
                if (!facts.alphaMasked) {
                    mChoices.push_back({geometry::ShadowPath::Wedges, "opaque: " + mWedgeMethodName});
                    continue;
                }
                facts.requested = geometry::ShadowMethod::Auto;
                geometry::ShadowPathChoice alpha = geometry::chooseShadowPath(facts);
                alpha.reason = mWedgeMethodName + " occludes with whole triangles, so auto's alpha "
                               "path, " + std::string(geometry::toString(alpha.path)) +
                               ", shadows this object: " + alpha.reason;
                mChoices.push_back(std::move(alpha));
                continue;
            }
            mChoices.push_back(geometry::chooseShadowPath(facts));
        }
    }

    static constexpr int kPaths = 4; // geometry::ShadowPath: Wedges, Occlusion, Pcss, SampleMaps

    static geometry::ShadowPath alphaPath(const std::string& name) {
        return name == "occlusion" ? geometry::ShadowPath::Occlusion
               : name == "pcss"    ? geometry::ShadowPath::Pcss
                                   : geometry::ShadowPath::SampleMaps;
    }

    // The method of a path other than wedges, built on first use with its defaults (ownPlane)
    // or with its own-plane term off.
    VisibilityMethod& pathMethod(const FrameContext& ctx, geometry::ShadowPath path,
                                 bool ownPlane) {
        std::unique_ptr<VisibilityMethod>& m =
            mPathMethods[ownPlane ? 1 : 0][static_cast<int>(path)];
        if (!m) {
            const std::string name = geometry::toString(path);
            const MethodInfo& info = findMethod(name);
            if (!info.implemented()) {
                for (std::size_t c = 0; c < mChoices.size(); ++c)
                    if (mChoices[c].path == path)
                        throw geometry::InputError(
                            "auto: object '" +
                            ctx.scene.objects[ctx.casters.sceneObject(c)].name + "' needs " +
                            name + " (" + mChoices[c].reason +
                            "), which is not implemented yet; give it \"method\": \"wedges\" "
                            "or \"none\" in the scene JSON");
            }
            m = createByName(mResources, name,
                             ownPlane ? std::vector<ParameterValue>{} : withoutOwnPlane(path));
            m->resize(mWidth, mHeight);
        }
        return *m;
    }

    MethodResources mResources; // shaders and scene (the parameters are auto's own)
    std::string mWedgeMethodName;
    geometry::ShadowPath mAlphaPath; // what alpha-tested objects take (auto's alpha parameter;
                                     // SampleMaps: Pcss for objects it cannot hold)
    std::unique_ptr<VisibilityMethod> mWedges;
    // [without, with the own-plane term][Occlusion, Pcss, SampleMaps]; [.][0] unused.
    std::unique_ptr<VisibilityMethod> mPathMethods[2][kPaths];
    VisibilityProduct mProduct;
    int mWidth = 0, mHeight = 0;
    std::vector<geometry::ShadowPathChoice> mChoices; // per caster
    std::vector<std::uint32_t> mWedgeCasters;         // this frame's, for the debug views
    bool mPrimaryAsked = false; // createAlphaComposite: mWedges is the method asked for
};

} // namespace

std::unique_ptr<VisibilityMethod> createAutoMethod(const MethodResources& r) {
    return std::make_unique<AutoMethod>(r);
}

std::unique_ptr<VisibilityMethod> createAlphaComposite(const MethodResources& r,
                                                       const MethodInfo& primary) {
    return std::make_unique<AutoMethod>(r, primary);
}

} // namespace gpu

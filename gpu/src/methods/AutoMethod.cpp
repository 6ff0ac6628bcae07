// auto (the contract's default): per casting object the path geometry/shadow/AutoChoice.h decides —
// penumbra wedges (`wedges-bitmask` with its defaults — potential silhouettes, the ratio
// estimator — unless the `wedges` parameter picks another wedge method) or
// occlusion textures — run each on its own casters and composed in one frame as
// V = V_wedges · V_occlusion (the two sets of occluders treated as independent). A caster's path
// is decided the first frame it is seen and then kept, so that a moving light never flips it.
// The same composition serves a method asked for by name that occludes with whole triangles
// (hard, reference, the wedge methods) on a scene with alpha-tested objects
// (createAlphaComposite): that method shadows the opaque objects, occlusion textures — auto's
// alpha path — the alpha-tested ones, and each object's choice says so.
#include "engine/DebugViews.h"
#include "engine/Method.h"
#include "methods/MethodUtil.h"
#include "engine/MethodOptions.h"
#include "passes/FullscreenPass.h"
#include "engine/ShaderBindings.h"

#include <geometry/scene/AlphaMask.h>
#include <geometry/shadow/AutoChoice.h>
#include <geometry/core/Error.h>

#include <optional>

namespace gpu {

namespace {

std::unique_ptr<VisibilityMethod> createByName(const MethodResources& r, std::string_view name) {
    const MethodInfo& info = findMethod(name);
    const std::vector<ParameterValue> defaults = resolveParameters(info, {});
    return info.create(MethodResources{r.shaders, r.scene, defaults});
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
          mMultiply(r.shaders, "blend-multiply.frag", "auto-compose", kMultiplyState) {
        mWedges = createByName(r, mWedgeMethodName);
    }

    // The composition for `primary` (asked for by name, with its parameters) on a scene with
    // alpha-tested objects: `primary` for every opaque object, occlusion textures for the rest.
    AutoMethod(const MethodResources& r, const MethodInfo& primary)
        : mResources{r.shaders, r.scene, {}}, mWedgeMethodName(primary.name),
          mMultiply(r.shaders, "blend-multiply.frag", "auto-compose", kMultiplyState),
          mPrimaryAsked(true) {
        mWedges = primary.create(r);
    }

    void resize(int width, int height) override {
        mWidth = width;
        mHeight = height;
        mWedges->resize(width, height);
        if (mOcclusion) mOcclusion->resize(width, height);
        mSaved = Texture({.width = width, .height = height, .format = GL_R32F,
                          .label = "auto-wedge-visibility"});
    }

    std::size_t targetBytesPerPixel() const override {
        // mSaved (R32F) and the wedge method's; occlusion textures do not scale with the image.
        return 4 + mWedges->targetBytesPerPixel() +
               (mOcclusion ? mOcclusion->targetBytesPerPixel() : 0);
    }

    void execute(const FrameContext& ctx) override {
        decide(ctx);
        std::vector<std::uint32_t> wedgeCasters, occlusionCasters;
        for (const std::uint32_t c : ctx.casterSubset)
            (mChoices[c].path == geometry::ShadowPath::Occlusion ? occlusionCasters
                                                                 : wedgeCasters)
                .push_back(c);
        for (const std::uint32_t c : ctx.casterSubset)
            ctx.stats.objectChoices.push_back(
                {ctx.casters.sceneObject(c),
                 mPrimaryAsked && mChoices[c].path == geometry::ShadowPath::Wedges
                     ? mWedgeMethodName
                     : geometry::toString(mChoices[c].path),
                 mChoices[c].reason});
        ctx.addCounter(mPrimaryAsked ? "opaque_objects" : "auto_wedge_objects",
                       static_cast<double>(wedgeCasters.size()));
        ctx.addCounter(mPrimaryAsked ? "alpha_tested_objects_by_occlusion" : "auto_occlusion_objects",
                       static_cast<double>(occlusionCasters.size()));

        mWedgeCasters = wedgeCasters;
        if (occlusionCasters.empty()) {
            mWedges->execute(subContext(ctx, wedgeCasters));
            return;
        }
        VisibilityMethod& occlusion = occlusionMethod(ctx);
        if (wedgeCasters.empty()) {
            occlusion.execute(subContext(ctx, occlusionCasters));
            return;
        }
        const Targets& t = ctx.targets;
        mWedges->execute(subContext(ctx, wedgeCasters));
        {
            ScopedPass pass(&ctx.timers, "compose");
            glCopyImageSubData(t.visibility.id(), GL_TEXTURE_2D, 0, 0, 0, 0, mSaved.id(),
                               GL_TEXTURE_2D, 0, 0, 0, 0, t.width, t.height, 1);
            const float zero = 0.0f; // methods start from V = 0 (gpu/src/engine/Method.h)
            glClearTexImage(t.visibility.id(), 0, GL_RED, GL_FLOAT, &zero);
        }
        occlusion.execute(subContext(ctx, occlusionCasters));
        {
            ScopedPass pass(&ctx.timers, "compose");
            glBindTextureUnit(TEXUNIT_SILHOUETTE, mSaved.id());
            mMultiply.execute(t.visibilityFbo, t.width, t.height, kMultiplyState,
                              [] { glUniform1f(0, 0.0f); }); // blend-multiply: clamp(0 + V)
        }
    }

    // Wedge views are the wedge method's, on the casters it served this frame.
    bool drawDebug(DebugView view, const FrameContext& ctx, DebugViews& debug) override {
        if (!mPrimaryAsked && view != DebugView::WedgeWireframe && view != DebugView::GroupParts)
            return false;
        if (mWedgeCasters.empty()) {
            debug.note = std::string(debugViewInfo(view).name) + ": " +
                         (mPrimaryAsked ? "every caster is alpha-tested and went to occlusion "
                                          "textures (no " + mWedgeMethodName + " casters)"
                                        : std::string("auto gave every caster to occlusion "
                                                      "textures (no wedges)")) +
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
            if (facts.alphaMasked) facts.alphaMaterials = alphaTestedMaterials(object.mesh);
            facts.topology = ctx.casters.topology(c).stats();
            facts.silhouetteEdges = ctx.casters.frame(c).edges.size();
            if (mPrimaryAsked) {
                // Only the alpha test decides: the scene JSON's "method" is auto's to read.
                mChoices.push_back(
                    facts.alphaMasked
                        ? geometry::ShadowPathChoice{
                              geometry::ShadowPath::Occlusion,
                              "alpha-tested materials: " + facts.alphaMaterials + "; " +
                                  mWedgeMethodName +
                                  " occludes with whole triangles, so occlusion textures (auto's "
                                  "alpha path) shadow this object"}
                        : geometry::ShadowPathChoice{geometry::ShadowPath::Wedges,
                                                     "opaque: " + mWedgeMethodName});
                continue;
            }
            mChoices.push_back(geometry::chooseShadowPath(facts));
        }
    }

    VisibilityMethod& occlusionMethod(const FrameContext& ctx) {
        if (!mOcclusion) {
            const MethodInfo& info = [] () -> const MethodInfo& {
                for (const MethodInfo& m : methodTable())
                    if (m.name == "occlusion") return m;
                throw std::logic_error("auto: no occlusion entry in the method table");
            }();
            if (!info.implemented()) {
                for (std::size_t c = 0; c < mChoices.size(); ++c)
                    if (mChoices[c].path == geometry::ShadowPath::Occlusion)
                        throw geometry::InputError(
                            "auto: object '" +
                            ctx.scene.objects[ctx.casters.sceneObject(c)].name +
                            "' needs occlusion textures (" + mChoices[c].reason +
                            "), which are not implemented yet; give it \"method\": \"wedges\" "
                            "or \"none\" in the scene JSON");
            }
            mOcclusion = createByName(mResources, "occlusion");
            mOcclusion->resize(mWidth, mHeight);
        }
        return *mOcclusion;
    }

    MethodResources mResources; // shaders and scene (the parameters are auto's own)
    std::string mWedgeMethodName;
    std::unique_ptr<VisibilityMethod> mWedges, mOcclusion;
    FullscreenPass mMultiply;
    Texture mSaved;
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

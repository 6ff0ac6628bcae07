// A visibility method: one class per method behind one small interface, created from the table
// in gpu/Methods.h. A method writes V into Targets::visibility (cleared to 0 before it runs) for
// the pixels its casters affect, and may run on a subset of the casters (`auto` composes methods
// per object in one frame).
#pragma once

#include <geometry/scene/Scene.h>
#include <gpu/gl/Debug.h>
#include <gpu/Methods.h>
#include <gpu/Renderer.h>
#include <gpu/gl/ShaderLoader.h>

#include "engine/CasterSet.h"
#include "engine/SceneGeometry.h"
#include "engine/Targets.h"

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string_view>

namespace gpu {

// What a method may use when it is built.
struct MethodResources {
    const ShaderLoader& shaders;
    const geometry::Scene& scene;
    // Every parameter the method declares, with its value (resolveParameters: given or default).
    std::span<const ParameterValue> parameters;
};

struct SurfaceTiles; // passes/SurfaceTilePass.h

// What the methods of one frame share (auto's paths run in turn): the visible surface's tiles,
// once one of them has measured them (measureSurface, a wait for the G-buffer), for the next.
struct FrameScratch {
    std::shared_ptr<const SurfaceTiles> surfaceTiles;
};

// What a method sees during one frame.
struct FrameContext {
    const RenderSettings& settings;
    const geometry::Scene& scene;
    const geometry::RectLight& light; // of this frame: the scene's or RenderSettings::light
    const Targets& targets;
    const glm::mat4& viewProj; // of the frame uniforms
    CasterSet& casters;
    std::span<const std::uint32_t> casterSubset; // caster indices this method serves
    GpuTimers& timers;
    FrameStats& stats;
    // Re-uploads the frame uniforms with another accumulation weight (params.y).
    std::function<void(float weight)> setAccumulationWeight;
    // The scene's surfaces as drawn (unwelded, texcoords and alpha-tested materials), indexed
    // by scene object (CasterSet::sceneObject maps a caster to it).
    const SceneGeometry& sceneGeometry;
    FrameScratch* scratch = nullptr; // the renderer's, for this frame

    void addCpuTime(std::string_view stage, double ms) const;
    void addCounter(std::string_view name, double value) const;
};

class DebugViews; // DebugViews.h

class VisibilityMethod {
public:
    virtual ~VisibilityMethod() = default;
    virtual void resize(int /*width*/, int /*height*/) {}
    // Bytes per pixel of what resize() allocates (and per-pixel CPU buffers of a frame), beyond
    // the renderer's Targets: the renderer's size check sums them (Renderer::renderFrame).
    virtual std::size_t targetBytesPerPixel() const { return 0; }
    virtual void execute(const FrameContext& ctx) = 0;
    // Multiplies this method's V into the target's (V_target * V, by blending) in its own
    // passes, where its last pass writes every pixel once: true if it did; false, with nothing
    // drawn, for a method that builds V in the target from 0. A composition (auto's later paths,
    // VisibilityProduct) asks first: one pass instead of a copy, a clear and a multiply.
    virtual bool executeMultiplied(const FrameContext& /*ctx*/) { return false; }
    // The method's share of a debug view (WedgeWireframe, GroupParts), drawn over Targets::image
    // after this frame's execute() and the shade pass, with `debug`'s helpers; may set
    // debug.note. false: the method has nothing for `view` (it drew nothing; the renderer says
    // so in FrameStats::debugNote).
    virtual bool drawDebug(DebugView /*view*/, const FrameContext& /*ctx*/,
                           DebugViews& /*debug*/) {
        return false;
    }
    // The last frame's light-sample masks, for a method that keeps them (Renderer::lightMasks).
    virtual LightMasks lightMasks() const { return {}; }
    // Whether V already counts the light behind every receiver's own plane as hidden, for any
    // geometry (wedges-bitmask with potential silhouettes, reference). A composition (auto)
    // then runs its other paths without their plane or horizon term, so that the receiver's
    // own plane is counted once.
    virtual bool countsOwnPlane() const { return false; }
};

using Clock = std::chrono::steady_clock;
inline double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Factories of the implemented methods (gpu/src/methods/*.cpp).
std::unique_ptr<VisibilityMethod> createHardMethod(const MethodResources&);
std::unique_ptr<VisibilityMethod> createReferenceMethod(const MethodResources&);
std::unique_ptr<VisibilityMethod> createRaytraceMethod(const MethodResources&);
std::unique_ptr<VisibilityMethod> createAdditiveWedgesMethod(const MethodResources&);
std::unique_ptr<VisibilityMethod> createMultiplyWedgesMethod(const MethodResources&);
std::unique_ptr<VisibilityMethod> createBlendWedgesMethod(const MethodResources&);
std::unique_ptr<VisibilityMethod> createBitmaskWedgesMethod(const MethodResources&);
std::unique_ptr<VisibilityMethod> createAutoMethod(const MethodResources&);
// `primary` (a method that occludes with whole triangles, with its parameters in the resources)
// on a scene with alpha-tested objects: it shadows the opaque objects and auto's alpha path (sample maps or pcss)
// the alpha-tested ones, composed as auto composes (AutoMethod.cpp).
struct MethodInfo;
std::unique_ptr<VisibilityMethod> createAlphaComposite(const MethodResources&,
                                                       const MethodInfo& primary);
std::unique_ptr<VisibilityMethod> createOcclusionMethod(const MethodResources&);
std::unique_ptr<VisibilityMethod> createPcssMethod(const MethodResources&);
std::unique_ptr<VisibilityMethod> createSampleMapsMethod(const MethodResources&);
std::unique_ptr<VisibilityMethod> createPdsmMethod(const MethodResources&);
std::unique_ptr<VisibilityMethod> createLinearLightSmMethod(const MethodResources&);
std::unique_ptr<VisibilityMethod> createDeepSmMethod(const MethodResources&);

} // namespace gpu

// The frame: G-buffer → visibility (per method) → shading, on the current GL context.
//
// The visibility step is one object per method, chosen by name from the table in gpu/Methods.h
// (gpu/src/methods/). Every pass opens a debug group and a GPU timer; FrameStats carries them by
// name.
#pragma once

#include <geometry/ErrorStats.h>
#include <geometry/ImageIO.h>
#include <geometry/Scene.h>
#include <geometry/Topology.h>
#include <gpu/Debug.h>
#include <gpu/Methods.h>
#include <gpu/Objects.h>
#include <gpu/ShaderLoader.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace geometry {
class RayTracer;
} // namespace geometry

namespace gpu {

// One settings struct for the renderer, the command line and (later) the viewer UI.
struct RenderSettings {
    std::string method = "hard"; // a name from methodTable()
    // The method's parameters as given (gpu/Methods.h); the others take their defaults. A name
    // or value the method does not declare is a geometry::InputError from renderFrame.
    std::vector<ParameterValue> parameters;
    // Replaces the scene's light for this frame (bench light sweeps and size scales, the viewer).
    // It is checked like the scene's (finite, non-zero area, touching no geometry) whenever it
    // changes: a geometry::InputError from renderFrame otherwise.
    std::optional<geometry::RectLight> light;
    // Replaces the scene's camera for this frame (the viewer's fly camera); checked like the
    // scene's whenever it changes (geometry::validateCamera).
    std::optional<geometry::Camera> camera;
    // true (headless tools): the frame ends with glFinish and FrameStats::gpu holds this frame's
    // pass times. false (the viewer): nothing waits; FrameStats::gpu holds the newest earlier
    // frame whose timer queries have completed (a ring of a few frames), gpuTimesLag its age.
    bool waitForGpu = true;
    int width = 512;
    int height = 512;
    int samples = 1024;       // reference methods: light samples per pixel
    std::uint32_t seed = 1;   // reference methods: sample pattern
    float ambient = 0.15f;    // shading only; V never includes it
    float exposure = 1.0f;    // shading only
    // Called during long reference renders with (done, total) samples. May be empty.
    std::function<void(int, int)> progress;
};

struct CpuTime {
    std::string name;
    double ms = 0.0;
};

// A named count of the frame (pixels clamped, wedges culled, ...), written to report.json.
struct Counter {
    std::string name;
    double value = 0.0;
};

// The shadow path a method chose for one scene object (`auto`), and why.
struct ObjectChoice {
    std::size_t object = 0; // index into Scene::objects
    std::string path;       // "wedges", "occlusion"
    std::string reason;
};

struct FrameStats {
    std::vector<PassTime> gpu; // per pass, GL timer queries
    std::vector<CpuTime> cpu;  // per CPU stage
    double frameMs = 0.0;      // wall clock of the whole frame, including GPU completion
    double gpuFrameMs = 0.0;   // GPU time of the whole frame (one timer span; passes may nest)
    // Frames between this one and the one `gpu` and gpuFrameMs were measured in: 0 when the
    // frame waited for the GPU, -1 while no earlier frame has completed (then they are empty).
    int gpuTimesLag = 0;
    std::size_t triangles = 0;
    std::size_t silhouetteEdges = 0;  // directed silhouette edges from the light centre
    std::size_t silhouetteGroups = 0; // groups (geometry/Silhouette.h) from the light centre
    std::size_t volumeTriangles = 0; // shadow-volume triangles for the light centre
    std::size_t silhouetteUploadBytes = 0; // per-frame upload of the centre's silhouettes
    std::vector<Counter> counters;         // method-specific counts
    std::vector<ObjectChoice> objectChoices; // per casting object, for methods that choose
};

// What the renderer made of each scene object (welded topology of the shadow casters).
struct ObjectInfo {
    std::string name;
    std::size_t triangles = 0;
    bool casts = false; // method != none
    geometry::Manifoldness manifoldness = geometry::Manifoldness::Closed; // casters only
    geometry::TopologyStats topology;                                     // casters only
};

class Renderer {
public:
    // Needs a current GL 4.5 context. Builds topology for every casting object (CPU) and uploads
    // the scene once.
    Renderer(const geometry::Scene& scene, const ShaderLoader& shaders);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // Renders one frame with `settings` (resizes targets when the size changed). Throws
    // geometry::InputError for settings or a scene the method cannot serve (alpha-tested casters
    // with a method that does not honour alpha masks: MethodInfo::alphaMasks).
    FrameStats renderFrame(const RenderSettings& settings);

    // Results of the last frame, rows top to bottom.
    geometry::FloatImage visibility() const; // 1 channel, NaN where no surface
    geometry::FloatImage position() const;   // 3 channels, NaN where no surface
    geometry::FloatImage normal() const;     // 3 channels (viewer-facing), NaN where no surface
    std::vector<std::uint8_t> imageRgba8() const;
    // Draws the last frame's image into the default framebuffer's viewport (x, y, width, height),
    // scaled with linear filtering (the viewer's window).
    void blitImage(int x, int y, int width, int height) const;

    const geometry::Scene& scene() const { return mScene; }
    std::size_t triangleCount() const;
    std::vector<ObjectInfo> objects() const;

private:
    struct Impl;
    std::unique_ptr<Impl> mImpl;
    const geometry::Scene& mScene;
};

} // namespace gpu

// The frame: G-buffer → visibility (per method) → shading, on the current GL context.
//
// The visibility step is one object per method, chosen by name from the table in gpu/Methods.h
// (gpu/src/methods/). Every pass opens a debug group and a GPU timer; FrameStats carries them by
// name.
#pragma once

#include <geometry/reference/ErrorImage.h>
#include <geometry/reference/ErrorStats.h>
#include <geometry/scene/ImageIO.h>
#include <geometry/scene/Scene.h>
#include <geometry/shadow/Topology.h>
#include <gpu/gl/Debug.h>
#include <gpu/Methods.h>
#include <gpu/gl/Objects.h>
#include <gpu/gl/ShaderLoader.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace geometry {
class RayTracer;
} // namespace geometry

namespace gpu {

// What Targets::image shows (the viewer's toggles, penumbra-render --debug-view): composited
// after the shade pass, so imageRgba8() and blitImage() return it. Views that need something the
// method does not have (wedges, silhouette groups) show the shaded image and say so in
// FrameStats::debugNote.
enum class DebugView {
    Shaded,          // the shaded image (no extra work)
    Visibility,      // V as grey
    SilhouetteEdges, // the light centre's directed silhouette edges over the shaded image
    WedgeWireframe,  // the method's wedge hulls as lines over the shaded image
    StencilCount,    // the light centre's z-fail count as a colour ramp
    GroupParts,      // wedges-blend: one silhouette group's per-part visibility buffers
    ErrorHeatMap,    // |V - V_ref| against a reference accumulated over frames
};

struct DebugViewInfo {
    DebugView view;
    std::string_view name; // for flags and the UI: "shaded", "visibility", ...
    std::string_view help; // one line
};

// Every view, in DebugView order.
std::span<const DebugViewInfo> debugViews();
// The entry for `name`; throws geometry::InputError listing the names for an unknown one.
const DebugViewInfo& findDebugView(std::string_view name);
const DebugViewInfo& debugViewInfo(DebugView view);

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
    // Shadow-volume and wedge methods (hard, wedges-*, auto's wedges): draw only the silhouette
    // groups and wedges that can reach a tile of visible surface (measured from the G-buffer,
    // gpu/src/methods/GroupBatches.h), and batch the per-silhouette methods' groups by those
    // tiles (with 64 groups or more: below that the pass costs more than it saves). Off: every
    // group in the view frustum, batched by screen rectangles, as a comparison (the same V up
    // to the order in which groups blend; slower inside levels).
    bool depthAwareCulling = true;
    // Image size. A new size is checked before anything is allocated against the GL limits
    // (GL_MAX_TEXTURE_SIZE, _RENDERBUFFER_SIZE, _FRAMEBUFFER_WIDTH/HEIGHT, _VIEWPORT_DIMS), a
    // proxy RGBA32F texture of that size, and a memory budget for every per-pixel target of the
    // frame (the GPU's memory where the driver tells, else half of main memory): a
    // geometry::InputError giving the limit otherwise.
    int width = 512;
    int height = 512;
    // The memory budget of that check in bytes; 0: from the device as described there.
    std::size_t targetMemoryBudget = 0;
    // wedges-bitmask evaluate=tiles: the most (tile, wedge) list entries a frame may hold before
    // it rasterises the hulls instead (counted: wedge_tiles_over_limit); 0: what one buffer
    // texture holds (GL_MAX_TEXTURE_BUFFER_SIZE). Lower only to test that fallback.
    std::size_t wedgeTileEntryLimit = 0;
    int samples = 1024;       // reference methods: light samples per pixel
    std::uint32_t seed = 1;   // reference methods: sample pattern
    float ambient = 0.15f;    // shading only; V never includes it
    float exposure = 1.0f;    // shading only
    // Called during long reference renders with (done, total) samples. May be empty.
    std::function<void(int, int)> progress;

    // What Targets::image shows (DebugView).
    DebugView debugView = DebugView::Shaded;
    // GroupParts: the silhouette group shown, an index into the frame's groups (of the casters
    // the wedge method serves), wrapped into range (negative counts from the end);
    // FrameStats::debugNote names the one shown.
    int debugGroup = 0;
    // ErrorHeatMap: light samples (of the `samples`/`seed` pattern, as the `reference` method
    // takes them) added per frame to the progressive reference; it restarts when the camera,
    // light, size, samples or seed change and stops adding once all `samples` are in.
    int referenceSamplesPerFrame = 16;
    // ErrorHeatMap: |dV| at the top of the colour scale (geometry::heatColour).
    float errorScale = geometry::kDefaultErrorScale;
};

// The light-sample masks of a method that keeps them (wedges-bitmask): per pixel, rows bottom to
// top, samples / 32 words; bit i % 32 of word i / 32 set when light sample i is hidden (the
// pattern: geometry::lightMaskPattern(samples, RenderSettings::seed), shifted per pixel with
// pattern=rotated: geometry::maskPixelShift). Empty (samples 0) for other methods.
struct LightMasks {
    int samples = 0;
    int width = 0, height = 0;
    std::vector<std::uint32_t> words;
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
    std::size_t silhouetteGroups = 0; // groups (geometry/shadow/Silhouette.h) from the light centre
    std::size_t volumeTriangles = 0; // shadow-volume triangles for the light centre
    std::size_t silhouetteUploadBytes = 0; // per-frame upload of the centre's silhouettes
    std::vector<Counter> counters;         // method-specific counts
    std::vector<ObjectChoice> objectChoices; // per casting object, for methods that choose
    // One line for the UI about the debug view: what it shows, or why it shows only the shaded
    // image; empty for Shaded.
    std::string debugNote;
    // ErrorHeatMap: light samples in the progressive reference after this frame (0 otherwise).
    int referenceSamplesDone = 0;
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
    // geometry::InputError for bad settings. A method that does not honour alpha masks
    // (MethodInfo::alphaMasks) on a scene with alpha-tested casters shadows the opaque objects
    // only; occlusion textures shadow the alpha-tested ones, and FrameStats::objectChoices says
    // which object went where.
    FrameStats renderFrame(const RenderSettings& settings);

    // Results of the last frame, rows top to bottom.
    geometry::FloatImage visibility() const; // 1 channel, NaN where no surface
    geometry::FloatImage position() const;   // 3 channels, NaN where no surface
    geometry::FloatImage normal() const;     // 3 channels (viewer-facing), NaN where no surface
    std::vector<std::uint8_t> imageRgba8() const; // the image incl. its debug view
    // The ErrorHeatMap view's progressive reference: the mean of V over the light samples added
    // so far (FrameStats::referenceSamplesDone; all of them: the `reference` method's V for the
    // same samples and seed), NaN where no surface; empty (0x0) before the view was first shown.
    geometry::FloatImage referenceVisibility() const;
    // The last frame's light-sample masks (LightMasks; reads them back from the GPU).
    LightMasks lightMasks() const;

    // Draws the last frame's image (with its debug view) into `framebuffer` (0: the window's)
    // at the viewport (x, y, width, height), lower-left origin, linearly filtered. Leaves the
    // caller's framebuffer bindings and scissor as they were.
    void blitImage(int x, int y, int width, int height, unsigned int framebuffer = 0) const;

    const geometry::Scene& scene() const { return mScene; }
    std::size_t triangleCount() const;
    std::vector<ObjectInfo> objects() const;

private:
    struct Impl;
    std::unique_ptr<Impl> mImpl;
    const geometry::Scene& mScene;
};

} // namespace gpu

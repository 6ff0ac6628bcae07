// silhouette_bench: the per-frame CPU step of the wedge method (issue 3), timed with Google
// Benchmark.
//
// - silhouette_full: SilhouetteExtractor::update with default settings (classification,
//   multiplicities, groups and loops, z-fail volumes with caps by reference, penumbra wedges):
//   everything the CPU does per frame for one object. Target: <= 5 ms per 1M triangles on one
//   core (>= 200 Mtri/s).
// - silhouette_full_caps: the same with capVertices = true (both caps of every light-oriented
//   triangle re-emitted as vertices, ~96 bytes per triangle per frame), for comparison.
// - silhouette_volumes: the same without wedges; silhouette_classify: without volumes and wedges
//   (classification, multiplicities, groups, loops). The differences show where the time goes.
// - silhouette_lean: SilhouetteSettings::lean(), the per-frame step when the GPU builds volumes
//   and wedges itself: groups, triangle ids, directed edges (not chained into loops) and cheap
//   influence bounds per group (occluder box x light). The counter upload_bytes is what the
//   frame holds for the GPU in each mode.
// - topology_build: Topology construction (welding, edge CSR, OpenMesh), once per mesh; context
//   only, never per frame.
// - Meshes: UV spheres and icospheres at ~10k / ~100k / ~1M triangles, noisy icospheres (radial
//   noise of half an edge length: a long, jagged silhouette), and the OpenArena levels with the
//   light of their interior framing (geometry::loadScene).
// - The light moves on a small circle every iteration so that the extractor's reuse of an
//   unchanged frame never kicks in (checked: a reused frame aborts the benchmark).
// - One thread: the step is single-threaded by design (one extractor per object; objects could
//   run in parallel, a single object does not: in the lean step only the classification and the
//   per-cluster split, about a third of it on the levels, would spread over threads), so the
//   benchmark thread is pinned to one CPU and runs with Threads(1).
// - Meshes and their topology are built outside the timed loop and cached; only the most recent
//   mesh is kept, as the 1M-triangle topologies take a few hundred MB each.
#include "geometry/TestMeshes.h"

#include <geometry/reference/Framing.h>
#include <geometry/scene/Primitives.h>
#include <geometry/scene/Scene.h>
#include <geometry/shadow/PotentialSilhouettes.h>
#include <geometry/shadow/Silhouette.h>
#include <geometry/shadow/Topology.h>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#ifdef __linux__
#include <sched.h>
#endif

namespace {

using geometry::Aabb;
using geometry::MeshData;
using geometry::RectLight;

struct MeshSpec {
    std::string name;                // benchmark name suffix
    std::function<MeshData()> build; // primitives: builds the mesh
    bool isLevel = false;
    std::filesystem::path level; // for levels: the .glb, light from loadScene
};

// A mesh ready for the timed loop: its topology, the base light and the scene bounds.
struct BenchMesh {
    std::string name;
    MeshData mesh;
    std::unique_ptr<geometry::Topology> topology;
    RectLight light;
    Aabb sceneBounds;
};

// Sphere scenes: unit sphere at the origin, a 1 x 1 light 4 units above and off-axis (so the
// terminator follows no ring of the UV sphere), bounds including a 10 x 10 floor below it, where
// the shadow would fall.
RectLight sphereLight() {
    return testmeshes::squareLight({1.5f, 4.0f, 1.0f}, 0.5f);
}

Aabb sphereSceneBounds(const MeshData& mesh) {
    Aabb b = mesh.bounds();
    b.extend(glm::vec3(-5.0f, -1.5f, -5.0f));
    b.extend(glm::vec3(5.0f, -1.5f, 5.0f));
    return b;
}

// Only the most recent mesh is cached: benchmarks are registered mesh by mesh, so consecutive
// runs share it, and at most one large topology is alive at a time.
const BenchMesh& cachedMesh(const MeshSpec& spec) {
    static std::unique_ptr<BenchMesh> current;
    if (current && current->name == spec.name) return *current;
    current.reset(); // free the previous mesh before building the next one
    auto m = std::make_unique<BenchMesh>();
    m->name = spec.name;
    if (spec.isLevel) {
        geometry::Scene scene = geometry::loadScene(spec.level); // interior framing
        m->light = scene.light;
        m->sceneBounds = scene.bounds();
        m->mesh = std::move(scene.objects.at(0).mesh);
    } else {
        m->mesh = spec.build();
        m->light = sphereLight();
        m->sceneBounds = sphereSceneBounds(m->mesh);
    }
    m->topology = std::make_unique<geometry::Topology>(m->mesh);
    current = std::move(m);
    return *current;
}

// The spec's mesh, or nullptr once the benchmark is skipped with the reason (a level that does
// not load).
const BenchMesh* meshOrSkip(benchmark::State& state, const MeshSpec& spec) {
    try {
        return &cachedMesh(spec);
    } catch (const std::exception& e) {
        state.SkipWithError(e.what());
        for (auto _ : state) {
        }
        return nullptr;
    }
}

// Light of iteration i: the base light moved on a circle in its own plane, of radius 5% of its
// smaller half-axis, 97 steps per turn. Every frame differs from the previous one.
RectLight movedLight(const RectLight& base, std::int64_t i) {
    const float angle = 2.0f * std::numbers::pi_v<float> * float(i % 97) / 97.0f;
    const float radius = 0.05f * std::min(glm::length(base.u), glm::length(base.v));
    RectLight light = base;
    light.center += radius * (std::cos(angle) * glm::normalize(base.u) +
                              std::sin(angle) * glm::normalize(base.v));
    return light;
}

// Bytes of one frame's per-frame data for the GPU: triangle ids (4), edges (12), per group the
// ranges and two boxes the GPU reads (4 x 4 + 2 x 24 = 64; SilhouetteGroup's other fields index
// CPU-built arrays), and whatever the frame built on the CPU: loops, volume vertices, wedges
// and their boundary vertices.
std::size_t uploadBytes(const geometry::SilhouetteFrame& frame) {
    return 4 * frame.triangles.size() + sizeof(geometry::SilhouetteEdge) * frame.edges.size() +
           64 * frame.groups.size() + sizeof(geometry::SilhouetteLoop) * frame.loops.size() +
           sizeof(glm::vec4) * frame.volumeVertices.size() +
           sizeof(geometry::Wedge) * frame.wedges.wedges.size() +
           sizeof(glm::vec4) * frame.wedges.vertices.size();
}

// The target is stated as time per 1M triangles (<= 5 ms). A plain number, computed
// here from `seconds`, the timed loop's wall time: the library's inverted rate would print it
// with a misleading "s" unit.
void setMsPerMtri(benchmark::State& state, double triangles, double seconds) {
    const double iterations = double(state.iterations());
    if (iterations > 0.0 && triangles > 0.0)
        state.counters["ms_per_Mtri"] = 1e3 * seconds / iterations / (triangles * 1e-6);
}

// `seconds`: wall time of the timed loop, measured by the caller (Google Benchmark 1.7 does not
// expose it to the benchmark function).
void setCounters(benchmark::State& state, const BenchMesh& m,
                 const geometry::SilhouetteFrame& frame, double seconds) {
    const double tris = double(m.topology->triangles().size());
    state.counters["triangles"] = tris;
    state.counters["sil_edges"] = double(frame.edges.size());
    state.counters["loops"] = double(frame.loops.size());
    state.counters["groups"] = double(frame.groups.size());
    state.counters["wedges"] = double(frame.wedges.wedges.size());
    state.counters["upload_bytes"] = double(uploadBytes(frame));
    // A rate counter is multiplied by the iteration count and divided by the CPU time: triangles
    // per second, printed with an SI prefix ("250M/s" = 250 Mtri/s).
    state.counters["tri_rate"] =
        benchmark::Counter(tris, benchmark::Counter::kIsIterationInvariantRate);
    setMsPerMtri(state, tris, seconds);
}

void runExtractor(benchmark::State& state, const MeshSpec& spec,
                  const geometry::SilhouetteSettings& settings) {
    const BenchMesh* m = meshOrSkip(state, spec);
    if (!m) return;
    geometry::SilhouetteExtractor extractor(*m->topology);
    // One untimed frame: first-use allocations of the scratch and output arrays are not part of
    // the steady per-frame cost.
    extractor.update(movedLight(m->light, 0), m->sceneBounds, settings);
    std::int64_t i = 1;
    const geometry::SilhouetteFrame* frame = &extractor.frame();
    const auto start = std::chrono::steady_clock::now();
    for (auto _ : state) {
        frame = &extractor.update(movedLight(m->light, i++), m->sceneBounds, settings);
        benchmark::DoNotOptimize(frame);
        benchmark::ClobberMemory();
        if (extractor.reused()) {
            state.SkipWithError("the extractor reused a frame: the light did not move");
            break;
        }
    }
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
    setCounters(state, *m, *frame, elapsed.count());
}

void silhouetteFull(benchmark::State& state, const MeshSpec* spec) {
    runExtractor(state, *spec, geometry::SilhouetteSettings{});
}

void silhouetteFullCaps(benchmark::State& state, const MeshSpec* spec) {
    geometry::SilhouetteSettings settings;
    settings.capVertices = true;
    runExtractor(state, *spec, settings);
}

void silhouetteVolumes(benchmark::State& state, const MeshSpec* spec) {
    geometry::SilhouetteSettings settings;
    settings.buildWedges = false;
    runExtractor(state, *spec, settings);
}

void silhouetteClassify(benchmark::State& state, const MeshSpec* spec) {
    geometry::SilhouetteSettings settings;
    settings.buildVolumes = false;
    settings.buildWedges = false;
    runExtractor(state, *spec, settings);
}

// What a GPU that builds volumes and wedges from the directed edges needs (the target:
// <= 1/4 of silhouette_full on the levels).
void silhouetteLean(benchmark::State& state, const MeshSpec* spec) {
    runExtractor(state, *spec, geometry::SilhouetteSettings::lean());
}

// wedges-bitmask's potential silhouette edges (its default, silhouettes=potential): per frame
// with the light moving, geometry::PotentialSilhouettes::update (every edge that is a silhouette
// from some light point, with its triangles' third vertices). The lean step above runs beside it
// in that method's frame (the light centre's groups for the stencil pass).
void potentialEdges(benchmark::State& state, const MeshSpec* spec) {
    const BenchMesh* m = meshOrSkip(state, *spec);
    if (!m) return;
    geometry::PotentialSilhouettes potential(*m->topology);
    std::vector<geometry::PotentialEdge> edges;
    potential.update(movedLight(m->light, 0), edges); // untimed: first-use allocations
    std::int64_t i = 1;
    const auto start = std::chrono::steady_clock::now();
    for (auto _ : state) {
        potential.update(movedLight(m->light, i++), edges);
        benchmark::DoNotOptimize(edges.data());
        benchmark::ClobberMemory();
    }
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
    const double tris = double(m->topology->triangles().size());
    state.counters["triangles"] = tris;
    state.counters["potential_edges"] = double(edges.size());
    setMsPerMtri(state, tris, elapsed.count());
}

void topologyBuild(benchmark::State& state, const MeshSpec* spec) {
    const BenchMesh* m = meshOrSkip(state, *spec);
    if (!m) return;
    for (auto _ : state) {
        geometry::Topology topology(m->mesh);
        benchmark::DoNotOptimize(topology.edges().data());
    }
    state.counters["triangles"] = double(m->topology->triangles().size());
    state.counters["tri_rate"] = benchmark::Counter(double(m->topology->triangles().size()),
                                                    benchmark::Counter::kIsIterationInvariantRate);
}

// Mean edge length of an icosphere of radius 1: the icosahedron's edge (1.0515) halved per
// subdivision.
float icosphereEdge(int subdivisions) {
    return 1.0515f / float(1 << subdivisions);
}

MeshSpec primitive(std::string name, std::function<MeshData()> build) {
    MeshSpec spec;
    spec.name = std::move(name);
    spec.build = std::move(build);
    return spec;
}

std::vector<MeshSpec> meshSpecs() {
    std::vector<MeshSpec> specs;
    const glm::vec3 origin(0.0f);
    // UV spheres: 2 * s * (s/2 - 1) triangles: 10,200 / 100,488 / 1,002,000.
    for (int segments : {102, 318, 1002}) {
        const int tris = 2 * segments * (segments / 2 - 1);
        specs.push_back(primitive("uv_sphere/" + std::to_string(tris),
                                  [=] { return geometry::makeSphere(origin, 1.0f, segments); }));
    }
    // Icospheres: 20 * 4^s triangles: 20,480 / 81,920 / 327,680 / 1,310,720 (s = 4 gives 5,120,
    // too far below 10k; s = 7 fills the gap to 1M for the scaling curve).
    for (int s : {5, 6, 7, 8}) {
        const int tris = 20 << (2 * s);
        specs.push_back(primitive("icosphere/" + std::to_string(tris),
                                  [=] { return geometry::makeIcosphere(origin, 1.0f, s); }));
    }
    // Noisy icospheres: radial white noise of +-half an edge tilts the triangles by up to ~45
    // degrees, so the silhouette is a long, jagged, fragmented band around the terminator whose
    // length grows like the triangle count rather than its square root.
    for (int s : {5, 6, 7, 8}) {
        const int tris = 20 << (2 * s);
        specs.push_back(primitive("noisy_icosphere/" + std::to_string(tris), [=] {
            MeshData mesh = geometry::makeIcosphere(origin, 1.0f, s);
            geometry::displaceRadially(mesh, origin, 0.5f * icosphereEdge(s), 1234u);
            return mesh;
        }));
    }
    const std::filesystem::path levels = std::filesystem::path(PENUMBRA_SHARED_DIR) / "levels";
    for (const char* level : {"oa_dm4", "oa_dm1", "kaos2", "oa_dm5"}) {
        MeshSpec spec;
        spec.name = std::string("level/") + level;
        spec.isLevel = true;
        spec.level = levels / (std::string(level) + ".glb");
        specs.push_back(std::move(spec));
    }
    return specs;
}

// Keeps the benchmark thread on the CPU it starts on: no migrations in the middle of a run.
int pinToCurrentCpu() {
#ifdef __linux__
    const int cpu = sched_getcpu();
    if (cpu < 0) return -1;
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(cpu, &set);
    if (sched_setaffinity(0, sizeof(set), &set) != 0) return -1;
    return cpu;
#else
    return -1;
#endif
}

} // namespace

int main(int argc, char** argv) {
    // Registered mesh by mesh (full, lean, full with cap vertices, volumes, classify, topology)
    // so the one-mesh cache is hit.
    static const std::vector<MeshSpec> specs = meshSpecs();
    for (const MeshSpec& spec : specs) {
        const auto reg = [&](const char* kind, void (*fn)(benchmark::State&, const MeshSpec*)) {
            benchmark::RegisterBenchmark((std::string(kind) + "/" + spec.name).c_str(), fn, &spec)
                ->Unit(benchmark::kMillisecond)
                ->Threads(1);
        };
        reg("silhouette_full", silhouetteFull);
        reg("silhouette_lean", silhouetteLean);
        reg("potential_edges", potentialEdges);
        reg("silhouette_full_caps", silhouetteFullCaps);
        reg("silhouette_volumes", silhouetteVolumes);
        reg("silhouette_classify", silhouetteClassify);
        reg("topology_build", topologyBuild);
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    const int cpu = pinToCurrentCpu();
    benchmark::AddCustomContext("threads", "1 (the per-frame step is single-threaded)");
    benchmark::AddCustomContext("pinned_cpu", cpu >= 0 ? std::to_string(cpu) : "no");
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}

// geometry_bench: CPU costs of the geometry library that geometry_tests used to print, timed with
// Google Benchmark on the very inputs those tests timed (the tests keep what they assert on them).
//
// - silhouette/sphere_1m/...: SilhouetteExtractor::update on a 998,000-triangle UV sphere
//   (makeSphere, 1000 segments), closed and open (its first 1000 triangles, the north polar cap,
//   removed: the two-sided rule), the light cycling through 12 positions on a circle of radius 3
//   at height ~2 (half size 0.3), scene box the mesh's bounds grown by 4. classify: groups and
//   loops only; volumes: + z-fail volumes; full: + wedges (default settings). extractor_build:
//   constructing the extractor (once per mesh). hard_volume/sphere_1m/open:
//   appendHardShadowVolume on the open sphere from (3, 2, 0), into arrays that keep their
//   capacity (the test timed one call into fresh arrays, their growth included).
// - shadow_volume/height_field_100k: appendHardShadowVolume on a bumpy open 224 x 224 height
//   field (100,352 triangles), the light cycling through 15 positions; the reference method calls
//   it up to 1024 times per image.
// - wedge/...: 100,000 random generic edges over 16 random lights (tests/geometry/WedgeCases.h,
//   seed 99), arrays reused (steady state, as in a frame). edges_points: the draw with a query
//   point per edge: append_wedge (appendWedge) and edge_coverage (edgeCoverage at the point).
//   edges: the draw without points: builder_exact (WedgeBuilder, Path::Exact), builder_default
//   (its fast path where it applies; fast_path_pct) and append_wedge (the wrapper, a builder per
//   call). per_edge / per_call: CPU time per edge.
// - light_check/oa_dm5/{inside,above}: findLightContact on oa_dm5 (loadGltf, one object) with a
//   light of half size 1% of the bounds diagonal at the bounds' centre or 1 above them (both
//   clear: a full scan of the 66,922 triangles; contact = 1 would mean it hit one).
// - topology/split_grid_320k: Topology construction (welding, edges, manifoldness) of a 400 x 400
//   grid split per quad (320,000 triangles, 640,000 positions).
// - ray_tracer/{two_quads,grate}/{one_thread,all_threads}: RayTracer::visibility, 128 x 128 floor
//   points x 256 samples, over two quads or a grate of 64 x 64 squares (8194 triangles, penumbra
//   almost everywhere); rays_per_s over CPU time on one thread (it runs on the benchmark's), over
//   real time on all of them (the hardware concurrency).
//
// Each case builds its input outside the timed loop; only the most recent mesh is kept (the 1M
// sphere's topology takes a few hundred MB).
#include "geometry/RayTracerScenes.h"
#include "geometry/TestMeshes.h"
#include "geometry/WedgeCases.h"

#include <geometry/scene/GltfLoader.h>
#include <geometry/scene/LightCheck.h>
#include <geometry/scene/Primitives.h>
#include <geometry/reference/RayTracer.h>
#include <geometry/scene/Scene.h>
#include <geometry/shadow/ShadowVolume.h>
#include <geometry/shadow/Silhouette.h>
#include <geometry/shadow/Topology.h>
#include <geometry/shadow/Wedge.h>

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace {

using geometry::Aabb;
using geometry::MeshData;
using geometry::RectLight;
using geometry::Topology;

// The timed loop: body(i) with the iteration index.
template <class Body> void timedLoop(benchmark::State& state, Body&& body) {
    std::int64_t i = 0;
    for (auto _ : state) {
        body(i++);
        benchmark::ClobberMemory();
    }
}

// CPU time per item (real time where the benchmark uses it), printed with its unit ("555ns").
benchmark::Counter perItem(double itemsPerIteration) {
    return benchmark::Counter(itemsPerIteration, benchmark::Counter::kIsIterationInvariantRate |
                                                     benchmark::Counter::kInvert);
}

// Reports an input that could not be built (a missing level) as the benchmark's error.
template <class Build> bool buildOrSkip(benchmark::State& state, Build&& build) {
    try {
        build();
        return true;
    } catch (const std::exception& e) {
        state.SkipWithError(e.what());
        for (auto _ : state) {
        }
        return false;
    }
}

// --- Silhouettes on the 1M-triangle sphere ------------------------------------------------------

RectLight lightAt(const glm::vec3& center, float halfSize = 0.3f) {
    return testmeshes::squareLight(center, halfSize);
}

// Frame i's light: 12 positions, the same every turn; consecutive frames always differ, so the
// extractor never reuses a frame.
RectLight sphereLight(std::int64_t i) {
    const float a = 0.1f * static_cast<float>(i % 12);
    return lightAt({3.0f * std::cos(a), 2.0f + 0.1f * a, 3.0f * std::sin(a)});
}

struct SphereMesh {
    bool open = false;
    MeshData mesh;
    std::unique_ptr<Topology> topology;
    Aabb box;
};

// The closed or the open sphere; only one is alive at a time.
const SphereMesh& sphere(bool open) {
    static std::unique_ptr<SphereMesh> current;
    if (current && current->open == open) return *current;
    current.reset();
    auto s = std::make_unique<SphereMesh>();
    s->open = open;
    s->mesh = geometry::makeSphere({0, 0, 0}, 1.0f, 1000);
    if (open) s->mesh.triangles.erase(s->mesh.triangles.begin(), s->mesh.triangles.begin() + 1000);
    s->topology = std::make_unique<Topology>(s->mesh);
    for (const glm::vec3& p : s->topology->positions())
        s->box.extend(p);
    s->box.min -= glm::vec3(4.0f);
    s->box.max += glm::vec3(4.0f);
    current = std::move(s);
    return *current;
}

void silhouetteSphere(benchmark::State& state, bool open, geometry::SilhouetteSettings settings) {
    const SphereMesh& s = sphere(open);
    geometry::SilhouetteExtractor extractor(*s.topology);
    extractor.update(sphereLight(0), s.box, settings); // first-use allocations, untimed
    const geometry::SilhouetteFrame* frame = &extractor.frame();
    bool reused = false;
    timedLoop(state, [&](std::int64_t i) {
        frame = &extractor.update(sphereLight(i + 1), s.box, settings);
        benchmark::DoNotOptimize(frame);
        reused = reused || extractor.reused();
    });
    if (reused) state.SkipWithError("the extractor reused a frame: the light did not move");
    state.counters["triangles"] = double(s.topology->triangles().size());
    state.counters["sil_edges"] = double(frame->edges.size());
    state.counters["wedges"] = double(frame->wedges.wedges.size());
}

void extractorBuild(benchmark::State& state, bool open) {
    const SphereMesh& s = sphere(open);
    timedLoop(state, [&](std::int64_t) {
        geometry::SilhouetteExtractor extractor(*s.topology);
        benchmark::DoNotOptimize(&extractor);
    });
    state.counters["triangles"] = double(s.topology->triangles().size());
}

void hardVolumeOpenSphere(benchmark::State& state) {
    const SphereMesh& s = sphere(true);
    geometry::ShadowVolumeGeometry volume;
    timedLoop(state, [&](std::int64_t) {
        volume.clear(); // capacity kept
        geometry::appendHardShadowVolume(*s.topology, {3.0f, 2.0f, 0.0f}, volume);
        benchmark::DoNotOptimize(volume.vertices.data());
    });
    state.counters["triangles"] = double(s.topology->triangles().size());
    state.counters["sil_edges"] = double(volume.silhouetteEdges);
}

// --- Hard shadow volume of the height field -----------------------------------------------------

void shadowVolumeHeightField(benchmark::State& state) {
    const Topology topo(testmeshes::heightField(224));
    geometry::ShadowVolumeGeometry volume;
    timedLoop(state, [&](std::int64_t i) {
        volume.clear();
        const glm::vec3 light(0.5f + 0.01f * static_cast<float>(i % 15), 1.0f, 0.4f);
        geometry::appendHardShadowVolume(topo, light, volume);
        benchmark::DoNotOptimize(volume.vertices.data());
    });
    state.counters["triangles"] = double(topo.triangles().size());
    state.counters["edges"] = double(topo.edges().size());
    state.counters["sil_edges"] = double(volume.silhouetteEdges);
    state.counters["vertices"] = double(volume.vertices.size());
}

// --- Wedges --------------------------------------------------------------------------------------

constexpr int kWedgeEdges = 100000;

struct WedgeInput {
    std::vector<RectLight> lights; // edge i belongs to lights[i % 16]
    std::vector<wedgecases::TestEdge> edges;
    std::vector<glm::vec3> points; // empty for the draw without points
};

// The draws of seed 99: 16 random lights, then per edge a generic edge and, withPoints, a point
// up to 3 away from its midpoint (drawn right after its edge, as the coverage timing did).
WedgeInput wedgeInput(bool withPoints) {
    wedgecases::Rng rng(99);
    WedgeInput in;
    in.lights.resize(16);
    for (RectLight& l : in.lights)
        l = wedgecases::randomLight(rng);
    in.edges.reserve(kWedgeEdges);
    for (int i = 0; i < kWedgeEdges; ++i) {
        in.edges.push_back(
            wedgecases::randomEdge(rng, in.lights[i % 16], wedgecases::EdgeKind::Generic));
        if (withPoints) {
            const auto& e = in.edges.back();
            in.points.push_back(glm::vec3(0.5 * (glm::dvec3(e.e0) + glm::dvec3(e.e1)) +
                                          rng.uniform(0, 3) * rng.direction()));
        }
    }
    return in;
}

const WedgeInput& cachedWedgeInput(bool withPoints) {
    static const WedgeInput withP = wedgeInput(true), without = wedgeInput(false);
    return withPoints ? withP : without;
}

// Times one pass of append(i) over every edge per iteration, into arrays cleared each pass.
template <class Append> void wedgePass(benchmark::State& state, Append&& append) {
    geometry::WedgeArrays arrays;
    for (int i = 0; i < kWedgeEdges; ++i)
        append(i, arrays); // grow the arrays once, untimed
    timedLoop(state, [&](std::int64_t) {
        arrays.clear();
        for (int i = 0; i < kWedgeEdges; ++i)
            append(i, arrays);
        benchmark::DoNotOptimize(arrays.wedges.data());
    });
    state.counters["edges"] = double(kWedgeEdges);
    state.counters["vertices_per_wedge"] = double(arrays.vertices.size()) / kWedgeEdges;
    state.counters["per_edge"] = perItem(kWedgeEdges);
}

void appendWedgeBench(benchmark::State& state, bool withPoints) {
    const WedgeInput& in = cachedWedgeInput(withPoints);
    wedgePass(state, [&](int i, geometry::WedgeArrays& arrays) {
        geometry::appendWedge(in.edges[i].e0, in.edges[i].e1, in.lights[i % 16], arrays);
    });
}

void wedgeBuilderBench(benchmark::State& state, geometry::WedgeBuilder::Path path) {
    const WedgeInput& in = cachedWedgeInput(false);
    std::vector<geometry::WedgeBuilder> builders;
    for (const RectLight& l : in.lights)
        builders.emplace_back(l, path);
    wedgePass(state, [&](int i, geometry::WedgeArrays& arrays) {
        builders[i % 16].append(in.edges[i].e0, in.edges[i].e1, arrays);
    });
    int fast = 0;
    for (int i = 0; i < kWedgeEdges; ++i)
        fast += builders[i % 16].takesFastPath(in.edges[i].e0, in.edges[i].e1);
    state.counters["fast_path_pct"] = 100.0 * fast / kWedgeEdges;
}

void edgeCoverageBench(benchmark::State& state) {
    const WedgeInput& in = cachedWedgeInput(true);
    double sum = 0.0;
    timedLoop(state, [&](std::int64_t) {
        sum = 0.0;
        for (int i = 0; i < kWedgeEdges; ++i) {
            sum += geometry::edgeCoverage(in.points[i], in.edges[i].e0, in.edges[i].e1,
                                          in.lights[i % 16]);
        }
        benchmark::DoNotOptimize(sum);
    });
    state.counters["calls"] = double(kWedgeEdges);
    state.counters["checksum"] = sum;
    state.counters["per_call"] = perItem(kWedgeEdges);
}

// --- Light check on oa_dm5
// ------------------------------------------------------------------------

void lightCheckLevel(benchmark::State& state, bool above) {
    static std::unique_ptr<geometry::Scene> scene;
    if (!buildOrSkip(state, [&] {
            if (scene) return;
            const std::filesystem::path level =
                std::filesystem::path(PENUMBRA_SHARED_DIR) / "levels" / "oa_dm5.glb";
            auto s = std::make_unique<geometry::Scene>();
            s->objects.push_back(geometry::SceneObject{"oa_dm5.glb", geometry::ShadowMethod::Auto,
                                                       geometry::loadGltf(level)});
            scene = std::move(s);
        })) {
        return;
    }
    geometry::Scene& s = *scene;
    const Aabb b = s.bounds();
    const float half = 0.01f * glm::length(b.extent());
    const glm::vec3 center =
        above ? glm::vec3(b.center().x, b.max.y + 1.0f, b.center().z) : b.center();
    s.light = lightAt(center, half);
    const float tol = 1e-5f * glm::length(b.extent());
    bool contact = false;
    timedLoop(state, [&](std::int64_t) {
        const auto c = geometry::findLightContact(s, tol);
        benchmark::DoNotOptimize(c); // not on the bool: GCC's "+m,r" operand garbled its value
        contact = c.has_value();
    });
    state.counters["triangles"] = double(s.triangleCount());
    state.counters["contact"] = contact ? 1.0 : 0.0;
}

// --- Topology of the split grid
// ---------------------------------------------------------------------

void topologySplitGrid(benchmark::State& state) {
    const MeshData mesh = testmeshes::splitGrid(400);
    timedLoop(state, [&](std::int64_t) {
        const Topology topo(mesh);
        benchmark::DoNotOptimize(topo.edges().data());
    });
    state.counters["triangles"] = double(mesh.triangles.size());
    state.counters["positions"] = double(mesh.positions.size());
}

// --- Ray tracer
// ------------------------------------------------------------------------------------

void rayTracerVisibility(benchmark::State& state, bool grate, int threads) {
    const geometry::Scene scene =
        grate ? raytracerscenes::makeScene(raytracerscenes::grate())
              : raytracerscenes::makeScene(
                    {{-0.6f, 0.2f, -0.4f, 0.4f, 2.0f}, {-0.1f, 0.7f, -0.3f, 0.6f, 3.5f}});
    const geometry::RayTracer tracer(scene);
    std::vector<glm::vec3> points, normals;
    raytracerscenes::floorGrid(128, 2.5f, points, normals);
    std::vector<float> v(points.size());
    geometry::RayTraceSettings settings;
    settings.samples = 256;
    settings.threads = threads;
    timedLoop(state, [&](std::int64_t) {
        tracer.visibility(scene.light, points, normals, settings, v);
        benchmark::DoNotOptimize(v.data());
    });
    const double rays = double(points.size()) * settings.samples;
    state.counters["triangles"] = double(scene.triangleCount());
    state.counters["rays_per_s"] =
        benchmark::Counter(rays, benchmark::Counter::kIsIterationInvariantRate);
}

} // namespace

int main(int argc, char** argv) {
    using Path = geometry::WedgeBuilder::Path;
    const auto reg = [](const std::string& name, auto fn) {
        return benchmark::RegisterBenchmark(name.c_str(), fn)->Unit(benchmark::kMillisecond);
    };
    const geometry::SilhouetteSettings classify{.buildVolumes = false, .buildWedges = false};
    const geometry::SilhouetteSettings volumes{.buildVolumes = true, .buildWedges = false};
    const geometry::SilhouetteSettings full{};
    // Registered closed sphere first, then open, so each sphere is built once.
    for (const bool open : {false, true}) {
        const std::string mesh =
            open ? "silhouette/sphere_1m/open/" : "silhouette/sphere_1m/closed/";
        reg(mesh + "classify", [=](benchmark::State& s) { silhouetteSphere(s, open, classify); });
        if (!open)
            reg(mesh + "volumes", [=](benchmark::State& s) { silhouetteSphere(s, open, volumes); });
        reg(mesh + "full", [=](benchmark::State& s) { silhouetteSphere(s, open, full); });
        reg(mesh + "extractor_build", [=](benchmark::State& s) { extractorBuild(s, open); });
    }
    reg("hard_volume/sphere_1m/open", hardVolumeOpenSphere);
    reg("shadow_volume/height_field_100k", shadowVolumeHeightField);
    reg("wedge/append_wedge/edges_points", [](benchmark::State& s) { appendWedgeBench(s, true); });
    reg("wedge/edge_coverage/edges_points", edgeCoverageBench);
    reg("wedge/builder_exact/edges",
        [](benchmark::State& s) { wedgeBuilderBench(s, Path::Exact); });
    reg("wedge/builder_default/edges",
        [](benchmark::State& s) { wedgeBuilderBench(s, Path::Auto); });
    reg("wedge/append_wedge/edges", [](benchmark::State& s) { appendWedgeBench(s, false); });
    reg("light_check/oa_dm5/inside", [](benchmark::State& s) { lightCheckLevel(s, false); });
    reg("light_check/oa_dm5/above", [](benchmark::State& s) { lightCheckLevel(s, true); });
    reg("topology/split_grid_320k", topologySplitGrid);
    for (const bool grate : {false, true}) {
        for (const int threads : {1, 0}) {
            const std::string name = std::string("ray_tracer/") + (grate ? "grate" : "two_quads") +
                                     (threads == 1 ? "/one_thread" : "/all_threads");
            auto* b =
                reg(name, [=](benchmark::State& s) { rayTracerVisibility(s, grate, threads); });
            if (threads != 1) b->UseRealTime(); // the workers' time is not this thread's CPU time
        }
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::AddCustomContext("hardware_concurrency",
                                std::to_string(std::thread::hardware_concurrency()));
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}

// CPU ray-traced visibility with Embree 3 (DESIGN.md §2, §4 "Reference"):
// - one Embree scene, one triangle geometry per shadow-casting object, robust build;
// - V(P) estimated with stratified light samples, Cranley-Patterson rotated per point;
// - shadow rays in packets of 8 from one origin (coherent), points spread over std::threads.
#include <geometry/reference/RayTracer.h>
#include <geometry/core/Sampling.h>

#include <geometry/scene/AlphaMask.h>
#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

namespace geometry {

namespace {

const char* errorName(RTCError code) {
    switch (code) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_UNKNOWN: return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
    }
    return "unrecognised error";
}

bool isFinite(const glm::vec3& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

// Per-point 64-bit hash (the SplitMix64 finaliser) for the Cranley-Patterson rotation. A hash of
// the index, not a running generator, so the result does not depend on how points are split
// between threads.
std::uint64_t hashPoint(std::uint32_t seed, std::size_t index) {
    std::uint64_t z = (static_cast<std::uint64_t>(seed) << 32) ^ 0x6A09E667F3BCC909ull;
    z += static_cast<std::uint64_t>(index) * 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

// Shift in [0, 2) on each axis (the period of [-1, 1)) from 24 bits of the hash each.
glm::vec2 rotationFor(std::uint32_t seed, std::size_t index) {
    const std::uint64_t h = hashPoint(seed, index);
    const float scale = 2.0f / 16777216.0f;
    return {static_cast<float>(h >> 40) * scale, static_cast<float>((h >> 8) & 0xFFFFFF) * scale};
}

float wrapUnit(float x) { return x >= 1.0f ? x - 2.0f : x; }

// Shadow-ray packet width. Rays of one point share their origin and head to one small light, so
// packets are coherent. Measured on the case now geometry_bench's ray_tracer/grate/all_threads
// (Release, 2 threads, AVX-512 host, 8194-triangle grate, Mrays/s): rtcOccluded1 24.8,
// rtcOccluded1M stream 25.7, packets of 4 29.3, of 8 33.7, of 16 34.0. 16 wins only on trivial
// scenes and needs AVX-512 to be native, so 8 (native on AVX2) is the portable choice.
constexpr int kPacket = 8;
using RayPacket = RTCRay8;

// Points handed to a thread at a time: small enough to balance uneven shadow cost between image
// rows, large enough that the atomic counter is never contended.
constexpr std::size_t kChunk = 64;

} // namespace

struct RayTracer::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    float diagonal = 1.0f; // scene bounds diagonal, scales the origin offset
    // Alpha-masked objects' meshes (geometry/scene/AlphaMask.h), the user data of their filters.
    std::vector<std::unique_ptr<MeshData>> alphaMeshes;

    // The error callback may run on any thread (workers inside visibility()); rtcGetDeviceError
    // only reports the calling thread's error, so workers' errors are collected here.
    std::mutex errorMutex;
    std::string errorMessage;
    std::atomic<bool> errorSeen{false};

    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }

    static void onError(void* user, RTCError code, const char* str) {
        auto* self = static_cast<Impl*>(user);
        std::lock_guard lock(self->errorMutex);
        if (!self->errorSeen.exchange(true)) {
            self->errorMessage =
                std::string(errorName(code)) + (str ? std::string(": ") + str : "");
        }
    }

    // Throws if Embree reported an error on this thread or through the callback.
    void check(const char* what) {
        const RTCError code = rtcGetDeviceError(device);
        if (code == RTC_ERROR_NONE && !errorSeen.load()) return;
        std::string message;
        {
            std::lock_guard lock(errorMutex);
            message = errorMessage.empty() ? errorName(code) : errorMessage;
            errorMessage.clear();
            errorSeen = false;
        }
        throw std::runtime_error(std::string("Embree: ") + what + " failed: " + message);
    }

    float offsetDistance(const RayTraceSettings& settings) const {
        return settings.offsetScale * diagonal;
    }
};

namespace {

// The origin offset rule (DESIGN.md §2: every object shadows itself). The caller passes the
// geometric normal facing the *viewer*. Offsetting to the viewer's side keeps the ray off the
// surface it starts on, and has a meaning: when the surface faces away from the light, the light
// lies behind it, so every ray from the viewer's side must cross the surface itself and V = 0 —
// a back-facing surface is in its own shadow, as a rasterised shadow volume would make it.
glm::vec3 offsetOrigin(const glm::vec3& p, const glm::vec3& n, float eps) {
    const float len = glm::length(n);
    if (!(len > 0.0f) || !std::isfinite(len)) return p; // no usable normal: no offset
    return p + n * (eps / len);
}

// tfar just below 1 so the ray stops short of the light plane (an emissive quad modelled as an
// object there must not shadow its own light), by the same absolute distance as the offset.
float shortOfTarget(float eps, float length) {
    return 1.0f - std::max(1e-5f, length > 0.0f ? eps / length : 1.0f);
}

// tnear: hits closer to the origin than the offset itself are ignored. The offset moves the
// origin along the surface's normal, i.e. parallel to a face meeting the surface at a concave
// corner (a wall under a ceiling, a floor against a step): a G-buffer point on or within float
// error of such a corner gets an origin lying in that face's plane, and the ray leaving it was
// reported as blocked at t = 0 or within ~1e-5 of it (rows of V = 0 pixels along corners where
// both GPU methods see the light). Geometry that close is contact geometry, below what the
// offset resolves anyway; the surface's own plane is decided exactly by facesSample().
float nearLimit(float eps, float length) { return length > 0.0f ? eps / length : 0.0f; }

// A query's context: Embree's, and where the alpha filter records what the transmittance rule
// needs (the filters get the address of `rtc`, the first member).
struct CrossedSurface {
    unsigned geom = 0, prim = 0;
    float t = 0.0f, alpha = 0.0f;
    glm::vec3 normal{0.0f};
};
struct QueryContext {
    RTCIntersectContext rtc;
    // Transmittance rule: per ray id of the query, the translucent surfaces it crossed (each
    // once: with RTC_BUILD_QUALITY_HIGH a filter may see one triangle twice). nullptr: the
    // alpha test.
    std::vector<CrossedSurface>* crossed = nullptr;

    QueryContext() {
        rtcInitIntersectContext(&rtc);
    }
};

// Runs fn(begin, end, context) over [0, count) in chunks on `threads` threads; each thread owns
// its context (Embree contexts are not shared between concurrent queries).
template <class Fn>
void parallelChunks(std::size_t count, int threads, Fn&& fn) {
    unsigned hw =
        threads > 0 ? static_cast<unsigned>(threads) : std::thread::hardware_concurrency();
    hw = std::max(1u, hw);
    const std::size_t chunks = (count + kChunk - 1) / kChunk;
    const auto workers = static_cast<unsigned>(std::min<std::size_t>(hw, chunks));
    std::atomic<std::size_t> next{0};
    auto work = [&] {
        QueryContext context;
        context.rtc.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        for (;;) {
            const std::size_t begin = next.fetch_add(kChunk);
            if (begin >= count) break;
            fn(begin, std::min(begin + kChunk, count), context);
        }
    };
    if (workers <= 1) {
        work();
        return;
    }
    std::vector<std::thread> pool;
    pool.reserve(workers - 1);
    for (unsigned i = 1; i < workers; ++i) {
        // Out of threads is not an error: the shared counter lets fewer workers finish the job.
        try {
            pool.emplace_back(work);
        } catch (const std::system_error&) {
            break;
        }
    }
    work();
    for (std::thread& t : pool) t.join();
}

void checkSpans(std::size_t points, std::size_t normals, std::size_t out, const char* fn) {
    if (normals != points || out != points) {
        throw std::invalid_argument(std::string("RayTracer::") + fn +
                                    ": points, normals and out must have the same size");
    }
}

// Light sample k of a point: the base pattern shifted on the torus, as a point on the light.
glm::vec3 samplePoint(const RectLight& light, const std::vector<glm::vec2>& base,
                      const glm::vec2& shift, int k) {
    const glm::vec2 st = base[static_cast<std::size_t>(k)] + shift;
    return light.point(wrapUnit(st.x), wrapUnit(st.y));
}

// Counts the unoccluded shadow rays of one point, kPacket rays per rtcOccluded call.
// Samples behind the point's own tangent plane (dot(n, y - p) <= 0) are blocked by the surface
// the point lies on and get no ray: decided exactly here, they do not depend on the origin
// offset, which would otherwise let rays that cross the surface just past a nearby edge
// escape (a bias of the order of the offset, visible on narrow faces whose plane cuts the
// light). The rasterised reference makes the same decision through the surface's own cap.
bool facesSample(const glm::vec3& p, const glm::vec3& n, const glm::vec3& y) {
    return glm::dot(n, y - p) > 0.0f || !(glm::dot(n, n) > 0.0f);
}

// The light the rays of one point let through, summed over the samples, kPacket rays per
// rtcOccluded call: 1 per unoccluded ray (the alpha test), or the product of (1 - alpha) over
// the translucent surfaces it crosses (the transmittance rule: context.crossed set).
float sumUnoccluded(RTCScene scene, QueryContext& context, const RectLight& light,
                    const glm::vec3& point, const glm::vec3& normal, const glm::vec3& origin,
                    const std::vector<glm::vec2>& base, const glm::vec2& shift, float eps) {
    const int samples = static_cast<int>(base.size());
    float unoccluded = 0.0f;
    for (int k0 = 0; k0 < samples; k0 += kPacket) {
        RayPacket packet;
        alignas(64) int valid[kPacket];
        for (int j = 0; j < kPacket; ++j) {
            const int k = k0 + j;
            const glm::vec3 y = k < samples ? samplePoint(light, base, shift, k) : origin;
            const bool active = k < samples && facesSample(point, normal, y);
            valid[j] = active ? -1 : 0;
            // Unnormalised direction: t = 1 is the light sample itself. Inactive lanes (past
            // the last sample, or behind the surface) get a harmless finite ray.
            const glm::vec3 dir = active ? y - origin : glm::vec3(0.0f, 1.0f, 0.0f);
            packet.org_x[j] = origin.x;
            packet.org_y[j] = origin.y;
            packet.org_z[j] = origin.z;
            packet.dir_x[j] = dir.x;
            packet.dir_y[j] = dir.y;
            packet.dir_z[j] = dir.z;
            packet.tnear[j] = nearLimit(eps, glm::length(dir));
            packet.tfar[j] = shortOfTarget(eps, glm::length(dir));
            packet.time[j] = 0.0f;
            packet.mask[j] = 0xFFFFFFFFu;
            packet.id[j] = static_cast<unsigned>(j);
            packet.flags[j] = 0;
            if (context.crossed) context.crossed[j].clear();
        }
        rtcOccluded8(valid, scene, &context.rtc, &packet);
        for (int j = 0; j < kPacket; ++j) {
            // Embree sets tfar to -inf for an occluded ray.
            if (!valid[j] || !(packet.tfar[j] >= 0.0f)) continue;
            float through = 1.0f;
            if (context.crossed)
                for (const CrossedSurface& c : context.crossed[j]) through *= 1.0f - c.alpha;
            unoccluded += through;
        }
    }
    return unoccluded;
}

// Embree filter of alpha-masked geometry (occlusion and intersection queries alike). The alpha
// test: a hit on a point whose alpha is below the material's cutoff is no hit, and the ray goes
// on. The transmittance rule (the query's context records crossings): a hit of alpha below 1 is
// recorded once with its distance and alpha, and the ray goes on; an opaque one stands.
void alphaFilter(const RTCFilterFunctionNArguments* args) {
    const auto* mesh = static_cast<const MeshData*>(args->geometryUserPtr);
    // Every query of this file passes a QueryContext, whose first member is Embree's context.
    const auto* query = reinterpret_cast<const QueryContext*>(args->context);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
        const glm::vec2 bary(RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i));
        if (!query->crossed) {
            if (!surfaceOccludes(*mesh, prim, bary)) args->valid[i] = 0;
            continue;
        }
        const float alpha = surfaceOpacity(*mesh, prim, bary);
        if (alpha >= 1.0f) continue; // opaque there: the hit stands
        args->valid[i] = 0;
        if (!(alpha > 0.0f)) continue; // wholly transparent
        std::vector<CrossedSurface>& list = query->crossed[RTCRayN_id(args->ray, args->N, i)];
        const unsigned geom = RTCHitN_geomID(args->hit, args->N, i);
        // The filter runs with the ray's tfar set to the hit's distance.
        const float t = RTCRayN_tfar(args->ray, args->N, i);
        // One crossing per surface: a triangle seen twice, or two triangles of one mesh at one
        // distance (a ray through their shared edge hits both; watertight, as it must be).
        const bool seen = std::any_of(list.begin(), list.end(), [&](const CrossedSurface& c) {
            return c.geom == geom &&
                   (c.prim == prim || std::abs(c.t - t) <= 1e-6f * std::max(std::abs(t), 1.0f));
        });
        if (!seen)
            list.push_back({geom, prim, t, alpha,
                            glm::vec3(RTCHitN_Ng_x(args->hit, args->N, i),
                                      RTCHitN_Ng_y(args->hit, args->N, i),
                                      RTCHitN_Ng_z(args->hit, args->N, i))});
    }
}

// A ray with no hit yet, from origin along dir over [tnear, tfar] (units of |dir|).
RTCRayHit makeRayHit(const glm::vec3& origin, const glm::vec3& dir, float tnear, float tfar) {
    RTCRayHit rh{};
    rh.ray.org_x = origin.x;
    rh.ray.org_y = origin.y;
    rh.ray.org_z = origin.z;
    rh.ray.dir_x = dir.x;
    rh.ray.dir_y = dir.y;
    rh.ray.dir_z = dir.z;
    rh.ray.tnear = tnear;
    rh.ray.tfar = tfar;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

RTCRay makeRay(const glm::vec3& origin, const glm::vec3& target, float eps) {
    const glm::vec3 dir = target - origin;
    RTCRay ray{};
    ray.org_x = origin.x;
    ray.org_y = origin.y;
    ray.org_z = origin.z;
    ray.dir_x = dir.x;
    ray.dir_y = dir.y;
    ray.dir_z = dir.z;
    ray.tnear = nearLimit(eps, glm::length(dir));
    ray.tfar = shortOfTarget(eps, glm::length(dir));
    ray.mask = 0xFFFFFFFFu;
    return ray;
}

} // namespace

RayTracer::RayTracer(const Scene& scene) : mImpl(std::make_unique<Impl>()) {
    std::vector<std::size_t> casting;
    for (std::size_t i = 0; i < scene.objects.size(); ++i)
        if (scene.objects[i].method != ShadowMethod::None) casting.push_back(i);
    build(scene, casting);
}

RayTracer::RayTracer(const Scene& scene, std::span<const std::size_t> objects)
    : mImpl(std::make_unique<Impl>()) {
    for (const std::size_t i : objects)
        if (i >= scene.objects.size())
            throw std::invalid_argument("RayTracer: object index out of range");
    build(scene, objects);
}

void RayTracer::build(const Scene& scene, std::span<const std::size_t> objects) {
    Impl& impl = *mImpl;
    impl.device = rtcNewDevice(nullptr);
    if (!impl.device) {
        throw std::runtime_error(std::string("Embree: rtcNewDevice failed: ") +
                                 errorName(rtcGetDeviceError(nullptr)));
    }
    rtcSetDeviceErrorFunction(impl.device, &Impl::onError, &impl);

    impl.scene = rtcNewScene(impl.device);
    impl.check("rtcNewScene");
    // Robust: no watertightness-breaking shortcuts; shadow rays graze shared edges all the time
    // (light-sample rays along a silhouette) and a leak there is a visible bright speck.
    rtcSetSceneFlags(impl.scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(impl.scene, RTC_BUILD_QUALITY_HIGH);

    // Bounds of everything, receivers included (Scene::bounds lives in another file; computed
    // here from the meshes so the offset does not depend on it).
    Aabb bounds;
    for (const SceneObject& object : scene.objects) {
        for (const glm::vec3& p : object.mesh.positions) {
            if (isFinite(p)) bounds.extend(p);
        }
    }
    if (!bounds.empty()) {
        const float d = glm::length(bounds.extent());
        if (d > 0.0f && std::isfinite(d)) impl.diagonal = d;
    }

    for (const std::size_t index : objects) {
        const SceneObject& object = scene.objects[index];
        const MeshData& mesh = object.mesh;
        if (mesh.triangles.empty() || mesh.positions.empty()) continue;
        for (const glm::uvec3& tri : mesh.triangles) {
            if (tri.x >= mesh.positions.size() || tri.y >= mesh.positions.size() ||
                tri.z >= mesh.positions.size()) {
                throw std::runtime_error("RayTracer: object '" + object.name +
                                         "' has a triangle index out of range");
            }
        }
        RTCGeometry geom = rtcNewGeometry(impl.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        impl.check("rtcNewGeometry");
        // rtcSetNewGeometryBuffer pads the buffer as Embree's SIMD loads require.
        auto* vertices = static_cast<float*>(
            rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                    3 * sizeof(float), mesh.positions.size()));
        auto* indices = static_cast<unsigned*>(
            rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(unsigned), mesh.triangles.size()));
        if (!vertices || !indices) {
            rtcReleaseGeometry(geom);
            impl.check(("buffers of object '" + object.name + "'").c_str());
            throw std::runtime_error("Embree: no buffer for object '" + object.name + "'");
        }
        std::memcpy(vertices, mesh.positions.data(), mesh.positions.size() * sizeof(glm::vec3));
        std::memcpy(indices, mesh.triangles.data(), mesh.triangles.size() * sizeof(glm::uvec3));
        if (hasAlphaMask(mesh)) {
            impl.alphaMeshes.push_back(std::make_unique<MeshData>(mesh));
            rtcSetGeometryUserData(geom, impl.alphaMeshes.back().get());
            rtcSetGeometryOccludedFilterFunction(geom, &alphaFilter);
            rtcSetGeometryIntersectFilterFunction(geom, &alphaFilter);
        }
        rtcCommitGeometry(geom);
        rtcAttachGeometry(impl.scene, geom);
        rtcReleaseGeometry(geom); // the scene holds the reference now
        impl.check(("geometry of object '" + object.name + "'").c_str());
    }
    rtcCommitScene(impl.scene);
    impl.check("rtcCommitScene");
}

RayTracer::~RayTracer() = default;

void RayTracer::visibility(const RectLight& light, std::span<const glm::vec3> points,
                           std::span<const glm::vec3> normals, const RayTraceSettings& settings,
                           std::span<float> out) const {
    checkSpans(points.size(), normals.size(), out.size(), "visibility");
    if (settings.samples < 1) {
        throw std::invalid_argument("RayTracer::visibility: samples must be >= 1");
    }
    const std::vector<glm::vec2> base = stratifiedSquare(settings.samples, settings.seed);
    const float eps = mImpl->offsetDistance(settings);
    const int samples = settings.samples;
    const float invSamples = 1.0f / static_cast<float>(samples);
    RTCScene scene = mImpl->scene;

    parallelChunks(points.size(), settings.threads,
                   [&](std::size_t begin, std::size_t end, QueryContext& context) {
        std::vector<CrossedSurface> crossed[kPacket];
        context.crossed = settings.transmittance ? crossed : nullptr;
        for (std::size_t i = begin; i < end; ++i) {
            if (!isFinite(points[i])) {
                out[i] = std::numeric_limits<float>::quiet_NaN();
                continue;
            }
            const glm::vec3 origin = offsetOrigin(points[i], normals[i], eps);
            // Cranley-Patterson rotation: the same stratified pattern, shifted by a per-point
            // random vector on the torus [-1,1)^2. Still one sample per (shifted) stratum, but
            // neighbouring points no longer share their error, so there is no banding.
            const glm::vec2 shift = rotationFor(settings.seed, i);
            const float unoccluded = sumUnoccluded(scene, context, light, points[i], normals[i],
                                                   origin, base, shift, eps);
            out[i] = unoccluded * invSamples;
        }
    });
    mImpl->check("visibility");
}

void RayTracer::hardVisibility(const glm::vec3& lightPoint, std::span<const glm::vec3> points,
                               std::span<const glm::vec3> normals,
                               const RayTraceSettings& settings, std::span<float> out) const {
    checkSpans(points.size(), normals.size(), out.size(), "hardVisibility");
    const float eps = mImpl->offsetDistance(settings);
    RTCScene scene = mImpl->scene;
    parallelChunks(points.size(), settings.threads,
                   [&](std::size_t begin, std::size_t end, QueryContext& context) {
        for (std::size_t i = begin; i < end; ++i) {
            if (!isFinite(points[i])) {
                out[i] = std::numeric_limits<float>::quiet_NaN();
                continue;
            }
            if (!facesSample(points[i], normals[i], lightPoint)) {
                out[i] = 0.0f;
                continue;
            }
            RTCRay ray = makeRay(offsetOrigin(points[i], normals[i], eps), lightPoint, eps);
            rtcOccluded1(scene, &context.rtc, &ray);
            out[i] = ray.tfar >= 0.0f ? 1.0f : 0.0f;
        }
    });
    mImpl->check("hardVisibility");
}

bool RayTracer::intersect(const glm::vec3& origin, const glm::vec3& dir, float& t,
                          glm::vec3& normal) const {
    if (!isFinite(origin) || !isFinite(dir) || dir == glm::vec3(0.0f)) return false;
    QueryContext context;
    RTCRayHit rh = makeRayHit(origin, dir, 0.0f, std::numeric_limits<float>::infinity());
    rtcIntersect1(mImpl->scene, &context.rtc, &rh);
    mImpl->check("intersect");
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    t = rh.ray.tfar; // in units of |dir|
    normal = glm::normalize(glm::vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
    return true;
}

void RayTracer::surfacesAlong(const glm::vec3& origin, const glm::vec3& dir, float tnear,
                              float tfar, std::vector<SurfaceHit>& out) const {
    out.clear();
    if (!isFinite(origin) || !isFinite(dir) || dir == glm::vec3(0.0f) || !(tfar > tnear)) return;
    std::vector<CrossedSurface> crossed;
    QueryContext context;
    context.crossed = &crossed;
    RTCRayHit rh = makeRayHit(origin, dir, std::max(tnear, 0.0f), tfar);
    // The nearest opaque hit (the filter lets none of the others stand) and, recorded on the
    // way, the translucent ones: those nearer than it are crossed.
    rtcIntersect1(mImpl->scene, &context.rtc, &rh);
    const bool opaque = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    const float end = opaque ? rh.ray.tfar : tfar;
    for (const CrossedSurface& c : crossed)
        if (c.t < end) out.push_back({c.t, c.alpha, c.normal});
    std::sort(out.begin(), out.end(),
              [](const SurfaceHit& a, const SurfaceHit& b) { return a.t < b.t; });
    if (opaque) out.push_back({end, 1.0f, glm::vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z)});
}

} // namespace geometry

// The deep-sm method's map (geometry/shadow/DeepShadowMap.h).
#include <geometry/shadow/DeepShadowMap.h>

#include <geometry/shadow/PenumbraDeepShadowMap.h>

#include "shared/Pdsm.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

namespace geometry {

namespace {

// A surface crossed by one of a texel's rays is stored at its plane's depth along the texel's
// centre ray, kept within this many texels (their size at the crossing's depth) of the
// crossing's own depth (a plane nearly along the centre ray meets it far away).
constexpr float kCentreSpanTexels = 8.0f;

std::uint32_t deepValueCode(float v) {
    return static_cast<std::uint32_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

// The depth code of depth z in a face (shared/Pdsm.h pdsmDepthCode, rounded to 16 bits).
std::uint32_t deepDepthCode(float z, const DeepShadowFace& f) {
    const float t = shader::pdsmDepthCode(z, f.zc, f.sFar);
    return static_cast<std::uint32_t>(std::lround(std::clamp(t, 0.0f, 1.0f) * 65535.0f));
}

// One crossing of one ray: at `code` the texel's mean transmittance drops by `drop`.
struct Drop {
    std::uint32_t code = 0;
    float drop = 0.0f;
};

} // namespace

DeepShadowFace deepShadowFace(const PcssFrame& frame, int face, const Aabb& receivers) {
    DeepShadowFace out;
    const PcssFace& s = frame.faces[face];
    out.built = s.drawn && s.casterNear > 0.0f;
    out.zc = s.casterNear > 0.0f ? s.casterNear : frame.zNear;
    float zFar = 0.0f;
    if (!receivers.empty())
        for (int k = 0; k < 8; ++k) {
            const glm::vec3 corner((k & 1) ? receivers.max.x : receivers.min.x,
                                   (k & 2) ? receivers.max.y : receivers.min.y,
                                   (k & 4) ? receivers.max.z : receivers.min.z);
            zFar = std::max(zFar, frame.depth(corner, face));
        }
    // A receiver no deeper than the casters: any range beyond them will do.
    zFar = std::max(zFar, 2.0f * out.zc);
    out.sFar = out.zc / zFar;
    return out;
}

DeepShadowMap buildDeepShadowMap(const PcssFrame& frame, const Aabb& receivers,
                                 const SurfaceQuery& query, const DeepShadowSettings& settings) {
    const auto t0 = std::chrono::steady_clock::now();
    if (settings.resolution < 1 || settings.resolution > 8192)
        throw std::invalid_argument("deep-sm: resolution must lie in [1, 8192], got " +
                                    std::to_string(settings.resolution));
    if (settings.supersample < 1 || settings.supersample > 16)
        throw std::invalid_argument("deep-sm: supersample must lie in [1, 16], got " +
                                    std::to_string(settings.supersample));
    if (!(settings.tolerance > 0.5f / 255.0f + 1e-6f))
        throw std::invalid_argument("deep-sm: tolerance must exceed 0.5 / 255 (the 8-bit "
                                    "values' half step), got " +
                                    std::to_string(settings.tolerance));
    DeepShadowMap out;
    const int R = settings.resolution, S = settings.supersample;
    out.resolution = R;
    out.index.assign(2 * static_cast<std::size_t>(kPcssFaces) * R * R, 0u);
    std::vector<int> faces;
    for (int f = 0; f < kPcssFaces; ++f) {
        out.faces[static_cast<std::size_t>(f)] = deepShadowFace(frame, f, receivers);
        if (out.faces[static_cast<std::size_t>(f)].built) faces.push_back(f);
    }
    // The rays' positions within a texel: cell (a, b) of the S x S grid, moved within it by the
    // R2 sequence over the cell's index (S = 1: the texel's centre, a depth map's sample).
    std::vector<glm::vec2> offsets;
    for (int b = 0; b < S; ++b)
        for (int a = 0; a < S; ++a) {
            const int k = a + S * b;
            offsets.emplace_back((a + std::fmod(0.5f + k * 0.7548776662f, 1.0f)) / S,
                                 (b + std::fmod(0.5f + k * 0.5698402910f, 1.0f)) / S);
        }
    const float share = 1.0f / static_cast<float>(S * S);

    const int rows = R * static_cast<int>(faces.size());
    std::vector<std::vector<std::uint32_t>> rowPoints(static_cast<std::size_t>(rows));
    int threads = settings.threads > 0 ? settings.threads
                                       : static_cast<int>(std::thread::hardware_concurrency());
    threads = std::clamp(threads, 1, 64);
    std::vector<DeepShadowStats> partial(static_cast<std::size_t>(threads));
    std::atomic<int> nextRow{0}, rowsDone{0};
    std::atomic<bool> failed{false};
    std::exception_ptr error; // the first exception of a worker (the query's), rethrown here
    std::mutex errorMutex;
    const auto walkRows = [&](int w) {
        DeepShadowStats& st = partial[static_cast<std::size_t>(w)];
        std::vector<SurfaceHit> hits;
        std::vector<Drop> drops;
        std::vector<PdsmStep> steps;
        for (int row = nextRow++; row < rows && !failed; row = nextRow++) {
            const int face = faces[static_cast<std::size_t>(row / R)], j = row % R;
            const PcssFace& s = frame.faces[face];
            const DeepShadowFace& df = out.faces[static_cast<std::size_t>(face)];
            const float zFar = df.zc / df.sFar;
            const glm::vec2 texel = (s.hi - s.lo) / static_cast<float>(R);
            const float span = kCentreSpanTexels * std::max(texel.x, texel.y);
            std::vector<std::uint32_t>& points = rowPoints[static_cast<std::size_t>(row)];
            for (int i = 0; i < R; ++i) {
                drops.clear();
                const glm::vec2 mc = s.lo + (glm::vec2(i, j) + 0.5f) * texel;
                const glm::vec3 centreDir = mc.x * s.b1 + mc.y * s.b2 + s.axis;
                for (const glm::vec2& o : offsets) {
                    const glm::vec2 m = s.lo + (glm::vec2(i, j) + o) * texel;
                    const glm::vec3 dir = m.x * s.b1 + m.y * s.b2 + s.axis; // t = depth
                    query(frame.center, dir, 1.001f * zFar, hits);
                    ++st.rays;
                    float through = 1.0f;
                    for (const SurfaceHit& h : hits) {
                        const float alpha = std::clamp(h.alpha, 0.0f, 1.0f);
                        if (!(alpha > 0.0f)) continue;
                        ++st.crossings;
                        // The crossing's plane along the centre ray: what the lookup reads
                        // along it is then each surface's coverage of the texel at that
                        // surface's depth there, as a depth map stores the depth at the
                        // texel's centre; a receiver's own surface, the light grazing it, lies
                        // at its plane's depth and not spread over the texel's depths in front
                        // of it (which darkened it by up to half: textured oa_dm5's first spawn
                        // view with the lamp, 0.0077 mean error against 0.0044 at
                        // supersample=1).
                        const float ratio = glm::dot(h.normal, dir) / glm::dot(h.normal, centreDir);
                        const float z =
                            std::isfinite(ratio) && ratio > 0.0f
                                ? std::clamp(h.t * ratio, h.t * (1.0f - span), h.t * (1.0f + span))
                                : h.t;
                        drops.push_back(
                            {std::max(deepDepthCode(z, df), 1u), share * through * alpha});
                        through *= 1.0f - alpha;
                        if (through <= 0.0f) break;
                    }
                }
                std::uint32_t count = 0, nearest = 0;
                if (!drops.empty()) {
                    std::sort(drops.begin(), drops.end(),
                              [](const Drop& a, const Drop& b) { return a.code < b.code; });
                    nearest = drops.front().code;
                    steps.clear();
                    float value = 1.0f;
                    for (const Drop& d : drops) {
                        const float after = std::max(value - d.drop, 0.0f);
                        if (!steps.empty() && steps.back().code == d.code)
                            steps.back().after = after;
                        else
                            steps.push_back({d.code, value, after});
                        value = after;
                    }
                    if (deepValueCode(value) != 255u) {
                        const std::vector<PdsmPoint> pts =
                            compressPdsmStaircase(1.0f, steps, settings.tolerance);
                        st.maxDeviation =
                            std::max(st.maxDeviation, pdsmDeviation(1.0f, steps, pts));
                        if (pts.size() > 0xFFFFu) {
                            failed = true;
                            continue;
                        }
                        for (const PdsmPoint& p : pts)
                            points.push_back(p.code | deepValueCode(p.value) << 16);
                        count = static_cast<std::uint32_t>(pts.size());
                        ++st.texelsStored;
                        st.longest = std::max(st.longest, count);
                        st.points += count;
                    }
                }
                out.index[out.at(face, i, j) + 1] = count | (count ? nearest << 16 : 0u);
            }
            const int done = ++rowsDone;
            if (w == 0 && settings.progress) settings.progress(done, rows);
        }
    };
    const auto work = [&](int w) {
        try {
            walkRows(w);
        } catch (...) {
            std::lock_guard lock(errorMutex);
            if (!error) error = std::current_exception();
            failed = true;
        }
    };
    std::vector<std::thread> pool;
    for (int w = 1; w < threads; ++w)
        pool.emplace_back(work, w);
    work(0); // an exception (the progress callback's: an interrupted run) stops the others
    for (std::thread& t : pool)
        t.join();
    if (error) std::rethrow_exception(error);
    if (failed)
        throw std::length_error("deep-sm: a texel's function holds more than 65535 points; "
                                "raise tolerance");
    if (settings.progress) settings.progress(rows, rows);

    for (const DeepShadowStats& p : partial) {
        out.stats.rays += p.rays;
        out.stats.crossings += p.crossings;
        out.stats.points += p.points;
        out.stats.texelsStored += p.texelsStored;
        out.stats.longest = std::max(out.stats.longest, p.longest);
        out.stats.maxDeviation = std::max(out.stats.maxDeviation, p.maxDeviation);
    }
    std::uint64_t groups = 0;
    for (std::size_t k = 1; k < out.index.size(); k += 2)
        groups += (deepPointCount(out.index[k]) + 3) / 4;
    if (groups > 0xFFFFFFFFull) throw std::length_error("deep-sm: more than 2^32 point groups");
    out.data.assign(3 * groups, 0u);
    std::uint32_t group = 0;
    for (int row = 0; row < rows; ++row) {
        const int face = faces[static_cast<std::size_t>(row / R)], j = row % R;
        group = packPdsmRow(rowPoints[static_cast<std::size_t>(row)],
                            out.index.data() + out.at(face, 0, j), R, 0xFFFFu, group,
                            out.data.data());
    }
    out.stats.buildMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

float evaluateDeepShadowMap(const DeepShadowMap& map, int face, int i, int j, float t) {
    const std::size_t at = map.at(face, i, j);
    return evaluatePdsmFunction(map.data, map.index[at], deepPointCount(map.index[at + 1]), t);
}

} // namespace geometry

// The method table (gpu/Methods.h): the one list of method names.
#include <gpu/Methods.h>

#include "engine/MethodOptions.h"

#include <geometry/core/Error.h>

#include "engine/Method.h"

#include <algorithm>
#include <array>

namespace gpu {

namespace {

// wedges-blend (Forest et al. 2006): the three parameters of the method's issue.
constexpr std::string_view kBlendParts[] = {"1", "4", "8"};
constexpr std::string_view kBlendBits[] = {"8", "16"};
constexpr std::string_view kBlendOverlap[] = {"paper", "centroid"};
constexpr MethodParameter kBlendParameters[] = {
    {"parts", kBlendParts, "4",
     "radial parts of the light: 1 (the whole light), 4 (quadrants, the paper), 8 (half-quadrants)"},
    {"bits", kBlendBits, "8", "bits per packed value of the stored states (8: the paper)"},
    {"overlap", kBlendOverlap, "paper",
     "overlap estimate: paper (occlusion uniform over each rectangle) or centroid (linear "
     "densities through the stored centroids)"},
};

// wedges-bitmask: light samples per pixel and their pattern.
constexpr std::string_view kBitmaskSamples[] = {"32", "64", "128", "256"};
constexpr std::string_view kBitmaskPattern[] = {"fixed", "rotated"};
constexpr std::string_view kBitmaskCombine[] = {"parity", "counts"};
constexpr std::string_view kBitmaskSilhouettes[] = {"potential", "centre"};
constexpr std::string_view kBitmaskEstimate[] = {"ratio", "quadrants", "moments", "samples"};
constexpr std::string_view kBitmaskEvaluate[] = {"auto", "tiles", "raster"};
constexpr MethodParameter kBitmaskParameters[] = {
    {"samples", kBitmaskSamples, "64",
     "light samples per pixel and silhouette group, one bit each (the reference's stratified "
     "pattern for the same count and seed)"},
    {"pattern", kBitmaskPattern, "fixed",
     "fixed: the same samples at every pixel and frame (stable, bands in wide penumbrae); "
     "rotated: shifted per pixel (noise instead of bands)"},
    {"combine", kBitmaskCombine, "counts",
     "with silhouettes=centre, within a group: counts (signed 4-bit counts per sample by image "
     "atomics; exact while each stays in [-8, 7]) or parity (XOR by the logic op, no atomics; a "
     "sample the group covers twice reads as lit: open level geometry folding behind itself)"},
    {"silhouettes", kBitmaskSilhouettes, "potential",
     "potential: per receiver, every edge that is a silhouette from some light point, one count "
     "per sample over all casters (exact to the samples for any caster and light); centre: the "
     "light centre's silhouette per group (the wedge papers' approximation)"},
    {"estimate", kBitmaskEstimate, "moments",
     "with silhouettes=potential: ratio (the exact integral of the counts times the sampled share "
     "of hidden samples over their mean count: exact at any N where one layer hides the light), "
     "quadrants (the same per quadrant of the light, each with its own exact integral: less "
     "error where layers overlap), moments (quadrants, but where the hidden samples show two "
     "layer counts, both layers' exact areas from the exact first and second moments of the "
     "count over the light, the second from every pair of edges' overlap: exact where no third "
     "count hides; needs the tiled evaluation, which it takes) or samples (the share of hidden "
     "samples)"},
    {"evaluate", kBitmaskEvaluate, "auto",
     "with silhouettes=potential: tiles (the wedges binned to 8x8 pixel tiles whose surface they "
     "may reach, then every pixel over its tile's list in one compute pass), raster (the wedge "
     "hulls rasterised, one fragment per pixel and wedge; also any frame whose tile lists pass "
     "their limits) or auto (with estimate=moments, the default, tiles on every frame; with the "
     "other estimates tiles from 512 potential edges drawn in the frame, raster below: the "
     "crossover measured by scripts/bench-tiles.sh); the same counts and V"},
};

// occlusion (Eisemann & Decoret 2006): slices, prefilter, leak fix, texture size.
constexpr std::string_view kOcclusionSlices[] = {"4", "8", "16"};
constexpr std::string_view kOcclusionPrefilter[] = {"nbuffers", "sat", "mipmaps"};
constexpr std::string_view kOcclusionLeakFix[] = {"auto", "on", "off", "paper"};
constexpr std::string_view kOcclusionResolution[] = {"256", "512", "1024"};
constexpr std::string_view kOcclusionHorizon[] = {"on", "off"};
constexpr std::string_view kOcclusionOutside[] = {"pcss", "lit"};
constexpr MethodParameter kOcclusionParameters[] = {
    {"slices", kOcclusionSlices, "8",
     "binary slices parallel to the light over the casters' depth range (4 per RGBA target)"},
    {"prefilter", kOcclusionPrefilter, "nbuffers",
     "box filter of the slices: nbuffers (the paper's choice), sat (summed-area tables, exact), "
     "mipmaps (blocky; for comparison)"},
    {"leakfix", kOcclusionLeakFix, "auto",
     "thin-occluder leaks: also write fragments near the next slice into it (within slice "
     "depth x tan(tilt)); auto: for open, non-manifold and alpha-tested casters; paper: every "
     "fragment of every caster (flat sheets then count twice)"},
    {"resolution", kOcclusionResolution, "512", "side of the occlusion textures in texels"},
    {"horizon", kOcclusionHorizon, "on",
     "V times the fraction of the light in front of the surface (not in the paper, which leaves "
     "surfaces turned from the light to the diffuse term)"},
    {"outside", kOcclusionOutside, "pcss",
     "receivers the slicing frustum cannot hold (behind or in the light's plane, beyond the "
     "capped frustum: the walls and ceiling of a room around a lamp): pcss (shadowed from pcss's "
     "shadow maps, its defaults; counted as occlusion_pixels_outside) or lit (the paper's V = 1)"},
};

// pcss (Fernando 2005): shadow-map size and the samples of its two steps.
constexpr std::string_view kPcssResolution[] = {"512", "1024", "2048"};
constexpr std::string_view kPcssSamples[] = {"16", "32", "64"};
constexpr std::string_view kPcssBias[] = {"0.0", "0.5", "1.5", "3.0"};
constexpr std::string_view kPcssHorizon[] = {"on", "off"};
constexpr MethodParameter kPcssParameters[] = {
    {"resolution", kPcssResolution, "1024", "side of each shadow map in texels"},
    {"blocker_samples", kPcssSamples, "16",
     "samples of the blocker search (each reads 2 x 2 texels; a fixed stratified pattern)"},
    {"pcf_samples", kPcssSamples, "32",
     "samples of the percentage-closer filter (each 2 x 2 texels, bilinear; a fixed pattern)"},
    {"bias", kPcssBias, "1.5",
     "depth bias: the receiver's plane moved this many map texels (their world size at the "
     "receiver) towards the light; more hides acne and concave corners, less keeps contact"},
    {"horizon", kPcssHorizon, "on",
     "V times the fraction of the light in front of the surface (not in the paper; as occlusion's)"},
};

// sample-maps: one alpha-tested shadow map per light sample.
constexpr std::string_view kSampleMapsSamples[] = {"16", "32", "64", "128", "256"};
constexpr std::string_view kSampleMapsResolution[] = {"256", "512", "1024"};
constexpr std::string_view kSampleMapsBias[] = {"0.0", "0.5", "1.0", "2.0"};
constexpr std::string_view kSampleMapsPlane[] = {"on", "off"};
constexpr std::string_view kSampleMapsEarlyOut[] = {"on", "off"};
constexpr MethodParameter kSampleMapsParameters[] = {
    {"samples", kSampleMapsSamples, "64",
     "light samples, one shadow map each (the reference's stratified pattern for the same count "
     "and seed)"},
    {"resolution", kSampleMapsResolution, "512",
     "side of each map in texels (each map holds the casters' box as seen from its sample)"},
    {"bias", kSampleMapsBias, "0.5",
     "the receiver moved 0.25 + bias x sin(angle between its normal and the sample) map texels "
     "(their world size at the receiver) along its normal, towards the sample: more hides acne "
     "on surfaces the light grazes, less keeps contact shadows"},
    {"plane", kSampleMapsPlane, "on",
     "on: a sample behind the receiver's own plane is hidden (as raytrace counts it); off: only "
     "the casters hide (auto's composition, whose wedge path counts the plane)"},
    {"early_out", kSampleMapsEarlyOut, "on",
     "on: a receiver whose pyramid to the light holds no caster (four reads of a max N-buffer "
     "of the map nearest the light's centre) is lit from every sample in front of its plane "
     "without reading the N maps (the same V up to the maps' rasterisation); off: every "
     "receiver in reach reads all N maps"},
};

// linear-light-sm (Heidrich et al. 2000): linear lights' end-point maps with skins.
constexpr std::string_view kLinearLights[] = {"1", "2", "4", "8"};
constexpr std::string_view kLinearResolution[] = {"256", "512", "1024"};
constexpr MethodParameter kLinearLightSmParameters[] = {
    {"lights", kLinearLights, "2",
     "linear lights along the light's longer axis, at stratified offsets across the shorter "
     "one, each from the rectangle's edge to its edge; two shadow maps (its end points) each"},
    {"resolution", kLinearResolution, "512", "side of each end point's map in texels"},
    {"bias", kSampleMapsBias, "1.0",
     "as sample-maps' bias (more by default: with two maps per linear light, a map's acne on a "
     "surface the light grazes is not averaged away; a closed room's walls err 0.036 mean at "
     "0.5, 0.024 at 1.0)"},
    {"plane", kSampleMapsPlane, "on", "as sample-maps' plane"},
};

// pdsm (St-Amour et al. 2005): the sample maps merged into one deep map from the light's centre.
constexpr std::string_view kPdsmSamples[] = {"16", "32", "64", "128", "256"};
constexpr std::string_view kPdsmResolution[] = {"128", "256", "512", "1024"};
constexpr std::string_view kPdsmTolerance[] = {"0.002", "0.003", "0.004", "0.008", "0.016",
                                               "0.032"};
constexpr std::string_view kPdsmNoise[] = {"0", "0.25", "0.5", "1", "2"};
constexpr std::string_view kPdsmBias[] = {"0.0", "0.05", "0.1", "0.25", "0.5", "1.0"};
constexpr std::string_view kPdsmPlane[] = {"on", "off"};
constexpr std::string_view kPdsmCull[] = {"on", "off"};
constexpr MethodParameter kPdsmParameters[] = {
    {"samples", kPdsmSamples, "256",
     "light samples k, one shadow map each (the reference's stratified pattern for the same "
     "count and seed), merged into the deep map; precomputed once per light and casters"},
    {"resolution", kPdsmResolution, "512",
     "side of each sample map and of the deep map (from the light's centre) in texels"},
    {"tolerance", kPdsmTolerance, "0.004",
     "the compression's guaranteed bound on |V stored - V of the k samples| at every depth of "
     "every texel, 8-bit values included: more stores fewer points (at or below 1 / (2k) + "
     "0.002 every sample's step is kept)"},
    {"noise", kPdsmNoise, "0.5",
     "where V lies between 0 and 1, the bound may be this many standard errors of the k "
     "samples' own estimate, sqrt(V (1 - V) / k), where that is more than tolerance (0: "
     "tolerance everywhere)"},
    {"bias", kPdsmBias, "0.05",
     "the receiver moved bias x tan(angle between its normal and the light's centre) deep-map "
     "texels along its normal, to the side it faces (tan capped at 8): a surface the light "
     "grazes, narrower in the maps than a texel, is otherwise hidden by the surface beside it "
     "in the same texel (a level's stair risers); more lifts every receiver towards its casters "
     "(lighter penumbrae)"},
    {"plane", kPdsmPlane, "on",
     "on: V at most the share of the light in front of the receiver's own plane (as raytrace "
     "counts it); off: only the deep map"},
    {"cull", kPdsmCull, "on",
     "on: each texel's function kept only at the depths where the lookup may read it for a "
     "point of the scene's surfaces (a level's rays cross rock between its rooms; a texel no "
     "surface reads holds nothing), not applied while objects are dynamic, which may be "
     "anywhere when it is read (pdsm_cull says which); off: at every depth"},
};

// deep-sm (Lokovic & Veach 2000): pcss's faces as deep shadow maps of transmittance.
constexpr std::string_view kDeepSmResolution[] = {"128", "256", "512", "1024"};
constexpr std::string_view kDeepSmSupersample[] = {"1", "2", "3", "4"};
constexpr std::string_view kDeepSmTolerance[] = {"0.004", "0.008", "0.016", "0.032"};
constexpr MethodParameter kDeepSmParameters[] = {
    {"resolution", kDeepSmResolution, "512",
     "side of each face's deep map in texels (the faces of pcss's cube around the light)"},
    {"supersample", kDeepSmSupersample, "3",
     "S: S x S rays per texel from the light's centre through its area, their transmittance "
     "averaged (pixel-area filtering; 1: one ray through the texel's centre, a depth map's "
     "sample)"},
    {"tolerance", kDeepSmTolerance, "0.004",
     "the compression's guaranteed bound on |T stored - T of the texel's rays| at every depth, "
     "8-bit values included: more stores fewer points"},
    {"blocker_samples", kPcssSamples, "16",
     "samples of the blocker search (each reads 2 x 2 texels, weighted by their opacity at the "
     "receiver; a fixed stratified pattern)"},
    {"pcf_samples", kPcssSamples, "32",
     "samples of the filter over the light (each 2 x 2 texels' transmittance at the receiver, "
     "bilinear; a fixed pattern)"},
    {"bias", kPcssBias, "1.5",
     "the receiver's plane moved this many map texels (their world size at the receiver) "
     "towards the light before the transmittance is read, as pcss's depth bias"},
    {"horizon", kPcssHorizon, "on",
     "V times the fraction of the light in front of the surface (as pcss's)"},
};

// raytrace: the alpha rule.
constexpr std::string_view kRaytraceTransmittance[] = {"off", "on"};
constexpr MethodParameter kRaytraceParameters[] = {
    {"transmittance", kRaytraceTransmittance, "off",
     "off: alpha-tested (MASK, and BLEND at 0.5) surfaces hide a ray where their alpha reaches "
     "the cutoff; on: every surface lets 1 - alpha through, the ray carrying the product (the "
     "rule deep-sm computes: translucent flames and glass, soft leaf edges)"},
};

// auto: which wedge method serves the objects it gives to wedges.
constexpr std::string_view kAutoWedges[] = {"bitmask", "blend", "additive", "multiply"};
constexpr std::string_view kAutoAlpha[] = {"sample-maps", "pcss", "occlusion"};
constexpr MethodParameter kAutoParameters[] = {
    {"wedges", kAutoWedges, "bitmask",
     "the wedge method of the objects auto gives to wedges: wedges-blend, -additive, -multiply "
     "or -bitmask (its default parameters)"},
    {"alpha", kAutoAlpha, "sample-maps",
     "the alpha path, for alpha-tested objects (foliage, grates): sample-maps (one shadow map "
     "per light sample; objects it cannot hold in front of the light, a lamp among them, go to "
     "pcss), pcss's shadow maps or occlusion textures (each with its default parameters)"},
};

const std::array<MethodInfo, 14> kMethods = {{
    {"hard", "z-fail stencil shadow volumes from the light centre", false, createHardMethod},
    {"reference", "average of N hard-shadow passes from stratified light points (GPU)", true,
     createReferenceMethod},
    {"raytrace", "N stratified Embree rays per pixel to the light (CPU)", true,
     createRaytraceMethod, kRaytraceParameters, true},
    {"wedges-additive", "penumbra wedges, coverage summed (Assarsson & Akenine-Moller 2003)",
     false, createAdditiveWedgesMethod},
    {"wedges-blend", "per-silhouette visibility buffers blended (Forest et al. 2006)", false,
     createBlendWedgesMethod, kBlendParameters},
    {"wedges-bitmask",
     "light-sample counts from every edge that is a silhouette from some light point, per "
     "receiver (exact to the samples), ratio estimator; silhouettes=centre: per-group masks",
     false, createBitmaskWedgesMethod, kBitmaskParameters},
    {"wedges-multiply", "per-silhouette visibility buffers multiplied (independent occluders)",
     false, createMultiplyWedgesMethod},
    {"occlusion", "occlusion textures (Eisemann & Decoret 2006); honours alpha-tested casters",
     false, createOcclusionMethod, kOcclusionParameters, true},
    {"pcss", "percentage-closer soft shadows (Fernando 2005), shadow maps from the light centre; "
     "honours alpha-tested casters", false, createPcssMethod, kPcssParameters, true},
    {"sample-maps", "average of N hard shadows from light samples, one shadow map each; honours "
     "alpha-tested casters", false, createSampleMapsMethod, kSampleMapsParameters, true},
    {"linear-light-sm", "soft shadow maps for linear lights (Heidrich et al. 2000): the "
     "rectangle as parallel linear lights, shadow maps from their end points, skin polygons "
     "from each map's depth discontinuities warped into the other's view with a visibility "
     "ramp; honours alpha-tested casters", false, createLinearLightSmMethod,
     kLinearLightSmParameters, true},
    {"pdsm", "penumbra deep shadow maps (St-Amour et al. 2005): k sample shadow maps merged "
     "into one map of compressed visibility functions along depth, precomputed per light; "
     "honours alpha-tested casters", false, createPdsmMethod, kPdsmParameters, true},
    {"deep-sm", "deep shadow maps (Lokovic & Veach 2000): per texel of maps from the light's "
     "centre, the transmittance along depth from S x S rays (partial coverage and alpha), "
     "compressed; filtered over the light as pcss; honours alpha and translucency", false,
     createDeepSmMethod, kDeepSmParameters, true},
    {"auto", "per-object choice (wedges or occlusion textures), composed in one frame", false,
     createAutoMethod, kAutoParameters, true},
}};

} // namespace

std::span<const MethodInfo> methodTable() { return kMethods; }

std::string methodNameList(bool implementedOnly) {
    std::string list;
    for (const MethodInfo& m : kMethods) {
        if (implementedOnly && !m.implemented()) continue;
        if (!list.empty()) list += ", ";
        list += m.name;
    }
    return list;
}

namespace {

std::string joined(std::span<const std::string_view> values, const char* separator) {
    std::string list;
    for (std::string_view v : values) {
        if (!list.empty()) list += separator;
        list += v;
    }
    return list;
}

} // namespace

std::vector<ParameterValue> resolveParameters(const MethodInfo& method,
                                              std::span<const ParameterValue> given) {
    const std::string what = "method '" + std::string(method.name) + "'";
    std::vector<std::string_view> names;
    for (const MethodParameter& p : method.parameters) names.push_back(p.name);
    for (std::size_t i = 0; i < given.size(); ++i) {
        const ParameterValue& g = given[i];
        if (method.parameters.empty())
            throw geometry::InputError(what + " has no parameters (got '" + g.name + "')");
        const auto declared =
            std::find_if(method.parameters.begin(), method.parameters.end(),
                         [&](const MethodParameter& p) { return p.name == g.name; });
        if (declared == method.parameters.end())
            throw geometry::InputError("unknown parameter '" + g.name + "' of " + what +
                                       " (its parameters: " + joined(names, ", ") + ")");
        if (std::find(declared->values.begin(), declared->values.end(), g.value) ==
            declared->values.end())
            throw geometry::InputError("parameter '" + g.name + "' of " + what + ": '" + g.value +
                                       "' is not allowed (allowed: " +
                                       joined(declared->values, ", ") + ")");
        for (std::size_t j = 0; j < i; ++j)
            if (given[j].name == g.name)
                throw geometry::InputError("parameter '" + g.name + "' of " + what +
                                           " is given twice");
    }
    std::vector<ParameterValue> resolved;
    for (const MethodParameter& p : method.parameters) {
        ParameterValue v{std::string(p.name), std::string(p.defaultValue)};
        for (const ParameterValue& g : given)
            if (g.name == p.name) v.value = g.value;
        resolved.push_back(std::move(v));
    }
    return resolved;
}

ParameterValue parseParameter(std::string_view text) {
    const std::size_t eq = text.find('=');
    if (eq == std::string_view::npos || eq == 0 || eq + 1 == text.size())
        throw geometry::InputError("--param: expected NAME=VALUE (e.g. parts=8), got '" +
                                   std::string(text) + "'");
    return {std::string(text.substr(0, eq)), std::string(text.substr(eq + 1))};
}

std::string_view parameterValue(std::span<const ParameterValue> resolved, std::string_view name) {
    for (const ParameterValue& p : resolved)
        if (p.name == name) return p.value;
    return {};
}

const MethodInfo& findMethod(std::string_view name) {
    for (const MethodInfo& m : kMethods) {
        if (m.name != name) continue;
        if (!m.implemented())
            throw geometry::InputError("method '" + std::string(name) +
                                       "' is part of the render contract but not implemented "
                                       "yet; implemented: " +
                                       methodNameList(true));
        return m;
    }
    throw geometry::InputError("unknown method '" + std::string(name) +
                               "' (known: " + methodNameList() + ")");
}

// --- Typed options (engine/MethodOptions.h) ---

namespace {

int intValue(std::span<const ParameterValue> resolved, std::string_view name) {
    return std::stoi(std::string(parameterValue(resolved, name)));
}

} // namespace

BlendOptions blendOptions(std::span<const ParameterValue> given) {
    const std::vector<ParameterValue> r = resolveParameters(findMethod("wedges-blend"), given);
    return {.parts = intValue(r, "parts"),
            .bits = intValue(r, "bits"),
            .centroid = parameterValue(r, "overlap") == "centroid"};
}

BitmaskOptions bitmaskOptions(std::span<const ParameterValue> given) {
    const std::vector<ParameterValue> r = resolveParameters(findMethod("wedges-bitmask"), given);
    BitmaskOptions o{.samples = intValue(r, "samples"),
                     .rotated = parameterValue(r, "pattern") == "rotated",
                     .counts = parameterValue(r, "combine") == "counts",
                     .potential = parameterValue(r, "silhouettes") == "potential",
                     .estimate = parameterValue(r, "estimate") == "samples"
                                     ? BitmaskOptions::Estimate::Samples
                                 : parameterValue(r, "estimate") == "quadrants"
                                     ? BitmaskOptions::Estimate::Quadrants
                                 : parameterValue(r, "estimate") == "moments"
                                     ? BitmaskOptions::Estimate::Moments
                                     : BitmaskOptions::Estimate::Ratio,
                     .evaluate = parameterValue(r, "evaluate") == "tiles"    ? BitmaskOptions::Evaluate::Tiles
                                 : parameterValue(r, "evaluate") == "raster" ? BitmaskOptions::Evaluate::Raster
                                                                             : BitmaskOptions::Evaluate::Auto};
    if (o.potential && o.estimate == BitmaskOptions::Estimate::Moments &&
        o.evaluate == BitmaskOptions::Evaluate::Raster)
        throw geometry::InputError("wedges-bitmask: estimate=moments needs the tiled evaluation "
                                   "(evaluate=auto or tiles), which sums the pairs of edges");
    if (o.potential && !o.counts)
        throw geometry::InputError("wedges-bitmask: combine=parity needs silhouettes=centre "
                                   "(silhouettes=potential always counts)");
    return o;
}

OcclusionOptions occlusionOptions(std::span<const ParameterValue> given) {
    const std::vector<ParameterValue> r = resolveParameters(findMethod("occlusion"), given);
    const std::string_view prefilter = parameterValue(r, "prefilter");
    const std::string_view leakFix = parameterValue(r, "leakfix");
    return {.slices = intValue(r, "slices"),
            .prefilter = prefilter == "sat"       ? OcclusionPrefilter::Sat
                         : prefilter == "mipmaps" ? OcclusionPrefilter::Mipmaps
                                                  : OcclusionPrefilter::NBuffers,
            .leakFix = leakFix == "on"      ? OcclusionLeakFix::On
                       : leakFix == "off"   ? OcclusionLeakFix::Off
                       : leakFix == "paper" ? OcclusionLeakFix::Paper
                                            : OcclusionLeakFix::Auto,
            .resolution = intValue(r, "resolution"),
            .horizon = parameterValue(r, "horizon") == "on",
            .outsidePcss = parameterValue(r, "outside") == "pcss"};
}

PcssOptions pcssOptions(std::span<const ParameterValue> given) {
    const std::vector<ParameterValue> r = resolveParameters(findMethod("pcss"), given);
    return {.resolution = intValue(r, "resolution"),
            .blockerSamples = intValue(r, "blocker_samples"),
            .pcfSamples = intValue(r, "pcf_samples"),
            .bias = std::string(parameterValue(r, "bias")),
            .horizon = parameterValue(r, "horizon") == "on"};
}

SampleMapsOptions sampleMapsOptions(std::span<const ParameterValue> given) {
    const std::vector<ParameterValue> r = resolveParameters(findMethod("sample-maps"), given);
    return {.samples = intValue(r, "samples"),
            .resolution = intValue(r, "resolution"),
            .normalOffset = std::stof(std::string(parameterValue(r, "bias"))),
            .ownPlane = parameterValue(r, "plane") == "on",
            .earlyOut = parameterValue(r, "early_out") == "on"};
}

LinearLightSmOptions linearLightSmOptions(std::span<const ParameterValue> given) {
    const std::vector<ParameterValue> r = resolveParameters(findMethod("linear-light-sm"), given);
    return {.lights = intValue(r, "lights"),
            .resolution = intValue(r, "resolution"),
            .normalOffset = std::stof(std::string(parameterValue(r, "bias"))),
            .ownPlane = parameterValue(r, "plane") == "on"};
}

PdsmOptions pdsmOptions(std::span<const ParameterValue> given) {
    const std::vector<ParameterValue> r = resolveParameters(findMethod("pdsm"), given);
    return {.samples = intValue(r, "samples"),
            .resolution = intValue(r, "resolution"),
            .tolerance = std::stof(std::string(parameterValue(r, "tolerance"))),
            .noise = std::stof(std::string(parameterValue(r, "noise"))),
            .normalOffset = std::stof(std::string(parameterValue(r, "bias"))),
            .ownPlane = parameterValue(r, "plane") == "on",
            .cull = parameterValue(r, "cull") == "on"};
}

DeepSmOptions deepSmOptions(std::span<const ParameterValue> given) {
    const std::vector<ParameterValue> r = resolveParameters(findMethod("deep-sm"), given);
    return {.lookup = {.resolution = intValue(r, "resolution"),
                       .blockerSamples = intValue(r, "blocker_samples"),
                       .pcfSamples = intValue(r, "pcf_samples"),
                       .bias = std::string(parameterValue(r, "bias")),
                       .horizon = parameterValue(r, "horizon") == "on"},
            .supersample = intValue(r, "supersample"),
            .tolerance = std::stof(std::string(parameterValue(r, "tolerance")))};
}

RaytraceOptions raytraceOptions(std::span<const ParameterValue> given) {
    const std::vector<ParameterValue> r = resolveParameters(findMethod("raytrace"), given);
    return {.transmittance = parameterValue(r, "transmittance") == "on"};
}

AutoOptions autoOptions(std::span<const ParameterValue> given) {
    const std::vector<ParameterValue> r = resolveParameters(findMethod("auto"), given);
    return {.wedgeMethod = "wedges-" + std::string(parameterValue(r, "wedges")),
            .alphaMethod = std::string(parameterValue(r, "alpha"))};
}

} // namespace gpu

// Typed options of the methods that take parameters (gpu/Methods.h). The method table in
// Methods.cpp is the one place a parameter is declared: its name, allowed values, default and
// help, which --help, the viewer's panel and report.json list. Each function below resolves the
// given values against that table (filling in the table's defaults; an unknown name or value
// is the table's InputError) and reads them once into the method's struct, so that no method
// parses strings or restates a default.
#pragma once

#include <gpu/Methods.h>

#include <cstddef>
#include <span>
#include <string>

namespace gpu {

// wedges-blend (Forest et al. 2006).
struct BlendOptions {
    int parts = 0;         // radial parts of the light: 1, 4 (the paper) or 8
    int bits = 0;          // bits per packed value of the stored states: 8 (the paper) or 16
    bool centroid = false; // overlap estimate from the parts' centroids instead of the paper's
};
BlendOptions blendOptions(std::span<const ParameterValue> given);

// wedges-bitmask.
struct BitmaskOptions {
    int samples = 0;       // light samples per mask: 32, 64, 128 or 256
    bool rotated = false;  // per-pixel Cranley-Patterson shift of the pattern
    bool counts = false;   // combine=counts (signed 4-bit counts); false: parity
    // silhouettes=potential: one two-sided count per sample over every caster, from the
    // potential silhouettes seen per receiver (engine/PotentialSet.h); false: centre.
    bool potential = false;
    // With potential: how V is estimated from the counts (bitmask-potential-resolve.frag's
    // uEstimate).
    enum class Estimate { Ratio = 0, Samples = 1, Quadrants = 2, Moments = 3 };
    Estimate estimate = Estimate::Ratio;
    // With potential: the wedges evaluated per pixel over screen tiles' lists (a compute pass,
    // passes/WedgeTilePass.h) or rasterised as hulls (the same counts), or per frame by the
    // number of potential edges drawn (Auto: tiles from kAutoTiledEdges; with Moments, which
    // needs the tiled lists, tiles on every frame).
    enum class Evaluate { Auto, Tiles, Raster };
    Evaluate evaluate = Evaluate::Auto;
    static constexpr std::size_t kAutoTiledEdges = 512;
};
BitmaskOptions bitmaskOptions(std::span<const ParameterValue> given);

// occlusion (Eisemann & Decoret 2006).
enum class OcclusionPrefilter { NBuffers, Sat, Mipmaps };
enum class OcclusionLeakFix { Auto, On, Off, Paper };
struct OcclusionOptions {
    int slices = 0;
    OcclusionPrefilter prefilter = OcclusionPrefilter::NBuffers;
    OcclusionLeakFix leakFix = OcclusionLeakFix::Auto;
    int resolution = 0; // side of the occlusion textures in texels
    bool horizon = false;
    bool outsidePcss = false; // receivers the frustum cannot hold: from pcss's maps (else lit)
};
OcclusionOptions occlusionOptions(std::span<const ParameterValue> given);

// pcss (Fernando 2005).
struct PcssOptions {
    int resolution = 0; // side of each shadow map in texels
    int blockerSamples = 0;
    int pcfSamples = 0;
    std::string bias; // the depth bias in map texels, as the table writes it (the shader's define)
    bool horizon = false;
};
PcssOptions pcssOptions(std::span<const ParameterValue> given);

// deep-sm: deep shadow maps (Lokovic & Veach 2000) in pcss's frame and lookup.
struct DeepSmOptions {
    PcssOptions lookup;    // resolution (of each face's deep map), samples, bias, horizon
    int supersample = 0;   // S: S x S rays per texel
    float tolerance = 0.0f; // the compression's bound on |dT|
};
DeepSmOptions deepSmOptions(std::span<const ParameterValue> given);

// raytrace.
struct RaytraceOptions {
    bool transmittance = false; // the product of (1 - alpha) along each ray (RayTraceSettings)
};
RaytraceOptions raytraceOptions(std::span<const ParameterValue> given);

// sample-maps: one shadow map per light sample.
struct SampleMapsOptions {
    int samples = 0;          // light samples N, one map each
    int resolution = 0;       // side of each map in texels
    float normalOffset = 0.0f; // the receiver offset's grazing part: x sin(angle) map texels
    bool ownPlane = true;      // a sample behind the receiver's own plane is hidden
    bool earlyOut = true;      // receivers whose pyramid to the light is empty skip the maps
};
SampleMapsOptions sampleMapsOptions(std::span<const ParameterValue> given);

// linear-light-sm: soft shadow maps for linear lights (Heidrich, Brabec & Seidel 2000), the
// rectangle as parallel linear lights; sample-maps' maps and lookup for their end points.
struct LinearLightSmOptions {
    int lights = 0;            // linear lights along the light's longer axis
    int resolution = 0;        // side of each end point's map
    float normalOffset = 0.0f; // as sample-maps' bias
    bool ownPlane = true;
};
LinearLightSmOptions linearLightSmOptions(std::span<const ParameterValue> given);

// pdsm: penumbra deep shadow maps (St-Amour et al. 2005).
struct PdsmOptions {
    int samples = 0;         // light samples k, one shadow map each, merged into the deep map
    int resolution = 0;      // side of each sample map and of the deep map in texels
    float tolerance = 0.0f;  // the compression's bound on |dV|
    float noise = 0.0f;      // up to this many standard errors of the samples' V where more
    float normalOffset = 0.0f; // the receiver offset: x tan(angle) deep-map texels
    bool ownPlane = true;    // V at most the share of the light in front of the receiver
    bool cull = true;        // functions kept only at the depths a receiver may read them
};
PdsmOptions pdsmOptions(std::span<const ParameterValue> given);

// auto.
struct AutoOptions {
    std::string wedgeMethod; // the method's name: "wedges-blend", "wedges-bitmask", ...
    std::string alphaMethod; // the alpha path's: "sample-maps", "pcss" or "occlusion"
};
AutoOptions autoOptions(std::span<const ParameterValue> given);

} // namespace gpu

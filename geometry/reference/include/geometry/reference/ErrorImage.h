// False-colour |V - V_ref| heat maps (penumbra-render --compare, penumbra-bench --save-images).
//
// The image is the view itself, with a legend strip below it: a colour bar from 0 to `maxError`
// with ticks and labels at fifths of it (the 0.05 "bad pixel" threshold of DESIGN.md §5 is a tick
// of the default scale 0.2). Errors above maxError saturate at the last colour. Pixels with no
// surface in either image are grey, pixels with a surface in only one of them bright green.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace geometry {

struct RgbImage {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgb; // rows top to bottom
};

constexpr float kDefaultErrorScale = 0.2f;

// The colour of t in [0, 1] (clamped): black → violet → red → orange → pale yellow, brightness
// rising monotonically, so it reads in grey too.
void heatColour(float t, std::uint8_t out[3]);

// v and reference: width*height values, rows top to bottom, NaN where no surface. Throws
// std::invalid_argument on a size mismatch or maxError <= 0.
RgbImage errorHeatMap(std::span<const float> v, std::span<const float> reference, int width,
                      int height, float maxError = kDefaultErrorScale);

// The legend's height for an image `width` wide (the heat map is height + this tall).
int errorLegendHeight(int width);

} // namespace geometry

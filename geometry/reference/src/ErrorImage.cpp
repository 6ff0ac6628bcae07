// False-colour error images with a legend (ErrorImage.h). The labels use a 3×5 pixel font of the
// few glyphs a number needs, scaled by an integer factor with the image width.
#include <geometry/reference/ErrorImage.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace geometry {

namespace {

// Control points of the colour ramp, evenly spaced in t.
constexpr std::array<std::array<float, 3>, 5> kRamp{{
    {0.00f, 0.00f, 0.00f},
    {0.35f, 0.05f, 0.55f},
    {0.85f, 0.15f, 0.30f},
    {1.00f, 0.60f, 0.05f},
    {1.00f, 1.00f, 0.70f},
}};

// 3×5 glyphs, one row per 3 bits (bit 2 = left column), top row first.
struct Glyph {
    char c;
    std::array<std::uint8_t, 5> rows;
};
constexpr std::array<Glyph, 12> kFont{{
    {'0', {7, 5, 5, 5, 7}}, {'1', {2, 6, 2, 2, 7}}, {'2', {7, 1, 7, 4, 7}},
    {'3', {7, 1, 3, 1, 7}}, {'4', {5, 5, 7, 1, 1}}, {'5', {7, 4, 7, 1, 7}},
    {'6', {7, 4, 7, 5, 7}}, {'7', {7, 1, 1, 2, 2}}, {'8', {7, 5, 7, 5, 7}},
    {'9', {7, 5, 7, 1, 7}}, {'.', {0, 0, 0, 0, 2}}, {'>', {4, 2, 1, 2, 4}},
}};

constexpr std::uint8_t kNoSurface[3] = {96, 96, 96};
constexpr std::uint8_t kMismatch[3] = {0, 255, 0};
constexpr std::uint8_t kLegendBackground[3] = {255, 255, 255};
constexpr std::uint8_t kInk[3] = {0, 0, 0};

int fontScale(int width) { return std::max(1, width / 128); }

struct Canvas {
    RgbImage& image;
    void put(int x, int y, const std::uint8_t c[3]) {
        if (x < 0 || y < 0 || x >= image.width || y >= image.height) return;
        std::uint8_t* p = &image.rgb[(static_cast<std::size_t>(y) * image.width + x) * 3];
        p[0] = c[0];
        p[1] = c[1];
        p[2] = c[2];
    }
    // Text with its top-left corner at (x, y); returns the width drawn.
    int text(int x, int y, const std::string& s, int scale) {
        int cx = x;
        for (char ch : s) {
            const auto g = std::find_if(kFont.begin(), kFont.end(),
                                        [ch](const Glyph& f) { return f.c == ch; });
            if (g != kFont.end())
                for (int row = 0; row < 5; ++row)
                    for (int col = 0; col < 3; ++col)
                        if (g->rows[row] & (4 >> col))
                            for (int dy = 0; dy < scale; ++dy)
                                for (int dx = 0; dx < scale; ++dx)
                                    put(cx + col * scale + dx, y + row * scale + dy, kInk);
            cx += 4 * scale;
        }
        return cx - x - scale;
    }
};

std::string label(float value) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", static_cast<double>(value));
    return buf;
}

} // namespace

void heatColour(float t, std::uint8_t out[3]) {
    t = std::isfinite(t) ? std::clamp(t, 0.0f, 1.0f) : 1.0f;
    const float x = t * static_cast<float>(kRamp.size() - 1);
    const std::size_t i = std::min(static_cast<std::size_t>(x), kRamp.size() - 2);
    const float f = x - static_cast<float>(i);
    for (int c = 0; c < 3; ++c) {
        const float value = kRamp[i][c] + f * (kRamp[i + 1][c] - kRamp[i][c]);
        out[c] = static_cast<std::uint8_t>(std::lround(255.0f * value));
    }
}

int errorLegendHeight(int width) {
    const int s = fontScale(width);
    return 4 * s + 6 * s + 2 * s + 5 * s + 2 * s; // gap, bar, tick, labels, margin
}

RgbImage errorHeatMap(std::span<const float> v, std::span<const float> reference, int width,
                      int height, float maxError) {
    if (width < 1 || height < 1 ||
        v.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) ||
        reference.size() != v.size())
        throw std::invalid_argument("errorHeatMap: image sizes do not match " +
                                    std::to_string(width) + "x" + std::to_string(height));
    if (!(maxError > 0.0f) || !std::isfinite(maxError))
        throw std::invalid_argument("errorHeatMap: the scale must be positive");
    RgbImage image;
    image.width = width;
    image.height = height + errorLegendHeight(width);
    image.rgb.assign(static_cast<std::size_t>(image.width) * image.height * 3, 0);
    Canvas canvas{image};
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * width + x;
            const bool a = std::isfinite(v[i]), b = std::isfinite(reference[i]);
            if (a != b) {
                canvas.put(x, y, kMismatch);
            } else if (!a) {
                canvas.put(x, y, kNoSurface);
            } else {
                std::uint8_t c[3];
                heatColour(std::abs(v[i] - reference[i]) / maxError, c);
                canvas.put(x, y, c);
            }
        }

    // Legend: background, the bar across the width (inset by a margin), ticks and labels at
    // fifths of the scale; the last label reads ">" max: errors above it saturate.
    const int s = fontScale(width);
    for (int y = height; y < image.height; ++y)
        for (int x = 0; x < width; ++x) canvas.put(x, y, kLegendBackground);
    const int margin = std::min(2 * s, width / 8);
    const int barTop = height + 4 * s, barBottom = barTop + 6 * s;
    const int x0 = margin, x1 = std::max(margin + 1, width - 1 - margin);
    for (int x = x0; x <= x1; ++x) {
        std::uint8_t c[3];
        heatColour(static_cast<float>(x - x0) / static_cast<float>(x1 - x0), c);
        for (int y = barTop; y < barBottom; ++y) canvas.put(x, y, c);
    }
    const int labelTop = barBottom + 2 * s;
    int freeFrom = 0; // labels never overlap: one that would is left out
    for (int k = 0; k <= 5; ++k) {
        const int x = x0 + (x1 - x0) * k / 5;
        for (int y = barBottom; y < barBottom + 2 * s; ++y) canvas.put(x, y, kInk);
        std::string text = label(maxError * static_cast<float>(k) / 5);
        if (k == 5) text.insert(text.begin(), '>');
        const int w = static_cast<int>(text.size()) * 4 * s - s;
        const int left = std::clamp(x - w / 2, 0, std::max(0, width - w));
        if (left < freeFrom || left + w > width) continue;
        canvas.text(left, labelTop, text, s);
        freeFrom = left + w + 2 * s;
    }
    return image;
}

} // namespace geometry

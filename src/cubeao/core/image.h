// A single-channel float image: the AO images that `reference` and `render` write and `compare`
// reads (DESIGN.md §5). Values are AO, 1 = open, 0 = fully occluded; nothing here clamps them.
#pragma once

#include <cstddef>
#include <vector>

namespace cubeao {

// Row-major, row 0 at the top (the scanline order of EXR and PNG), pixels.size() == width * height.
struct Image {
    int width = 0, height = 0;
    std::vector<float> pixels;

    Image() = default;
    Image(int w, int h, float value = 0.0f)
        : width(w), height(h), pixels(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), value) {}

    std::size_t pixelCount() const { return pixels.size(); }
    bool empty() const { return pixels.empty(); }
    bool sameSize(const Image& o) const { return width == o.width && height == o.height; }

    float& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
    float at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

}  // namespace cubeao

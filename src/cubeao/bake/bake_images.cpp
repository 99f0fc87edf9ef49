// Probe images; the layouts are documented in bake_images.h.
#include "cubeao/bake/bake_images.h"

#include <algorithm>
#include <array>
#include <cstdio>

#include "cubeao/core/error.h"
#include "cubeao/metrics/image_io.h"

namespace cubeao {
namespace fs = std::filesystem;

namespace {

constexpr std::array<const char*, 3> kQuantities = {"ao", "confidence", "distance"};

// Colours of the cross PNGs (linear RGB, image_io.h): background texels and cells outside the cross.
constexpr std::array<float, 3> kEmptyTint = {0.05f, 0.10f, 0.40f};
constexpr std::array<float, 3> kOutside = {0.30f, 0.00f, 0.30f};

// Cell (column, row) of each face in the horizontal cross, cube.h face order.
constexpr int kCrossCell[cube::kFaces][2] = {{2, 1}, {0, 1}, {1, 0}, {1, 2}, {1, 1}, {3, 1}};

std::vector<float> distances(const CubeGBuffer& g) {
    std::vector<float> d(g.texels.size());
    std::transform(g.texels.begin(), g.texels.end(), d.begin(), [](const glm::vec4& t) { return t.w; });
    return d;
}

// Face `face` of `values` (texelIndex order) as a res × res image, framebuffer orientation.
Image faceImage(const std::vector<float>& values, int face, int res) {
    Image image(res, res);
    for (int y = 0; y < res; ++y)
        for (int x = 0; x < res; ++x) image.at(x, y) = values[cube::texelIndex(face, x, res - 1 - y, res)];
    return image;
}

Image stackedImage(const std::vector<float>& values, int res) {
    Image image(res, cube::kFaces * res);
    for (int face = 0; face < cube::kFaces; ++face) {
        const Image f = faceImage(values, face, res);
        std::copy(f.pixels.begin(), f.pixels.end(), image.pixels.begin() + std::ptrdiff_t(face) * res * res);
    }
    return image;
}

std::vector<float> unstacked(const Image& image, int res) {
    std::vector<float> values(std::size_t(cube::kFaces) * res * res);
    for (int face = 0; face < cube::kFaces; ++face)
        for (int y = 0; y < res; ++y)
            for (int x = 0; x < res; ++x)
                values[cube::texelIndex(face, x, res - 1 - y, res)] = image.at(x, face * res + y);
    return values;
}

// RGB cross of `grey` (one value in [0, 1] per texel), empty texels tinted.
std::vector<float> crossRgb(const CubeGBuffer& g, const std::vector<float>& grey) {
    const int res = g.res, width = 4 * res, height = 3 * res;
    std::vector<float> rgb(3 * std::size_t(width) * std::size_t(height));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const std::ptrdiff_t texel = crossTexelIndex(x, y, res);
            std::array<float, 3> c = kOutside;
            if (texel >= 0)
                c = CubeGBuffer::empty(g.texels[std::size_t(texel)]) ? kEmptyTint
                                                                     : std::array<float, 3>{grey[std::size_t(texel)],
                                                                                            grey[std::size_t(texel)],
                                                                                            grey[std::size_t(texel)]};
            std::copy(c.begin(), c.end(), rgb.begin() + 3 * (std::ptrdiff_t(y) * width + x));
        }
    return rgb;
}

void checkProbe(const BakedProbe& probe) {
    const std::size_t n = probe.gbuffer.texelCount();
    if (probe.gbuffer.res < 1 || probe.gbuffer.texels.size() != n || probe.ao.size() != n ||
        probe.confidence.size() != n)
        throw Error("probe images: inconsistent baked probe (res " + std::to_string(probe.gbuffer.res) + ", " +
                    std::to_string(probe.gbuffer.texels.size()) + " G-buffer texels, " +
                    std::to_string(probe.ao.size()) + " AO values, " + std::to_string(probe.confidence.size()) +
                    " confidence values; expected " + std::to_string(n) + " each)");
}

}  // namespace

std::string probeFileStem(std::uint32_t probeIndex) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "probe_%04u", unsigned(probeIndex));
    return buffer;
}

std::ptrdiff_t crossTexelIndex(int x, int y, int res) {
    if (x < 0 || y < 0 || x >= 4 * res || y >= 3 * res) return -1;
    const int column = x / res, row = y / res;
    for (int face = 0; face < cube::kFaces; ++face)
        if (kCrossCell[face][0] == column && kCrossCell[face][1] == row)
            return std::ptrdiff_t(cube::texelIndex(face, x % res, y % res, res));
    return -1;
}

void writeProbeImages(const fs::path& dir, std::uint32_t probeIndex, const BakedProbe& probe) {
    checkProbe(probe);
    const int res = probe.gbuffer.res;
    const std::string stem = probeFileStem(probeIndex);
    const std::array<std::vector<float>, 3> values = {probe.ao, probe.confidence, distances(probe.gbuffer)};
    for (std::size_t k = 0; k < kQuantities.size(); ++k)
        writeExr(dir / (stem + "_" + kQuantities[k] + ".exr"), stackedImage(values[k], res));
}

ProbeImages readProbeImages(const fs::path& dir, std::uint32_t probeIndex) {
    const std::string stem = probeFileStem(probeIndex);
    ProbeImages out;
    std::array<std::vector<float>*, 3> targets = {&out.ao, &out.confidence, &out.distance};
    for (std::size_t k = 0; k < kQuantities.size(); ++k) {
        const fs::path path = dir / (stem + "_" + kQuantities[k] + ".exr");
        const Image image = readImage(path);
        const int res = image.width;
        if (res < 1 || image.height != cube::kFaces * res)
            throw Error("probe image '" + path.string() + "': " + std::to_string(image.width) + "x" +
                        std::to_string(image.height) + ", expected res x 6*res (six faces stacked)");
        if (out.res != 0 && res != out.res)
            throw Error("probe image '" + path.string() + "': faces of " + std::to_string(res) + " texels, but " +
                        kQuantities[0] + " has " + std::to_string(out.res));
        out.res = res;
        *targets[k] = unstacked(image, res);
    }
    return out;
}

void dumpProbe(const fs::path& dir, std::uint32_t probeIndex, const BakedProbe& probe) {
    checkProbe(probe);
    const CubeGBuffer& g = probe.gbuffer;
    const int res = g.res;
    const std::string stem = probeFileStem(probeIndex);
    const std::vector<float> distance = distances(g);
    const std::array<const std::vector<float>*, 3> values = {&probe.ao, &probe.confidence, &distance};
    for (int face = 0; face < cube::kFaces; ++face)
        for (std::size_t k = 0; k < kQuantities.size(); ++k)
            writeExr(dir / (stem + "_face" + std::to_string(face) + "_" + kQuantities[k] + ".exr"),
                     faceImage(*values[k], face, res));

    writePngRgb(dir / (stem + "_cross.png"), 4 * res, 3 * res, crossRgb(g, probe.ao));
    const float farthest = distance.empty() ? 0.0f : *std::max_element(distance.begin(), distance.end());
    std::vector<float> normalised(distance.size(), 0.0f);
    if (farthest > 0.0f)
        std::transform(distance.begin(), distance.end(), normalised.begin(), [&](float d) { return d / farthest; });
    writePngRgb(dir / (stem + "_cross_distance.png"), 4 * res, 3 * res, crossRgb(g, normalised));
}

}  // namespace cubeao

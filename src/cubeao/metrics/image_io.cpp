// AO image files through OpenImageIO, loaded as a plugin (oiio_module.h); conventions are
// documented in image_io.h.
#include "cubeao/metrics/image_io.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "cubeao/core/durable_file.h"
#include "cubeao/core/error.h"
#include "cubeao/metrics/oiio_module.h"

namespace cubeao {
namespace fs = std::filesystem;

namespace {

// Built with += because g++ 12 -O2 gives a false -Wrestrict on "'" + std::string (GCC PR 105329).
std::string quoted(const fs::path& p) {
    std::string s(1, '\'');
    s += p.string();
    s += '\'';
    return s;
}

// Writes `pixels` (laid out as `spec` says) into a DurableFile's temporary file by name, then commits
// it over `path`. OpenImageIO chooses the format from `path`'s extension, not the temporary name's.
void writeAtomically(const fs::path& path, const oiio::WriteSpec& spec, const void* pixels) {
    const oiio::Api& io = oiio::api();
    DurableFile file(path, "image");
    const std::string why = io.write(path.c_str(), file.temporaryPath().c_str(), spec, pixels);
    if (!why.empty()) throw Error("cannot write " + quoted(path) + ": " + why);
    file.commit();
}

void checkSize(const fs::path& path, int width, int height) {
    if (width <= 0 || height <= 0)
        throw Error("cannot write " + quoted(path) + ": image is empty (" + std::to_string(width) + "x" +
                    std::to_string(height) + ")");
}

// Linear 8-bit quantisation (image_io.h explains why no sRGB curve). NaN maps to 0.
std::vector<std::uint8_t> toBytes(const std::vector<float>& values) {
    std::vector<std::uint8_t> bytes(values.size());
    std::transform(values.begin(), values.end(), bytes.begin(), [](float v) {
        const float c = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f);
        return static_cast<std::uint8_t>(std::lround(c * 255.0f));
    });
    return bytes;
}

}  // namespace

void writeExr(const fs::path& path, const Image& image) {
    checkSize(path, image.width, image.height);
    writeAtomically(path, {image.width, image.height, 1, oiio::Pixel::F32, true}, image.pixels.data());
}

Image readImage(const fs::path& path) {
    Image image;
    const std::string why = oiio::api().readFirstChannel(path.c_str(), &image.width, &image.height, &image.pixels);
    if (!why.empty())
        throw Error("cannot read image " + quoted(path) + ": " + why);
    return image;
}

void writePng(const fs::path& path, const Image& image) {
    checkSize(path, image.width, image.height);
    const auto bytes = toBytes(image.pixels);
    writeAtomically(path, {image.width, image.height, 1, oiio::Pixel::U8, false}, bytes.data());
}

void writePngRgb(const fs::path& path, int width, int height, const std::vector<float>& rgb) {
    checkSize(path, width, height);
    if (rgb.size() != 3 * static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
        throw Error("cannot write " + quoted(path) + ": " + std::to_string(rgb.size()) + " values for a " +
                    std::to_string(width) + "x" + std::to_string(height) + " RGB image");
    const auto bytes = toBytes(rgb);
    writeAtomically(path, {width, height, 3, oiio::Pixel::U8, false}, bytes.data());
}

std::vector<unsigned char> encodePng(int width, int height, int channels, const std::vector<float>& values) {
    if (width <= 0 || height <= 0 || (channels != 1 && channels != 3 && channels != 4) ||
        values.size() != static_cast<std::size_t>(channels) * static_cast<std::size_t>(width) * height)
        throw Error("cannot encode PNG: " + std::to_string(values.size()) + " values for a " + std::to_string(width) +
                    "x" + std::to_string(height) + "x" + std::to_string(channels) + " image");
    const auto bytes = toBytes(values);
    std::vector<unsigned char> png;
    const std::string why = oiio::api().encodePng(width, height, channels, bytes.data(), &png);
    if (!why.empty())
        throw Error("cannot encode PNG: " + why);
    return png;
}

Image hstack(const std::vector<Image>& images, int gap, float fill) {
    if (gap < 0)
        throw Error("hstack: negative gap " + std::to_string(gap));
    if (images.empty())
        return {};
    int width = gap * (static_cast<int>(images.size()) - 1), height = 0;
    for (const Image& im : images) {
        width += im.width;
        height = std::max(height, im.height);
    }
    Image out(width, height, fill);
    int x0 = 0;
    for (const Image& im : images) {
        for (int y = 0; y < im.height; ++y)
            std::copy_n(im.pixels.data() + static_cast<std::size_t>(y) * im.width, im.width,
                        out.pixels.data() + static_cast<std::size_t>(y) * width + x0);
        x0 += im.width + gap;
    }
    return out;
}

}  // namespace cubeao

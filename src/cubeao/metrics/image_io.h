// Reading and writing AO images through OpenImageIO, which is loaded as a plugin on the first call
// (oiio_module.h: not linked, so programs start fast). Every error is a cubeao::Error that names the file.
//
// File conventions (DESIGN.md §5):
//  - EXR: one FLOAT channel named "Y" (OpenEXR's name for a luminance-only image, so viewers show
//    it as grey), ZIP compression (lossless: a write/read round trip is bit exact).
//  - PNG previews are *linear*: byte = round(255 * clamp(ao, 0, 1)), no sRGB curve. AO is a
//    visibility fraction, not a colour, and engines store AO maps linearly too; a linear preview
//    also lets anyone read the AO value back from a pixel (to 1/255).
// Writes go through a DurableFile (core/durable_file.h): a reader never sees a half-written image,
// and a failed write leaves the target as it was. The directory must exist.
#pragma once

#include <filesystem>
#include <vector>

#include "cubeao/core/image.h"

namespace cubeao {

// Single-channel FLOAT EXR, channel "Y".
void writeExr(const std::filesystem::path& path, const Image& image);

// Reads the first channel of the first subimage (any format OIIO reads; EXR in practice), as
// float. An 8-bit file comes back in 0..1.
Image readImage(const std::filesystem::path& path);

// 8-bit grayscale PNG preview, linear (see above).
void writePng(const std::filesystem::path& path, const Image& image);

// 8-bit RGB PNG, linear, rgb interleaved (size 3 * width * height), for colour previews such as
// difference maps and side-by-sides.
void writePngRgb(const std::filesystem::path& path, int width, int height, const std::vector<float>& rgb);

// 8-bit PNG encoded in memory (for pages that embed images as data: URIs, `cubeao report`), linear
// like writePng; `channels` 1 (grey), 3 (RGB) or 4 (RGBA), interleaved, values in 0..1.
std::vector<unsigned char> encodePng(int width, int height, int channels, const std::vector<float>& values);

// Side-by-side montage for reports: images left to right, `gap` pixels apart, top-aligned; the
// height is the tallest image's; gaps and the space below shorter images hold `fill` (1 = white).
// An empty list gives an empty image; a negative gap throws cubeao::Error.
Image hstack(const std::vector<Image>& images, int gap, float fill = 1.0f);

}  // namespace cubeao

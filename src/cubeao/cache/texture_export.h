// Probe cube maps as files other programs read (issue 17, `cubeao export`): DDS with the DX10 header
// (Direct3D, DirectXTex, most engines) and KTX 2.0 (Vulkan, the Khronos tools), one mip level, no
// supercompression. Part of cubeao_cache: bytes in, bytes out; no image library.
//
// Orientation: no flip, no reorder. GL (4.5 §8.13.1, table 8.19), Direct3D (D3D11 functional spec,
// "TextureCube" face selection) and Vulkan (1.3 §16.5.4, the same table) pick the face and the
// face coordinates (s, t) ∈ [0, 1]² of a direction with the same formulas, and all three address
// texel (⌊s·w⌋, ⌊t·h⌋) where t = 0 is the first row in memory (GL calls it the bottom, D3D the top;
// it is the same byte). Our caches store face f in exactly the bytes glCompressedTexSubImage takes
// for that face (cache/bc4.h "Cube layout", common/cube.h), faces +X −X +Y −Y +Z −Z, which is also
// the face order of DDS and KTX2. So the cache's blocks are the file's payload as they are
// (tests/cli/test_export.cpp samples the exported files with D3D's face table to check it).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "cubeao/cache/cache_file.h"

namespace cubeao::texport {

// Texel formats an exported cube map can have.
enum class TexelFormat : std::uint8_t {
    Bc4Unorm,  // AO only: the red BC4 block of each cached BC5 block
    Bc5Unorm,  // AO (red) + confidence (green), the cached blocks as they are
    R16Unorm,
    R16Float,
    R32Float,
};

struct FormatCodes {
    const char* name;         // "bc5_unorm", ...
    std::uint32_t dxgi;       // DXGI_FORMAT_*: BC4_UNORM 80, BC5_UNORM 83, R16_UNORM 56, R16_FLOAT 54, R32_FLOAT 41
    std::uint32_t vk;         // VkFormat: BC4_UNORM_BLOCK 139, BC5_UNORM_BLOCK 141, R16_UNORM 70, R16_SFLOAT 76,
                              // R32_SFLOAT 100
    std::uint32_t blockSide;  // texels per block side: 4 for BC, 1 otherwise
    std::uint32_t blockBytes; // bytes per block (per texel for the uncompressed formats)
};
const FormatCodes& formatCodes(TexelFormat f);

// The cube map format a cache's distance section already has (no conversion).
TexelFormat texelFormatOf(DepthFormat f);

// Bytes of one res × res face / of the six faces. Throws std::invalid_argument for a BC format whose
// res is not a positive multiple of 4, or a res of 0.
std::size_t faceBytes(TexelFormat f, std::uint32_t res);
std::size_t cubeBytes(TexelFormat f, std::uint32_t res);

// A cache's distance section as R32_FLOAT world units (depth::decodeTexel of every texel; 0 stays 0,
// "nothing there"). Throws std::invalid_argument when the size does not match depthRes and format.
std::vector<std::uint8_t> distancesAsFloat(std::span<const std::uint8_t> section, std::uint32_t depthRes,
                                           DepthFormat format, float maxDistance);

// A complete file holding one cube map of six res × res faces, one mip level: `faces` is
// cubeBytes(format, res) bytes, the faces in order +X −X +Y −Y +Z −Z, each in memory order (the
// layout above). Throws std::invalid_argument for a size mismatch.
//
// DDS: "DDS ", the 124-byte header (DDSD_CAPS|HEIGHT|WIDTH|PIXELFORMAT|MIPMAPCOUNT and LINEARSIZE
// or PITCH, mipMapCount 1, DDSCAPS_TEXTURE|COMPLEX, DDSCAPS2_CUBEMAP and all six faces), the pixel
// format FOURCC "DX10", the DX10 header (dxgiFormat, TEXTURE2D, miscFlag TEXTURECUBE, arraySize 1,
// alpha mode unknown), then the faces.
std::vector<std::uint8_t> ddsFile(TexelFormat format, std::uint32_t res, std::span<const std::uint8_t> faces);

// KTX 2.0 (KTX File Format Specification 2.0): identifier, header (vkFormat, typeSize, res × res,
// depth 0, layers 0, faceCount 6, levelCount 1, no supercompression), index, the level index, a
// Basic Data Format Descriptor (Khronos Data Format 1.3: BC4/BC5 colour models 131/132, RGBSDA for
// the others; linear transfer, BT.709 primaries), a KTXwriter key/value entry, then the faces, tightly
// packed (KTX2 has no cube or row padding) at an offset aligned to lcm(block bytes, 4).
std::vector<std::uint8_t> ktx2File(TexelFormat format, std::uint32_t res, std::span<const std::uint8_t> faces,
                                   const std::string& writer);

}  // namespace cubeao::texport

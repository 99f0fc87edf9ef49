#include "cubeao/cache/texture_export.h"

#include <cstring>
#include <stdexcept>

#include "cubeao/cache/depth_cube.h"

namespace cubeao::texport {
namespace {

// Every field is written explicitly, little-endian, as the cache file does: no struct dumps.
class Bytes {
public:
    void u8(std::uint8_t v) { b_.push_back(v); }
    void u16(std::uint16_t v) { u8(std::uint8_t(v)), u8(std::uint8_t(v >> 8)); }
    void u32(std::uint32_t v) { u16(std::uint16_t(v)), u16(std::uint16_t(v >> 16)); }
    void u64(std::uint64_t v) { u32(std::uint32_t(v)), u32(std::uint32_t(v >> 32)); }
    // resize + memcpy rather than insert: g++ 12 warns (-Wstringop-overflow, a false positive) on an
    // insert into the empty vector.
    void raw(const void* p, std::size_t n) {
        const std::size_t at = b_.size();
        b_.resize(at + n);
        if (n > 0) std::memcpy(&b_[at], p, n);
    }
    void zeros(std::size_t n) { b_.resize(b_.size() + n, 0); }
    void alignTo(std::size_t a) { zeros((a - b_.size() % a) % a); }
    std::size_t size() const { return b_.size(); }
    void put32(std::size_t at, std::uint32_t v) {  // fill in a field written before its value was known
        for (int k = 0; k < 4; ++k) b_[at + k] = std::uint8_t(v >> (8 * k));
    }
    void put64(std::size_t at, std::uint64_t v) { put32(at, std::uint32_t(v)), put32(at + 4, std::uint32_t(v >> 32)); }
    std::vector<std::uint8_t> take() { return std::move(b_); }

private:
    std::vector<std::uint8_t> b_;
};

void checkFaces(TexelFormat format, std::uint32_t res, std::span<const std::uint8_t> faces) {
    if (faces.size() != cubeBytes(format, res))
        throw std::invalid_argument(std::string("cube map of ") + formatCodes(format).name + " at " +
                                    std::to_string(res) + "²: expected " + std::to_string(cubeBytes(format, res)) +
                                    " bytes, got " + std::to_string(faces.size()));
}

bool isBlockCompressed(TexelFormat f) { return formatCodes(f).blockSide > 1; }

}  // namespace

const FormatCodes& formatCodes(TexelFormat f) {
    static constexpr FormatCodes kCodes[] = {
        {"bc4_unorm", 80, 139, 4, 8}, {"bc5_unorm", 83, 141, 4, 16}, {"r16_unorm", 56, 70, 1, 2},
        {"r16_float", 54, 76, 1, 2},  {"r32_float", 41, 100, 1, 4},
    };
    const auto i = std::size_t(f);
    if (i >= std::size(kCodes)) throw std::invalid_argument("unknown texel format " + std::to_string(i));
    return kCodes[i];
}

TexelFormat texelFormatOf(DepthFormat f) {
    switch (f) {
        case DepthFormat::R16Unorm: return TexelFormat::R16Unorm;
        case DepthFormat::R16Float: return TexelFormat::R16Float;
        case DepthFormat::R32Float: return TexelFormat::R32Float;
    }
    throw std::invalid_argument("unknown depth format " + std::to_string(int(f)));
}

std::size_t faceBytes(TexelFormat f, std::uint32_t res) {
    const FormatCodes& c = formatCodes(f);
    if (res == 0 || res % c.blockSide != 0 || res > 65536)
        throw std::invalid_argument(std::string(c.name) + " face of " + std::to_string(res) + "² texels: expected a " +
                                    (c.blockSide > 1 ? "multiple of 4" : "size") + " in 1..65536");
    const std::size_t blocks = res / c.blockSide;
    return blocks * blocks * c.blockBytes;
}

std::size_t cubeBytes(TexelFormat f, std::uint32_t res) { return 6 * faceBytes(f, res); }

std::vector<std::uint8_t> distancesAsFloat(std::span<const std::uint8_t> section, std::uint32_t depthRes,
                                           DepthFormat format, float maxDistance) {
    std::vector<float> d;
    if (!depth::decode(section, int(depthRes), format, maxDistance, d))
        throw std::invalid_argument("distance cube of " + std::to_string(section.size()) + " bytes does not match " +
                                    std::to_string(depthRes) + "² " + depthFormatName(format));
    Bytes out;
    for (float v : d) {
        std::uint32_t bits;
        std::memcpy(&bits, &v, 4);
        out.u32(bits);
    }
    return out.take();
}

std::vector<std::uint8_t> ddsFile(TexelFormat format, std::uint32_t res, std::span<const std::uint8_t> faces) {
    checkFaces(format, res, faces);
    const FormatCodes& c = formatCodes(format);
    // Flags and values as DirectXTex's DDS.h names them.
    constexpr std::uint32_t kCaps = 0x1, kHeight = 0x2, kWidth = 0x4, kPitch = 0x8, kPixelFormat = 0x1000,
                            kMipMapCount = 0x20000, kLinearSize = 0x80000;
    constexpr std::uint32_t kFourCC = 0x4, kCapsComplex = 0x8, kCapsTexture = 0x1000;
    constexpr std::uint32_t kCubeMapAllFaces = 0x200 | 0x400 | 0x800 | 0x1000 | 0x2000 | 0x4000 | 0x8000;
    constexpr std::uint32_t kDimensionTexture2D = 3, kMiscTextureCube = 0x4;
    const bool bc = isBlockCompressed(format);
    Bytes b;
    b.raw("DDS ", 4);
    b.u32(124);
    b.u32(kCaps | kHeight | kWidth | kPixelFormat | kMipMapCount | (bc ? kLinearSize : kPitch));
    b.u32(res);  // height
    b.u32(res);  // width
    // Compressed: bytes of the top level of one face; uncompressed: bytes of one row.
    b.u32(std::uint32_t(bc ? faceBytes(format, res) : std::size_t(res) * c.blockBytes));
    b.u32(0);  // depth
    b.u32(1);  // mipMapCount
    b.zeros(4 * 11);
    // DDS_PIXELFORMAT: the DX10 header says the rest.
    b.u32(32);
    b.u32(kFourCC);
    b.raw("DX10", 4);
    b.zeros(4 * 5);  // RGBBitCount, masks
    b.u32(kCapsTexture | kCapsComplex);
    b.u32(kCubeMapAllFaces);
    b.zeros(4 * 3);  // caps3, caps4, reserved2
    // DDS_HEADER_DXT10
    b.u32(c.dxgi);
    b.u32(kDimensionTexture2D);
    b.u32(kMiscTextureCube);
    b.u32(1);  // arraySize: cubes, not faces
    b.u32(0);  // miscFlags2: alpha mode unknown (there is no alpha)
    b.raw(faces.data(), faces.size());
    return b.take();
}

std::vector<std::uint8_t> ktx2File(TexelFormat format, std::uint32_t res, std::span<const std::uint8_t> faces,
                                   const std::string& writer) {
    checkFaces(format, res, faces);
    const FormatCodes& c = formatCodes(format);
    const bool bc = isBlockCompressed(format);
    static constexpr std::uint8_t kIdentifier[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n'};
    Bytes b;
    b.raw(kIdentifier, sizeof kIdentifier);
    b.u32(c.vk);
    b.u32(bc ? 1 : c.blockBytes);  // typeSize: 1 for block-compressed formats, else the component size
    b.u32(res);                    // pixelWidth
    b.u32(res);                    // pixelHeight
    b.u32(0);                      // pixelDepth: not a 3D texture
    b.u32(0);                      // layerCount: not an array
    b.u32(6);                      // faceCount
    b.u32(1);                      // levelCount
    b.u32(0);                      // supercompressionScheme: none
    const std::size_t indexAt = b.size();  // dfd offset/length, kvd offset/length, sgd offset/length
    b.zeros(4 * 4 + 8 * 2);
    const std::size_t levelIndexAt = b.size();
    b.zeros(3 * 8);

    // Data Format Descriptor: dfdTotalSize, then one Basic descriptor block.
    const std::size_t dfdAt = b.size();
    const std::uint32_t samples = format == TexelFormat::Bc5Unorm ? 2 : 1;
    const std::uint32_t blockSize = 24 + 16 * samples;
    b.u32(4 + blockSize);
    b.u32(0);  // vendorId 0 (Khronos), descriptorType 0 (basic)
    b.u16(2);  // versionNumber: Data Format 1.3
    b.u16(std::uint16_t(blockSize));
    constexpr std::uint8_t kModelRgbsda = 1, kModelBc4 = 131, kModelBc5 = 132, kPrimariesBt709 = 1, kTransferLinear = 1;
    b.u8(format == TexelFormat::Bc4Unorm ? kModelBc4 : format == TexelFormat::Bc5Unorm ? kModelBc5 : kModelRgbsda);
    b.u8(kPrimariesBt709);
    b.u8(kTransferLinear);
    b.u8(0);  // flags: alpha straight (there is none)
    const std::uint8_t dim = std::uint8_t(c.blockSide - 1);
    b.u8(dim), b.u8(dim), b.u8(0), b.u8(0);  // texelBlockDimension0..3, each minus 1
    b.u8(std::uint8_t(c.blockBytes));        // bytesPlane0
    b.zeros(7);                              // bytesPlane1..7
    // Samples: bitOffset, bitLength − 1, channelType (channel id | qualifiers), position, lower, upper.
    constexpr std::uint8_t kFloat = 0x80, kSigned = 0x40;
    const auto sample = [&](std::uint16_t bitOffset, std::uint8_t bits, std::uint8_t channel, std::uint32_t lower,
                            std::uint32_t upper) {
        b.u16(bitOffset);
        b.u8(std::uint8_t(bits - 1));
        b.u8(channel);
        b.zeros(4);  // samplePosition0..3: the block's origin
        b.u32(lower);
        b.u32(upper);
    };
    switch (format) {
        case TexelFormat::Bc4Unorm: sample(0, 64, 0, 0, 0xFFFFFFFFu); break;  // KHR_DF_CHANNEL_BC4_DATA
        case TexelFormat::Bc5Unorm:
            sample(0, 64, 0, 0, 0xFFFFFFFFu);   // KHR_DF_CHANNEL_BC5_RED
            sample(64, 64, 1, 0, 0xFFFFFFFFu);  // KHR_DF_CHANNEL_BC5_GREEN
            break;
        case TexelFormat::R16Unorm: sample(0, 16, 0, 0, 65535); break;  // KHR_DF_CHANNEL_RGBSDA_RED
        // Float samples: lower/upper are the float bits of −1 and 1 (the Data Format spec's convention).
        case TexelFormat::R16Float: sample(0, 16, kFloat | kSigned, 0xBF800000u, 0x3F800000u); break;
        case TexelFormat::R32Float: sample(0, 32, kFloat | kSigned, 0xBF800000u, 0x3F800000u); break;
    }
    const std::size_t dfdLength = b.size() - dfdAt;

    // Key/value data: KTXwriter, recommended by the spec so a file can be traced to what wrote it.
    b.alignTo(4);
    const std::size_t kvdAt = b.size();
    const std::string key = "KTXwriter";
    b.u32(std::uint32_t(key.size() + 1 + writer.size() + 1));
    b.raw(key.c_str(), key.size() + 1);
    b.raw(writer.c_str(), writer.size() + 1);
    b.alignTo(4);
    const std::size_t kvdLength = b.size() - kvdAt;

    // Level 0: lcm(texel block size, 4) alignment; block sizes here are 2, 4, 8 or 16.
    b.alignTo(c.blockBytes < 4 ? 4 : c.blockBytes);
    const std::size_t levelAt = b.size();
    b.raw(faces.data(), faces.size());

    b.put32(indexAt, std::uint32_t(dfdAt));
    b.put32(indexAt + 4, std::uint32_t(dfdLength));
    b.put32(indexAt + 8, std::uint32_t(kvdAt));
    b.put32(indexAt + 12, std::uint32_t(kvdLength));
    // sgd offset and length stay 0: no supercompression global data.
    b.put64(levelIndexAt, levelAt);
    b.put64(levelIndexAt + 8, faces.size());
    b.put64(levelIndexAt + 16, faces.size());  // uncompressedByteLength: = byteLength without supercompression
    return b.take();
}

}  // namespace cubeao::texport

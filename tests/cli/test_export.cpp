// `cubeao export` (issue 17): probe cube maps as DDS and KTX2 files, read back by something other than
// our writer. DDS BC4/BC5 files go through OpenImageIO (2.4.7 here: it reads DX10 BC4/BC5 cube maps
// as one image of the six faces stacked vertically, +X at the top, each face's first memory row
// first, decoded to uint8); OpenImageIO 2.4 refuses uncompressed DX10 formats ("Unsupported
// compression type") and reads 16-bit legacy DDS at 8 bits, so the distance files and every KTX2 file
// are checked by parsing their headers here, field by field at the offsets the specs give, and
// comparing their payload bytes with the cache's.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <nlohmann/json.hpp>

#include "cli_run.h"
#include "cubeao/cache/bc4.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/cache/depth_cube.h"
#include "cubeao/core/cube.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;
using cubeao::CacheReader;
using cubeao::test::CliRun;
using cubeao::test::contains;
using cubeao::test::lastLine;
using cubeao::test::TempDir;

CliRun run(const std::string& args, bool withStderr = false) { return cubeao::test::runCli(args, withStderr); }

std::vector<std::uint8_t> fileBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}
std::uint32_t u32(const std::vector<std::uint8_t>& b, std::size_t at) {
    return std::uint32_t(b.at(at)) | std::uint32_t(b.at(at + 1)) << 8 | std::uint32_t(b.at(at + 2)) << 16 |
           std::uint32_t(b.at(at + 3)) << 24;
}
std::uint64_t u64(const std::vector<std::uint8_t>& b, std::size_t at) {
    return std::uint64_t(u32(b, at)) | std::uint64_t(u32(b, at + 4)) << 32;
}
std::vector<std::uint8_t> slice(const std::vector<std::uint8_t>& b, std::size_t at, std::size_t n) {
    if (at + n > b.size()) return {};
    return {b.begin() + std::ptrdiff_t(at), b.begin() + std::ptrdiff_t(at + n)};
}
std::vector<std::uint8_t> bytesOf(std::span<const std::uint8_t> s) { return {s.begin(), s.end()}; }
std::vector<std::uint8_t> redBlocks(std::span<const std::uint8_t> bc5) {
    std::vector<std::uint8_t> out;
    for (std::size_t b = 0; b < bc5.size(); b += 16) out.insert(out.end(), bc5.begin() + b, bc5.begin() + b + 8);
    return out;
}
nlohmann::json readJson(const fs::path& p) {
    std::ifstream in(p);
    return nlohmann::json::parse(in);
}
bool stagingLeft(const fs::path& dir) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (contains(e.path().filename().string(), ".tmp-")) return true;
    return false;
}

// A DDS file as DirectXTex's DDS.h lays it out: "DDS ", DDS_HEADER (124 bytes), DDS_HEADER_DXT10 at
// 128; checks a one-level cube map of dxgi format `dxgi` and res × res faces; returns its payload.
std::vector<std::uint8_t> ddsCubePayload(const fs::path& p, std::uint32_t dxgi, std::uint32_t res) {
    const std::vector<std::uint8_t> b = fileBytes(p);
    EXPECT_GE(b.size(), 148u) << p;
    if (b.size() < 148) return {};
    EXPECT_EQ(std::string(b.begin(), b.begin() + 4), "DDS ");
    EXPECT_EQ(u32(b, 4), 124u);                            // dwSize
    EXPECT_EQ(u32(b, 8) & 0x1007u, 0x1007u);               // CAPS | HEIGHT | WIDTH | PIXELFORMAT
    EXPECT_EQ(u32(b, 12), res);                            // height
    EXPECT_EQ(u32(b, 16), res);                            // width
    EXPECT_EQ(u32(b, 28), 1u);                             // mipMapCount
    EXPECT_EQ(u32(b, 76), 32u);                            // ddspf.dwSize
    EXPECT_EQ(u32(b, 80) & 0x4u, 0x4u);                    // DDPF_FOURCC
    EXPECT_EQ(std::string(b.begin() + 84, b.begin() + 88), "DX10");
    EXPECT_EQ(u32(b, 108) & 0x1008u, 0x1008u);             // DDSCAPS_TEXTURE | DDSCAPS_COMPLEX
    EXPECT_EQ(u32(b, 112), 0xFE00u);                       // DDSCAPS2_CUBEMAP and all six faces
    EXPECT_EQ(u32(b, 128), dxgi);                          // dxgiFormat
    EXPECT_EQ(u32(b, 132), 3u);                            // D3D10_RESOURCE_DIMENSION_TEXTURE2D
    EXPECT_EQ(u32(b, 136), 0x4u);                          // DDS_RESOURCE_MISC_TEXTURECUBE
    EXPECT_EQ(u32(b, 140), 1u);                            // arraySize: one cube
    return slice(b, 148, b.size() - 148);
}

// The D3D11 functional spec's TextureCube face selection, written out on its own (not from
// common/cube.h): face, and (u, v) ∈ [0, 1]² with v = 0 the first row of the face in memory.
struct D3dTexel {
    int face;
    float u, v;
};
D3dTexel d3dCubeLookup(const glm::vec3& d) {
    const glm::vec3 a = glm::abs(d);
    float sc, tc, ma;
    int face;
    if (a.x >= a.y && a.x >= a.z) {
        face = d.x > 0 ? 0 : 1, ma = a.x, sc = d.x > 0 ? -d.z : d.z, tc = -d.y;
    } else if (a.y >= a.z) {
        face = d.y > 0 ? 2 : 3, ma = a.y, sc = d.x, tc = d.y > 0 ? d.z : -d.z;
    } else {
        face = d.z > 0 ? 4 : 5, ma = a.z, sc = d.z > 0 ? d.x : -d.x, tc = -d.y;
    }
    return {face, 0.5f * (sc / ma + 1.0f), 0.5f * (tc / ma + 1.0f)};
}

// The byte OpenImageIO 2.4 gives for a BC4 texel our decoder (cache/bc4.h) decodes to `v`. Our decoder
// returns the exact palette value q = num / d bytes (as the nearest float; d = 7 in the 8-level mode,
// 5 in the 6-level one); OpenImageIO decodes with bcdec, whose palette is (num + 1) / d in integers,
// i.e. floor(q + 1/d): q rounded, except that 1/7..3/7 and 1/5..2/5 past a byte round down. Exact
// emulation, so the comparison below stays exact per texel.
int bcdecByte(float v) {
    const double q = double(v) * 255.0;
    for (const int d : {7, 5}) {
        const double num = std::round(q * d);
        if (std::abs(num - q * d) < 1e-3) return int((std::int64_t(num) + 1) / d);
    }
    return -1;  // not a BC4 palette value: never matches
}

// One OpenImageIO read of an exported BC cube map: the stacked faces as uint8.
struct OiioCube {
    int width = 0, height = 0, channels = 0;
    std::string compression, textureFormat, sides;
    std::vector<std::uint8_t> pixels;
};
OiioCube readWithOiio(const fs::path& p) {
    OiioCube c;
    auto in = OIIO::ImageInput::open(p.string());
    EXPECT_TRUE(in) << p << ": " << OIIO::geterror();
    if (!in) return c;
    const OIIO::ImageSpec& spec = in->spec();
    c.width = spec.width, c.height = spec.height, c.channels = spec.nchannels;
    c.compression = spec.get_string_attribute("compression");
    c.textureFormat = spec.get_string_attribute("textureformat");
    c.sides = spec.get_string_attribute("dds:CubeMapSides");
    c.pixels.resize(std::size_t(c.width) * c.height * c.channels);
    EXPECT_TRUE(in->read_image(0, 0, 0, c.channels, OIIO::TypeDesc::UINT8, c.pixels.data())) << in->geterror();
    return c;
}

// A small real bake, shared by the tests of this file (about 1 s on the CPU).
class ExportTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new TempDir("export");
        const std::string probes = dir_->write(
            "probes.json", R"({"version":1,"probes":[{"pos":[3,1.4,2.5]},{"pos":[6,1.5,1.5]},{"pos":[1.5,1.2,4]}]})");
        cache_ = (dir_->path() / "box.cubeao").string();
        // BC5 (a traced bake's default is BC4): the export of both channels is what most tests read.
        const CliRun b = run("bake builtin:box-room --probes " + probes + " --out " + cache_ +
                             " --res 32 --spp 4 --device cpu --ao bc5", true);
        ASSERT_EQ(b.code, 0) << b.out;
    }
    static void TearDownTestSuite() {
        delete dir_;
        dir_ = nullptr;
    }
    static TempDir* dir_;
    static std::string cache_;
};
TempDir* ExportTest::dir_ = nullptr;
std::string ExportTest::cache_;

TEST_F(ExportTest, DdsReadsBackThroughOpenImageIo) {
    ASSERT_FALSE(HasFatalFailure());
    const fs::path out = dir_->path() / "dds";
    const CliRun r = run("export " + cache_ + " --format dds --out " + out.string() + " --json", true);
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = lastLine(r.out);
    EXPECT_EQ(j["probes"].get<int>(), 3);
    EXPECT_EQ(j["ao_format"], "bc5_unorm");
    EXPECT_EQ(j["distance_format"], "r16_unorm");
    EXPECT_FALSE(stagingLeft(out));

    const CacheReader cache(cache_);
    const int res = int(cache.params().res), depthRes = int(cache.params().depthRes);
    ASSERT_EQ(res, 32);
    ASSERT_EQ(depthRes, 8);
    const nlohmann::json m = readJson(out / "manifest.json");
    EXPECT_EQ(m["container"], "dds");
    EXPECT_EQ(m["ao"]["dxgi_format"].get<int>(), 83);
    EXPECT_EQ(m["distance"]["dxgi_format"].get<int>(), 56);
    EXPECT_EQ(m["distance"]["units"], "max_distance");
    EXPECT_EQ(m["bake"]["estimator"], "traced");
    EXPECT_EQ(m["source"]["scene_hash"], lastLine(run("info " + cache_ + " --json").out)["scene_hash"]);
    ASSERT_EQ(m["probes"].size(), cache.probeCount());

    std::mt19937 rng(7);
    std::normal_distribution<float> gauss;
    for (std::size_t i = 0; i < cache.probeCount(); ++i) {
        SCOPED_TRACE("probe " + std::to_string(i));
        const cubeao::ProbeView v = cache.probe(i);
        const nlohmann::json& mp = m["probes"][i];
        EXPECT_EQ(mp["id"].get<std::uint32_t>(), v.index);
        EXPECT_EQ(mp["position"][0].get<double>(), double(v.position.x));  // origin 0: file = local
        EXPECT_EQ(mp["max_distance"].get<float>(), v.maxDistance);

        // AO + confidence: OpenImageIO's decode of the file against ours of the cache, every texel.
        std::vector<glm::vec2> decoded;
        ASSERT_TRUE(cubeao::bc::decodeBc5Cube(v.aoConfidence.data(), v.aoConfidence.size(), res, decoded));
        const OiioCube ao = readWithOiio(out / mp["ao"].get<std::string>());
        ASSERT_EQ(ao.width, res);
        ASSERT_EQ(ao.height, 6 * res);
        ASSERT_EQ(ao.channels, 2);
        EXPECT_EQ(ao.compression, "BC5");
        EXPECT_EQ(ao.textureFormat, "CubeFace Environment");
        EXPECT_EQ(ao.sides, "+x -x +y -y +z -z");
        std::size_t mismatches = 0;
        for (int f = 0; f < 6; ++f)
            for (int jj = 0; jj < res; ++jj)
                for (int ii = 0; ii < res; ++ii) {
                    const glm::vec2 e = decoded[cubeao::cube::texelIndex(f, ii, jj, res)];
                    const std::uint8_t* px = &ao.pixels[2 * (std::size_t(f * res + jj) * res + ii)];
                    mismatches += px[0] != bcdecByte(e.x) || px[1] != bcdecByte(e.y);
                }
        EXPECT_EQ(mismatches, 0u);

        // Orientation: what a D3D (= GL) sampler fetches for a direction is the texel our shaders use.
        std::size_t wrong = 0, tried = 0;
        for (int k = 0; k < 2000; ++k) {
            const glm::vec3 d(gauss(rng), gauss(rng), gauss(rng));
            const D3dTexel t = d3dCubeLookup(d);
            const float x = t.u * res, y = t.v * res;
            if (std::abs(x - std::round(x)) < 1e-3f || std::abs(y - std::round(y)) < 1e-3f) continue;  // on a border
            ++tried;
            const int xi = std::min(res - 1, int(x)), yi = std::min(res - 1, int(y));
            const std::uint8_t* px = &ao.pixels[2 * (std::size_t(t.face * res + yi) * res + xi)];
            const glm::vec2 e = decoded[cubeao::cube::texelIndex(d, res)];
            wrong += px[0] != bcdecByte(e.x) || px[1] != bcdecByte(e.y);
        }
        EXPECT_GT(tried, 1900u);
        EXPECT_EQ(wrong, 0u);

        // Distance: the R16_UNORM texels exactly as cached.
        EXPECT_EQ(ddsCubePayload(out / mp["distance"].get<std::string>(), 56, std::uint32_t(depthRes)),
                  bytesOf(v.depth));
        EXPECT_EQ(ddsCubePayload(out / mp["ao"].get<std::string>(), 83, std::uint32_t(res)), bytesOf(v.aoConfidence));
    }

    // --ao bc4: one channel, AO only, the red half of every block; into the same directory (replaces).
    const CliRun r4 = run("export " + cache_ + " --out " + out.string() + " --ao bc4", true);
    ASSERT_EQ(r4.code, 0) << r4.out;
    EXPECT_EQ(readJson(out / "manifest.json")["ao"]["format"], "bc4_unorm");
    const cubeao::ProbeView v = cache.probe(1);
    const fs::path bc4File = out / m["probes"][1]["ao"].get<std::string>();
    EXPECT_EQ(ddsCubePayload(bc4File, 80, std::uint32_t(res)), redBlocks(v.aoConfidence));
    const OiioCube ao4 = readWithOiio(bc4File);
    ASSERT_EQ(ao4.channels, 1);
    EXPECT_EQ(ao4.compression, "BC4");
    std::vector<glm::vec2> decoded;
    ASSERT_TRUE(cubeao::bc::decodeBc5Cube(v.aoConfidence.data(), v.aoConfidence.size(), res, decoded));
    std::size_t mismatches = 0;
    for (int f = 0; f < 6; ++f)
        for (int jj = 0; jj < res; ++jj)
            for (int ii = 0; ii < res; ++ii)
                mismatches += ao4.pixels[std::size_t(f * res + jj) * res + ii] !=
                              bcdecByte(decoded[cubeao::cube::texelIndex(f, ii, jj, res)].x);
    EXPECT_EQ(mismatches, 0u);
}

// A BC4 cache (the traced default) exports BC4 by default: the very files `--ao bc4` writes from
// its BC5 twin; `--ao bc5` gives back the BC5 blocks with confidence 1.
TEST_F(ExportTest, ABc4CacheExportsBc4ByDefault) {
    ASSERT_FALSE(HasFatalFailure());
    const std::string bc4 = (dir_->path() / "box4.cubeao").string();
    ASSERT_EQ(run("merge " + bc4 + " " + cache_ + " --ao bc4").code, 0);
    const fs::path fromBc4 = dir_->path() / "from-bc4", fromBc5 = dir_->path() / "from-bc5",
                   widened = dir_->path() / "widened";
    ASSERT_EQ(run("export " + bc4 + " --out " + fromBc4.string()).code, 0);
    ASSERT_EQ(run("export " + cache_ + " --ao bc4 --out " + fromBc5.string()).code, 0);
    ASSERT_EQ(run("export " + bc4 + " --ao bc5 --out " + widened.string()).code, 0);
    const nlohmann::json m = readJson(fromBc4 / "manifest.json");
    EXPECT_EQ(m["ao"]["format"], "bc4_unorm");
    const CacheReader cache(cache_);
    for (std::size_t i = 0; i < m["probes"].size(); ++i) {
        const std::string ao = m["probes"][i]["ao"].get<std::string>();
        EXPECT_EQ(fileBytes(fromBc4 / ao), fileBytes(fromBc5 / ao)) << ao;
        const cubeao::ProbeView v = cache.probe(i);
        EXPECT_EQ(ddsCubePayload(widened / ao, 83, cache.params().res), bytesOf(v.aoConfidence))
            << "a traced probe's confidence is 1: widening gives its BC5 blocks back";
    }
}

// KTX 2.0 File Format Specification §3: identifier, header, index, level index, DFD, KVD, levels.
struct Ktx2 {
    std::uint32_t vkFormat = 0, typeSize = 0, width = 0, height = 0, depth = 0, layers = 0, faces = 0, levels = 0,
                  supercompression = 0;
    std::vector<std::uint8_t> dfdBlock, kvd, payload;
};
Ktx2 readKtx2(const fs::path& p) {
    Ktx2 k;
    const std::vector<std::uint8_t> b = fileBytes(p);
    static const std::uint8_t kId[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n'};
    EXPECT_GE(b.size(), 104u) << p;
    if (b.size() < 104) return k;
    EXPECT_EQ(std::memcmp(b.data(), kId, 12), 0);
    k.vkFormat = u32(b, 12), k.typeSize = u32(b, 16), k.width = u32(b, 20), k.height = u32(b, 24);
    k.depth = u32(b, 28), k.layers = u32(b, 32), k.faces = u32(b, 36), k.levels = u32(b, 40);
    k.supercompression = u32(b, 44);
    const std::uint32_t dfdOffset = u32(b, 48), dfdLength = u32(b, 52), kvdOffset = u32(b, 56), kvdLength = u32(b, 60);
    EXPECT_EQ(u64(b, 64), 0u);  // sgd offset
    EXPECT_EQ(u64(b, 72), 0u);  // sgd length
    EXPECT_EQ(dfdOffset, 104u);  // right after the one-entry level index
    EXPECT_EQ(u32(b, dfdOffset), dfdLength);  // dfdTotalSize
    k.dfdBlock = slice(b, dfdOffset + 4, dfdLength - 4);
    EXPECT_EQ(kvdOffset % 4, 0u);
    EXPECT_GE(kvdOffset, dfdOffset + dfdLength);
    k.kvd = slice(b, kvdOffset, kvdLength);
    const std::uint64_t levelOffset = u64(b, 80), levelLength = u64(b, 88);
    EXPECT_EQ(u64(b, 96), levelLength);  // uncompressedByteLength
    EXPECT_GE(levelOffset, std::uint64_t(kvdOffset) + kvdLength);
    EXPECT_EQ(levelOffset + levelLength, b.size());
    k.payload = slice(b, std::size_t(levelOffset), std::size_t(levelLength));
    const std::uint64_t align = k.vkFormat == 141 ? 16 : k.vkFormat == 139 ? 8 : 4;  // lcm(block bytes, 4)
    EXPECT_EQ(levelOffset % align, 0u);
    return k;
}

TEST_F(ExportTest, Ktx2HeadersDescriptorsAndPayload) {
    ASSERT_FALSE(HasFatalFailure());
    const CacheReader cache(cache_);
    const std::uint32_t res = cache.params().res, depthRes = cache.params().depthRes;
    for (const std::string ao : {"bc5", "bc4"}) {
        SCOPED_TRACE(ao);
        const fs::path out = dir_->path() / ("ktx2-" + ao);
        const CliRun r = run("export " + cache_ + " --format ktx2 --ao " + ao + " --out " + out.string(), true);
        ASSERT_EQ(r.code, 0) << r.out;
        const nlohmann::json m = readJson(out / "manifest.json");
        EXPECT_EQ(m["container"], "ktx2");
        for (std::size_t i = 0; i < cache.probeCount(); ++i) {
            const cubeao::ProbeView v = cache.probe(i);
            const Ktx2 a = readKtx2(out / m["probes"][i]["ao"].get<std::string>());
            const bool bc5 = ao == "bc5";
            EXPECT_EQ(a.vkFormat, bc5 ? 141u : 139u);
            EXPECT_EQ(a.typeSize, 1u);
            EXPECT_EQ(a.width, res);
            EXPECT_EQ(a.height, res);
            EXPECT_EQ(a.depth, 0u);
            EXPECT_EQ(a.layers, 0u);
            EXPECT_EQ(a.faces, 6u);
            EXPECT_EQ(a.levels, 1u);
            EXPECT_EQ(a.supercompression, 0u);
            EXPECT_EQ(a.payload, bc5 ? bytesOf(v.aoConfidence) : redBlocks(v.aoConfidence));
            // Basic DFD (Khronos Data Format 1.3 §5): vendor/type 0, version 2, size 24 + 16 per sample,
            // colour model BC5 (132) / BC4 (131), 4×4 blocks, bytesPlane0 16 / 8, 64-bit samples.
            const std::vector<std::uint8_t>& d = a.dfdBlock;
            ASSERT_EQ(d.size(), bc5 ? 56u : 40u);
            EXPECT_EQ(u32(d, 0), 0u);
            EXPECT_EQ(d[4] | d[5] << 8, 2);
            EXPECT_EQ(std::size_t(d[6] | d[7] << 8), d.size());
            EXPECT_EQ(d[8], bc5 ? 132 : 131);
            EXPECT_EQ(d[12], 3);
            EXPECT_EQ(d[13], 3);
            EXPECT_EQ(d[16], bc5 ? 16 : 8);
            EXPECT_EQ(d[24] | d[25] << 8, 0);  // sample 0: bits 0..63, channel 0 (red / data)
            EXPECT_EQ(d[26], 63);
            EXPECT_EQ(d[27], 0);
            EXPECT_EQ(u32(d, 36), 0xFFFFFFFFu);
            if (bc5) {
                EXPECT_EQ(d[40] | d[41] << 8, 64);  // sample 1: bits 64..127, channel 1 (green)
                EXPECT_EQ(d[42], 63);
                EXPECT_EQ(d[43], 1);
            }
            EXPECT_TRUE(contains(std::string(a.kvd.begin(), a.kvd.end()), std::string("KTXwriter\0cubeao", 16)));

            const Ktx2 dist = readKtx2(out / m["probes"][i]["distance"].get<std::string>());
            EXPECT_EQ(dist.vkFormat, 70u);  // VK_FORMAT_R16_UNORM
            EXPECT_EQ(dist.typeSize, 2u);
            EXPECT_EQ(dist.width, depthRes);
            EXPECT_EQ(dist.faces, 6u);
            EXPECT_EQ(dist.payload, bytesOf(v.depth));
            ASSERT_EQ(dist.dfdBlock.size(), 40u);
            EXPECT_EQ(dist.dfdBlock[8], 1);    // RGBSDA
            EXPECT_EQ(dist.dfdBlock[16], 2);   // bytesPlane0
            EXPECT_EQ(dist.dfdBlock[26], 15);  // 16 bits
            EXPECT_EQ(u32(dist.dfdBlock, 36), 65535u);
        }
    }
}

// Float distance caches, a georeferenced origin (format 2) and --distance float, on caches written
// directly (random blocks: any 16 bytes are a valid BC5 block).
TEST(Export, DistanceFormatsAndOrigin) {
    TempDir dir("export-formats");
    std::mt19937 rng(3);
    for (const cubeao::DepthFormat df : {cubeao::DepthFormat::R16Float, cubeao::DepthFormat::R32Float,
                                         cubeao::DepthFormat::R16Unorm}) {
        SCOPED_TRACE(cubeao::depthFormatName(df));
        cubeao::CacheParams p;
        p.sceneHash = 0x1234, p.res = 8, p.depthRes = 2, p.depthFormat = df, p.radius = 0.5f, p.spp = 4;
        p.origin = glm::vec3(500000.0f, 4000000.0f, 12.0f);
        std::vector<cubeao::ProbeRecord> probes(2);
        std::uniform_real_distribution<float> dist(0.5f, 40.0f);
        for (std::uint32_t i = 0; i < probes.size(); ++i) {
            cubeao::ProbeRecord& r = probes[i];
            r.index = 7 + i;
            r.position = glm::vec3(1.5f * i, 2.0f, -3.25f);
            r.aoConfidence.resize(cubeao::aoSectionSize(p));
            for (auto& b : r.aoConfidence) b = std::uint8_t(rng());
            std::vector<float> d(6 * p.depthRes * p.depthRes);
            for (float& x : d) x = dist(rng);
            d[3] = 0.0f;  // nothing there
            r.maxDistance = cubeao::depth::maxDistance(d);
            r.depth = cubeao::depth::encode(d, df, r.maxDistance);
        }
        const fs::path cache = dir / (std::string(cubeao::depthFormatName(df)) + ".cubeao");
        cubeao::writeCache(cache, p, probes);

        const fs::path native = dir / ("native-" + cache.stem().string()), asFloat = dir / ("float-" + cache.stem().string());
        ASSERT_EQ(run("export " + cache.string() + " --out " + native.string()).code, 0);
        ASSERT_EQ(run("export " + cache.string() + " --out " + asFloat.string() + " --distance float").code, 0);
        const nlohmann::json m = readJson(native / "manifest.json");
        EXPECT_EQ(m["source"]["format_version"].get<int>(), 2);
        EXPECT_EQ(m["distance"]["units"], df == cubeao::DepthFormat::R16Unorm ? "max_distance" : "world");
        EXPECT_EQ(readJson(asFloat / "manifest.json")["distance"]["units"], "world");
        const std::uint32_t dxgi = df == cubeao::DepthFormat::R16Float   ? 54
                                   : df == cubeao::DepthFormat::R32Float ? 41
                                                                         : 56;
        for (std::size_t i = 0; i < probes.size(); ++i) {
            const nlohmann::json& mp = m["probes"][i];
            EXPECT_EQ(mp["id"].get<std::uint32_t>(), probes[i].index);
            // File coordinates: position + origin in double, as probes.json has them.
            EXPECT_EQ(mp["position"][0].get<double>(), 500000.0 + double(probes[i].position.x));
            EXPECT_EQ(mp["position"][1].get<double>(), 4000002.0);
            EXPECT_EQ(mp["position"][2].get<double>(), 12.0 - 3.25);
            EXPECT_EQ(ddsCubePayload(native / mp["distance"].get<std::string>(), dxgi, 2), probes[i].depth);
            EXPECT_EQ(ddsCubePayload(native / mp["ao"].get<std::string>(), 83, 8), probes[i].aoConfidence);
            std::vector<float> expected;
            ASSERT_TRUE(cubeao::depth::decode(probes[i].depth, 2, df, probes[i].maxDistance, expected));
            const std::vector<std::uint8_t> f = ddsCubePayload(asFloat / mp["distance"].get<std::string>(), 41, 2);
            ASSERT_EQ(f.size(), 4 * expected.size());
            std::vector<float> got(expected.size());
            std::memcpy(got.data(), f.data(), f.size());
            EXPECT_EQ(got, expected);
            EXPECT_EQ(got[3], 0.0f);
        }
    }
}

TEST_F(ExportTest, RefusesBadInputAndLeavesNothingBehind) {
    ASSERT_FALSE(HasFatalFailure());
    TempDir dir("export-bad");
    const std::string out = (dir / "out").string();
    // The command line: exit 2, before anything is opened or created.
    CliRun r = run("export " + cache_ + " --out " + out + " --format png", true);
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_TRUE(contains(r.out, "--format \"png\": expected dds or ktx2")) << r.out;
    EXPECT_EQ(run("export " + cache_ + " --out " + out + " --ao bc7").code, 2);
    EXPECT_EQ(run("export " + cache_).code, 2);  // no --out
    EXPECT_FALSE(fs::exists(out));

    // Not a cache, a damaged cache: exit 1 naming the file, no output directory.
    r = run("export " + dir.write("notes.txt", "hello") + " --out " + out, true);
    EXPECT_EQ(r.code, 1);
    EXPECT_TRUE(contains(r.out, "not a cubeao cache")) << r.out;
    std::vector<std::uint8_t> bytes = fileBytes(cache_);
    bytes[bytes.size() - 100] ^= 0x40;  // in the last probe's payload
    const fs::path damaged = dir / "damaged.cubeao";
    std::ofstream(damaged, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    r = run("export " + damaged.string() + " --out " + out, true);
    EXPECT_EQ(r.code, 1);
    EXPECT_TRUE(contains(r.out, "checksum")) << r.out;
    EXPECT_FALSE(fs::exists(out));

    // An output that cannot be a directory.
    const std::string file = dir.write("file.txt", "x");
    r = run("export " + cache_ + " --out " + file, true);
    EXPECT_EQ(r.code, 1);
    EXPECT_TRUE(contains(r.out, "not a directory")) << r.out;

    // A write that fails half way (files over RLIMIT_FSIZE fail with EFBIG, as on a full disk): the
    // directory the export created is gone again, and an existing one keeps exactly what it had.
    cubeao::test::ChildSpec spec;
    spec.args = {"export", cache_, "--out", out};
    spec.fileSizeLimit = 3000;  // probe 0's distance file (916 bytes) is written, its AO file (6292) fails
    cubeao::test::ChildRun c = cubeao::test::runChild(spec);
    EXPECT_TRUE(c.exited && c.code == 1) << c.describe() << c.err;
    EXPECT_TRUE(contains(c.err, "probe_0000_ao.dds: cannot write export file: write")) << c.err;
    EXPECT_FALSE(fs::exists(out));
    const fs::path kept = dir / "kept";
    dir.write("kept/manifest.json", "{\"old\": true}");
    spec.args = {"export", cache_, "--out", kept.string()};
    c = cubeao::test::runChild(spec);
    EXPECT_TRUE(c.exited && c.code == 1) << c.describe();
    EXPECT_EQ(std::distance(fs::directory_iterator(kept), fs::directory_iterator()), 1);
    EXPECT_EQ(readJson(kept / "manifest.json")["old"], true);
}

}  // namespace

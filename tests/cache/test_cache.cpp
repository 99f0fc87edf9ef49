// The .cubeao cache file (src/cubeao/cache/cache_file.h, docs/FORMAT.md): round trips, damage of every
// kind (truncation at every byte, flipped bytes, forged offsets), atomic writes, append and merge.
// Run under the CUBEAO_SANITIZE build too: damaged files must fail cleanly, never read out of bounds.
#include <gtest/gtest.h>
#include <xxhash.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "cubeao/cache/bc4.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/core/error.h"
#include "test_util.h"

namespace cubeao {
namespace {

using test::contains;
using test::errorMessage;
using test::TempDir;
using Bytes = std::vector<std::uint8_t>;

CacheParams smallParams(std::uint32_t res = 8, std::uint32_t depthRes = 4, DepthFormat f = DepthFormat::R16Unorm) {
    CacheParams p;
    p.sceneHash = 0x0123456789abcdefULL;
    p.res = res;
    p.depthRes = depthRes;
    p.depthFormat = f;
    p.estimator = 3;
    p.falloff = 1;
    p.spp = 64;
    p.radius = 0.25f;
    p.seed = 7;
    p.directions = 16;
    p.steps = 16;
    p.hybridThreshold = 0.95f;
    return p;
}

// Random payload bytes; probe i sits at (i + 1 + offset, 2, 3) and has index i + offset, so positions
// and indices are distinct.
std::vector<ProbeRecord> randomProbes(const CacheParams& p, int n, unsigned seed, float offset = 0.0f) {
    std::mt19937 rng(seed);
    std::vector<ProbeRecord> probes(n);
    for (int i = 0; i < n; ++i) {
        probes[i].index = std::uint32_t(i) + std::uint32_t(offset);
        probes[i].position = {float(i) + 1.0f + offset, 2.0f, 3.0f};
        probes[i].maxDistance = 10.0f + float(i);
        probes[i].aoConfidence.resize(aoSectionSize(p));
        probes[i].depth.resize(depthSectionSize(p));
        for (auto& b : probes[i].aoConfidence) b = std::uint8_t(rng());
        for (auto& b : probes[i].depth) b = std::uint8_t(rng());
    }
    return probes;
}

Bytes readBytes(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return Bytes(std::istreambuf_iterator<char>(in), {});
}

void writeBytes(const std::filesystem::path& p, const Bytes& b, std::size_t n) {
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(b.data()), std::streamsize(n));
}
void writeBytes(const std::filesystem::path& p, const Bytes& b) { writeBytes(p, b, b.size()); }

void expectSameProbe(const ProbeView& v, const ProbeRecord& r) {
    EXPECT_EQ(v.index, r.index);
    EXPECT_EQ(v.position, r.position);
    EXPECT_EQ(v.maxDistance, r.maxDistance);
    EXPECT_TRUE(std::equal(v.aoConfidence.begin(), v.aoConfidence.end(), r.aoConfidence.begin(), r.aoConfidence.end()));
    EXPECT_TRUE(std::equal(v.depth.begin(), v.depth.end(), r.depth.begin(), r.depth.end()));
}

// The section a byte offset belongs to, from docs/FORMAT.md (written out here, not taken from the
// implementation): header 128 bytes, 64 per table entry, probe blocks padded to 16, 8-byte checksum.
std::string sectionAt(std::uint64_t offset, const CacheParams& p, std::uint64_t probes) {
    const std::uint64_t payload = 128 + 64 * probes;
    const std::uint64_t stride = (aoSectionSize(p) + depthSectionSize(p) + 15) / 16 * 16;
    if (offset < 128) return "header";
    if (offset < payload) return "probe table";
    if (offset < payload + stride * probes) return "probe " + std::to_string((offset - payload) / stride);
    return "file checksum";
}

// First error from opening the file, reading every probe and verifying it all; "" if none.
std::string firstFailure(const std::filesystem::path& path) {
    try {
        CacheReader r(path);
        for (std::size_t i = 0; i < r.probeCount(); ++i) r.probe(i);
        r.verifyAll();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

// Recomputes table, header and file checksums after a test forged a field, so the reader's value
// checks (not its checksums) must catch it.
void reseal(Bytes& b) {
    auto get32 = [&](std::size_t at) {
        std::uint32_t v;
        std::memcpy(&v, &b[at], 4);
        return v;
    };
    auto put64 = [&](std::size_t at, std::uint64_t v) { std::memcpy(&b[at], &v, 8); };  // host is little-endian
    const std::uint32_t count = get32(60);
    put64(96, XXH3_64bits(b.data() + 128, 64 * std::size_t(count)));
    put64(120, XXH3_64bits(b.data(), 120));
    put64(b.size() - 8, XXH3_64bits(b.data(), b.size() - 8));
}

TEST(CacheFile, SizesFollowTheParameters) {
    const CacheParams p = smallParams(512, 128, DepthFormat::R16Unorm);
    EXPECT_EQ(aoSectionSize(p), 6u * 128 * 128 * 16);  // 1 byte per texel
    EXPECT_EQ(aoSectionSize(p), 6u * 512 * 512);
    EXPECT_EQ(depthSectionSize(p), 6u * 128 * 128 * 2);
    EXPECT_EQ(depthSectionSize(smallParams(8, 3, DepthFormat::R32Float)), 6u * 9 * 4);
    EXPECT_EQ(cacheFileSize(p, 0), 136u);
    EXPECT_EQ(cacheFileSize(p, 200), 136u + 200 * (64 + 1572864 + 196608));
    EXPECT_EQ(cacheFileSize(smallParams(4, 3, DepthFormat::R16Float), 2), 136u + 2 * (64 + 208));  // 204 → 208
    EXPECT_TRUE(cacheParamProblems(p).empty());
}

TEST(CacheFile, RoundTrip) {
    TempDir dir("cache");
    const CacheParams p = smallParams();
    const auto probes = randomProbes(p, 3, 1);
    writeCache(dir / "a.cubeao", p, probes);

    const CacheReader r(dir / "a.cubeao");
    EXPECT_EQ(r.params(), p);
    EXPECT_EQ(r.formatVersion(), 1u);  // origin 0: the oldest format that holds it (FORMAT.md "Versioning")
    ASSERT_EQ(r.probeCount(), 3u);
    EXPECT_EQ(r.fileSize(), cacheFileSize(p, 3));
    EXPECT_EQ(std::filesystem::file_size(dir / "a.cubeao"), cacheFileSize(p, 3));
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(r.position(i), probes[i].position);
        EXPECT_EQ(r.index(i), probes[i].index);
        const ProbeView v = r.probe(i);
        expectSameProbe(v, probes[i]);
        // Sections are uploadable straight from the mapping.
        EXPECT_EQ(reinterpret_cast<std::uintptr_t>(v.aoConfidence.data()) % kCacheSectionAlignment, 0u);
        EXPECT_EQ(reinterpret_cast<std::uintptr_t>(v.depth.data()) % kCacheSectionAlignment, 0u);
        expectSameProbe(viewOf(r.copyProbe(i)), probes[i]);
    }
    EXPECT_NO_THROW(r.verifyAll());
    EXPECT_NO_THROW(r.expectScene(p.sceneHash));
    EXPECT_DOUBLE_EQ(r.bytesPerTexel(), double(cacheFileSize(p, 3)) / (3.0 * 6 * 8 * 8));
}

// The bake's AO filter (byte 35) is format 3; an unfiltered cache keeps the oldest format that holds it,
// byte 35 zero; a format-1 or 2 file with byte 35 set is damaged, a format-3 one with 9 out of range.
TEST(CacheFile, TheAoFilterIsFormatThreeAndABakeParameter) {
    TempDir dir("cache");
    CacheParams p = smallParams();
    const auto probes = randomProbes(p, 2, 21);
    writeCache(dir / "plain.cubeao", p, probes);
    const Bytes plain = readBytes(dir / "plain.cubeao");
    EXPECT_EQ(plain[8], 1u);
    EXPECT_EQ(plain[35], 0u);

    p.denoise = 2;
    writeCache(dir / "filtered.cubeao", p, probes);
    const CacheReader filtered(dir / "filtered.cubeao");
    EXPECT_EQ(filtered.formatVersion(), 3u);
    EXPECT_EQ(filtered.params(), p);
    EXPECT_EQ(filtered.params().denoise, 2u);
    filtered.verifyAll();
    const Bytes f = readBytes(dir / "filtered.cubeao");
    EXPECT_EQ(f[35], 2u);
    ASSERT_EQ(f.size(), plain.size());
    for (std::size_t at = 0; at < f.size(); ++at) {
        const bool checksum = (at >= 120 && at < 128) || at >= f.size() - 8;  // header's, file's
        if (at == 8 || at == 35 || checksum) continue;
        ASSERT_EQ(f[at], plain[at]) << "byte " << at << ": only the version and the filter differ";
    }

    CacheParams unfiltered = p;
    unfiltered.denoise = 0;
    const std::string differ = errorMessage([&] { filtered.expectParams(unfiltered); });
    EXPECT_TRUE(contains(differ, "denoise 2 vs 0")) << differ;
    EXPECT_TRUE(contains(errorMessage([&] { appendToCache(dir / "plain.cubeao", p, randomProbes(p, 1, 22, 10.0f)); }), "denoise"));

    Bytes forged = plain;
    forged[35] = 2;
    reseal(forged);
    writeBytes(dir / "forged.cubeao", forged);
    const std::string reserved = errorMessage([&] { CacheReader r(dir / "forged.cubeao"); });
    EXPECT_TRUE(contains(reserved, "reserved bytes are not zero")) << reserved;

    forged = f;
    forged[35] = 9;
    reseal(forged);
    writeBytes(dir / "wide.cubeao", forged);
    const std::string wide = errorMessage([&] { CacheReader r(dir / "wide.cubeao"); });
    EXPECT_TRUE(contains(wide, "denoise 9 is not in 0..8")) << wide;
}

// BC5 probes of a traced bake: random AO (red) blocks, confidence 1 in every texel (green blocks
// FF FE 00.., what the encoder makes of sixteen ones), the payload a traced bake hands the writer.
std::vector<ProbeRecord> tracedProbes(const CacheParams& p, int n, unsigned seed, float offset = 0.0f) {
    std::vector<ProbeRecord> probes = randomProbes(p, n, seed, offset);
    for (ProbeRecord& r : probes)
        for (std::size_t b = 0; b < r.aoConfidence.size(); b += 16) {
            const std::uint8_t one[8] = {255, 254, 0, 0, 0, 0, 0, 0};
            std::memcpy(&r.aoConfidence[b + 8], one, 8);
        }
    return probes;
}

// The red half of every 16-byte BC5 block, written out here (docs/FORMAT.md "AO alone").
Bytes redHalves(const std::vector<std::uint8_t>& bc5) {
    Bytes out;
    for (std::size_t b = 0; b < bc5.size(); b += 16) out.insert(out.end(), bc5.begin() + long(b), bc5.begin() + long(b + 8));
    return out;
}

// A traced cache stores its AO as BC4 (format 4, byte 116 = 1): half the AO bytes, the red halves
// of the BC5 blocks the bake made, converted on the way; BC5 from it again gives the bake's bytes
// back. Every other byte of the header is what a BC5 cache of the same probes has.
TEST(CacheFile, ATracedCacheStoresItsAoAsBc4InFormatFour) {
    TempDir dir("cache");
    CacheParams p = smallParams(16, 4);
    p.estimator = 2;  // traced
    p.hybridThreshold = 0.0f;
    const auto probes = tracedProbes(p, 3, 31);
    writeCache(dir / "bc5.cubeao", p, probes);
    CacheParams bc4 = p;
    bc4.aoFormat = AoFormat::Bc4;
    writeCache(dir / "bc4.cubeao", bc4, probes);  // BC5 records: converted as they are written

    const CacheReader r(dir / "bc4.cubeao");
    EXPECT_EQ(r.formatVersion(), 4u);
    EXPECT_EQ(r.params(), bc4);
    EXPECT_EQ(aoSectionSize(bc4), 6u * 4u * 4u * 8u);
    EXPECT_EQ(aoSectionSize(bc4) * 2, aoSectionSize(p));
    EXPECT_EQ(r.fileSize(), cacheFileSize(bc4, 3));
    r.verifyAll();
    for (std::size_t i = 0; i < probes.size(); ++i) {
        const ProbeView v = r.probe(i);
        EXPECT_EQ(v.aoFormat, AoFormat::Bc4);
        EXPECT_EQ(Bytes(v.aoConfidence.begin(), v.aoConfidence.end()), redHalves(probes[i].aoConfidence)) << i;
        EXPECT_TRUE(std::equal(v.depth.begin(), v.depth.end(), probes[i].depth.begin(), probes[i].depth.end()));
        const ProbeRecord back = withAoFormat(r.copyProbe(i), AoFormat::Bc5, p.res);
        EXPECT_EQ(back.aoConfidence, probes[i].aoConfidence) << "BC4 -> BC5 gives the bake's blocks back";
    }
    const Bytes a = readBytes(dir / "bc5.cubeao"), b = readBytes(dir / "bc4.cubeao");
    EXPECT_EQ(a[8], 1u);
    EXPECT_EQ(b[8], 4u);
    EXPECT_EQ(b[116], 1u);
    for (std::size_t at = 16; at < 120; ++at) {
        if ((at < 80 || at >= 104) && at != 116) {  // payload size, file size, table checksum (80..103) differ
            EXPECT_EQ(a[at], b[at]) << "header byte " << at;
        }
    }

    // Converting keeps the AO bit for bit whatever the confidence held; BC4 reads back confidence 1.
    const auto hybrid = randomProbes(p, 1, 32);
    const auto alone = convertAoSection(hybrid[0].aoConfidence, p.res, AoFormat::Bc5, AoFormat::Bc4);
    EXPECT_EQ(alone, redHalves(hybrid[0].aoConfidence));
    const auto widened = convertAoSection(alone, p.res, AoFormat::Bc4, AoFormat::Bc5);
    EXPECT_EQ(redHalves(widened), alone);
    for (std::size_t b5 = 8; b5 < widened.size(); b5 += 16)
        ASSERT_EQ(Bytes(widened.begin() + long(b5), widened.begin() + long(b5 + 8)), Bytes({255, 254, 0, 0, 0, 0, 0, 0}));
    const float ones[16] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
    EXPECT_EQ(bc::encodeBc4Block(ones), 0xFEFFu) << "the green block a traced bake writes";
    EXPECT_TRUE(contains(errorMessage([&] { convertAoSection(alone, p.res, AoFormat::Bc5, AoFormat::Bc4); }),
                         "is not bc5 at res 16"));
}

// BC4 drops the confidence, so only traced caches may use it: the writer refuses another estimator,
// and so does the reader (a forged byte 116); a format-3 file with byte 116 set is damaged, and a
// value outside the enum is named.
TEST(CacheFile, Bc4IsForTracedCachesAndByte116IsReservedBeforeFormatFour) {
    TempDir dir("cache");
    CacheParams p = smallParams(16, 4);  // hybrid: its confidence is what the projection ranks by
    CacheParams bc4 = p;
    bc4.aoFormat = AoFormat::Bc4;
    const std::string refused = errorMessage([&] { writeCache(dir / "h.cubeao", bc4, randomProbes(p, 1, 33)); });
    EXPECT_TRUE(contains(refused, "ao format bc4 holds no confidence: only traced caches")) << refused;
    EXPECT_FALSE(std::filesystem::exists(dir / "h.cubeao"));

    p.estimator = 2;
    p.hybridThreshold = 0.0f;
    p.denoise = 1;  // format 3
    writeCache(dir / "t3.cubeao", p, tracedProbes(p, 1, 34));
    Bytes forged = readBytes(dir / "t3.cubeao");
    ASSERT_EQ(forged[8], 3u);
    forged[116] = 1;
    reseal(forged);
    writeBytes(dir / "forged3.cubeao", forged);
    EXPECT_TRUE(contains(errorMessage([&] { CacheReader r(dir / "forged3.cubeao"); }), "reserved bytes are not zero"));

    bc4 = p;
    bc4.aoFormat = AoFormat::Bc4;
    writeCache(dir / "t4.cubeao", bc4, tracedProbes(p, 1, 34));
    forged = readBytes(dir / "t4.cubeao");
    forged[33] = 0;  // hsplit
    reseal(forged);
    writeBytes(dir / "hsplit4.cubeao", forged);
    EXPECT_TRUE(contains(errorMessage([&] { CacheReader r(dir / "hsplit4.cubeao"); }), "ao format bc4 holds no confidence"));
    forged = readBytes(dir / "t4.cubeao");
    forged[116] = 7;
    reseal(forged);
    writeBytes(dir / "seven.cubeao", forged);
    EXPECT_TRUE(contains(errorMessage([&] { CacheReader r(dir / "seven.cubeao"); }), "ao format 7 is not bc5 (0) or bc4 (1)"));
    forged = readBytes(dir / "t4.cubeao");
    forged[117] = 1;
    reseal(forged);
    writeBytes(dir / "r117.cubeao", forged);
    EXPECT_TRUE(contains(errorMessage([&] { CacheReader r(dir / "r117.cubeao"); }), "reserved bytes are not zero"));
}

TEST(CacheFile, LevelsOfDetailAreFormatFiveAndEachLevelIsItsOwnView) {
    TempDir dir("cache");
    CacheParams p = smallParams(32, 8);
    p.levels = 3;  // AO 32², 16², 8²; distances 8², 4², 2²
    EXPECT_EQ(aoSectionSize(p), 6u * (32 * 32 + 16 * 16 + 8 * 8));  // BC5: a byte a texel at every level
    EXPECT_EQ(depthSectionSize(p), 6u * 2 * (64 + 16 + 4));
    EXPECT_EQ(depthLevelOffset(p, 2), 6u * 2 * (64 + 16));
    const CacheParams two = levelParams(p, 2);
    EXPECT_EQ(two.res, 8u);
    EXPECT_EQ(two.depthRes, 2u);
    EXPECT_EQ(two.levels, 1u);
    EXPECT_TRUE(contains(errorMessage([&] { levelParams(p, 3); }), "level 3 of a cache of 3 levels (levels are 0..2)"));

    const auto probes = randomProbes(p, 2, 51);
    writeCache(dir / "l.cubeao", p, probes);
    const CacheReader r(dir / "l.cubeao");
    EXPECT_EQ(r.formatVersion(), 5u);
    EXPECT_EQ(r.params(), p);
    EXPECT_EQ(r.fileSize(), cacheFileSize(p, 2));
    for (std::size_t i = 0; i < probes.size(); ++i) {
        std::uint64_t ao = 0, depth = 0;
        for (std::uint32_t k = 0; k < 3; ++k) {
            const CacheParams l = levelParams(p, k);
            const ProbeView v = levelView(r.probe(i), p, k);
            ASSERT_EQ(v.aoConfidence.size(), aoSectionSize(l)) << k;
            ASSERT_EQ(v.depth.size(), depthSectionSize(l)) << k;
            EXPECT_EQ(Bytes(v.aoConfidence.begin(), v.aoConfidence.end()),
                      Bytes(probes[i].aoConfidence.begin() + long(ao), probes[i].aoConfidence.begin() + long(ao + aoSectionSize(l))));
            EXPECT_EQ(Bytes(v.depth.begin(), v.depth.end()),
                      Bytes(probes[i].depth.begin() + long(depth), probes[i].depth.begin() + long(depth + depthSectionSize(l))));
            ao += aoSectionSize(l), depth += depthSectionSize(l);
        }
    }

    // A traced cache with levels converts to BC4 level by level: each level's blocks lose their green half.
    CacheParams traced = p;
    traced.estimator = 2, traced.hybridThreshold = 0.0f;
    const CacheParams bc4 = withAoFormat(traced, AoFormat::Bc4);
    writeCache(dir / "t.cubeao", bc4, tracedProbes(traced, 1, 52));
    const CacheReader t(dir / "t.cubeao");
    EXPECT_EQ(t.formatVersion(), 5u);
    EXPECT_EQ(aoSectionSize(bc4) * 2, aoSectionSize(traced));
    for (std::uint32_t k = 0; k < 3; ++k) {
        const ProbeView v = levelView(t.probe(0), bc4, k);
        EXPECT_EQ(v.aoConfidence.size(), aoSectionSize(levelParams(bc4, k)));
    }

    // One level is format 4 or older, byte 117 reserved there; levels must halve into whole blocks.
    CacheParams one = p;
    one.levels = 1;
    writeCache(dir / "one.cubeao", one, randomProbes(one, 1, 53));
    Bytes forged = readBytes(dir / "one.cubeao");
    EXPECT_EQ(forged[8], 1u);
    forged[117] = 2;
    reseal(forged);
    writeBytes(dir / "r117.cubeao", forged);
    EXPECT_TRUE(contains(errorMessage([&] { CacheReader x(dir / "r117.cubeao"); }), "reserved bytes are not zero"));
    CacheParams odd = smallParams(24, 6);
    odd.levels = 2;  // 24 → 12: not whole 4×4 blocks... it is; depth 6 → 3 is too
    EXPECT_TRUE(cacheParamProblems(odd).empty());
    odd.levels = 3;  // 24 → 6: not a multiple of 4
    const std::string refused = errorMessage([&] { writeCache(dir / "odd.cubeao", odd, std::vector<ProbeRecord>{}); });
    EXPECT_TRUE(contains(refused, "3 levels need res a multiple of 16 and depthRes of 4 (res 24, depthRes 6)")) << refused;
    forged = readBytes(dir / "l.cubeao");
    forged[117] = 9;
    reseal(forged);
    writeBytes(dir / "nine.cubeao", forged);
    EXPECT_TRUE(contains(errorMessage([&] { CacheReader x(dir / "nine.cubeao"); }), "levels 9 is not in 1..8"));
    EXPECT_EQ(maxLevels(512, 128), 6u);  // 512² … 16²
    EXPECT_EQ(maxLevels(128, 32), 4u);
    EXPECT_EQ(maxLevels(24, 6), 1u);  // 12² < 16²
    EXPECT_EQ(maxLevels(512, 3), 1u);  // the distance cube does not halve
}

TEST(CacheFile, RoundTripEveryDepthFormatAndNoProbes) {
    TempDir dir("cache");
    for (DepthFormat f : {DepthFormat::R16Unorm, DepthFormat::R16Float, DepthFormat::R32Float})
        for (std::uint32_t depthRes : {1u, 3u, 4u}) {
            SCOPED_TRACE(std::string(depthFormatName(f)) + " depthRes " + std::to_string(depthRes));
            const CacheParams p = smallParams(4, depthRes, f);
            const auto probes = randomProbes(p, 2, depthRes);
            writeCache(dir / "f.cubeao", p, probes);
            const CacheReader r(dir / "f.cubeao");
            EXPECT_EQ(r.params(), p);
            for (std::size_t i = 0; i < 2; ++i) expectSameProbe(r.probe(i), probes[i]);
            EXPECT_NO_THROW(r.verifyAll());
        }
    writeCache(dir / "empty.cubeao", smallParams(), std::vector<ProbeRecord>{});
    const CacheReader r(dir / "empty.cubeao");
    EXPECT_EQ(r.probeCount(), 0u);
    EXPECT_EQ(r.fileSize(), 136u);
    EXPECT_EQ(r.bytesPerTexel(), 0.0);
    EXPECT_NO_THROW(r.verifyAll());
}

// Every prefix of a valid cache fails on open, naming the section the cut falls in.
TEST(CacheFile, TruncatedAtEveryByteNamesTheSection) {
    TempDir dir("cache");
    for (const CacheParams& p : {smallParams(8, 4, DepthFormat::R16Unorm), smallParams(4, 3, DepthFormat::R16Float)}) {
        writeCache(dir / "whole.cubeao", p, randomProbes(p, 2, 2));
        const Bytes whole = readBytes(dir / "whole.cubeao");
        ASSERT_LT(whole.size(), 2048u);
        const auto cut = dir / "cut.cubeao";
        for (std::size_t n = 0; n < whole.size(); ++n) {
            SCOPED_TRACE("cut at " + std::to_string(n) + " of " + std::to_string(whole.size()));
            writeBytes(cut, whole, n);
            const std::string msg = errorMessage([&] { CacheReader r(cut); });
            EXPECT_TRUE(contains(msg, cut.string())) << msg;
            if (n == 0) {
                EXPECT_TRUE(contains(msg, "not a cubeao cache (the file is empty)")) << msg;
                continue;
            }
            EXPECT_TRUE(contains(msg, ": " + sectionAt(n, p, 2) + ": truncated")) << msg;
        }
    }
}

// A flipped byte anywhere is caught: by open (magic, header, table), by the first access of the probe
// whose sections hold it, or, for padding and the trailing checksum, by verifyAll.
TEST(CacheFile, FlippedByteAnywhereIsReported) {
    TempDir dir("cache");
    for (const CacheParams& p : {smallParams(8, 4, DepthFormat::R16Unorm), smallParams(4, 3, DepthFormat::R16Float)}) {
        const auto probes = randomProbes(p, 2, 3);
        writeCache(dir / "whole.cubeao", p, probes);
        const Bytes whole = readBytes(dir / "whole.cubeao");
        const auto bad = dir / "flip.cubeao";
        const std::uint64_t stride = (aoSectionSize(p) + depthSectionSize(p) + 15) / 16 * 16;
        for (std::size_t at = 0; at < whole.size(); ++at)
            for (std::uint8_t mask : {0x01, 0x80}) {  // lowest and highest bit
                SCOPED_TRACE("byte " + std::to_string(at) + " ^ " + std::to_string(mask));
                Bytes b = whole;
                b[at] ^= mask;
                writeBytes(bad, b);
                const std::string section = sectionAt(at, p, 2);
                if (at < 8) {
                    EXPECT_TRUE(contains(errorMessage([&] { CacheReader r(bad); }), "not a cubeao cache (magic"));
                } else if (section == "header" || section == "probe table") {
                    const std::string msg = errorMessage([&] { CacheReader r(bad); });
                    EXPECT_TRUE(contains(msg, bad.string() + ": " + section + ": ")) << msg;
                } else {
                    const CacheReader r(bad);  // the table is intact: open reads no payload byte
                    const std::uint64_t inPayload = at - (128 + 64 * 2);
                    const bool inProbe = section != "file checksum" &&
                                         inPayload % stride < aoSectionSize(p) + depthSectionSize(p);
                    for (std::size_t i = 0; i < 2; ++i) {
                        if (inProbe && section == "probe " + std::to_string(i)) {
                            const std::string msg = errorMessage([&] { r.probe(i); });
                            EXPECT_TRUE(contains(msg, bad.string() + ": probe " + std::to_string(i) +
                                                          ": checksum mismatch"))
                                << msg;
                        } else {
                            expectSameProbe(r.probe(i), probes[i]);
                        }
                    }
                    const std::string msg = errorMessage([&] { r.verifyAll(); });
                    EXPECT_TRUE(contains(msg, inProbe ? section + ": checksum mismatch" : "file checksum: mismatch"))
                        << msg;
                }
                EXPECT_NE(firstFailure(bad), "");
            }
    }
}

// The run-time grid's read (CacheReader::unverifiedDepth): a probe's distance section as stored,
// damaged or not, without the check that would hash its AO too; probe(i) still refuses the damage.
// The run-time's read advice (no read-around) changes no byte that copyProbe and verifyAll read.
TEST(CacheFile, TheUnverifiedDepthIsTheStoredSectionAndSkipsOnlyTheCheck) {
    TempDir dir("cache");
    const CacheParams p = smallParams(8, 4, DepthFormat::R16Unorm);
    const auto probes = randomProbes(p, 2, 5);
    writeCache(dir / "whole.cubeao", p, probes);
    const Bytes whole = readBytes(dir / "whole.cubeao");
    const std::uint64_t stride = (aoSectionSize(p) + depthSectionSize(p) + 15) / 16 * 16;
    const std::uint64_t probe1 = 128 + 64 * 2 + stride;  // AO, then the distance section
    const auto bytes = [](std::span<const std::uint8_t> s) { return std::vector<std::uint8_t>(s.begin(), s.end()); };
    for (const std::uint64_t at : {probe1 + 5, probe1 + aoSectionSize(p) + 3}) {
        SCOPED_TRACE("byte " + std::to_string(at));
        Bytes b = whole;
        b[at] ^= 0x10;
        writeBytes(dir / "bad.cubeao", b);
        const CacheReader r(dir / "bad.cubeao");
        r.adviseRandomAccess();  // as the run-time does: a hint, the bytes read are the same
        std::vector<std::uint8_t> expected(probes[1].depth.begin(), probes[1].depth.end());
        if (at >= probe1 + aoSectionSize(p)) expected[at - probe1 - aoSectionSize(p)] ^= 0x10;
        EXPECT_EQ(bytes(r.unverifiedDepth(1)), expected);
        EXPECT_EQ(bytes(r.unverifiedDepth(0)), bytes(probes[0].depth));
        EXPECT_TRUE(contains(errorMessage([&] { r.probe(1); }), "probe 1: checksum mismatch"));
        EXPECT_TRUE(contains(errorMessage([&] { r.unverifiedDepth(2); }), "no such probe"));
        expectSameProbe(viewOf(r.copyProbe(0)), probes[0]);
        EXPECT_TRUE(contains(errorMessage([&] { r.verifyAll(); }), "probe 1: checksum mismatch"));
    }
}

// Checksums intact but values forged: the value checks alone must refuse them.
TEST(CacheFile, ForgedOffsetsAndSizesAreRefused) {
    TempDir dir("cache");
    const CacheParams p = smallParams();
    writeCache(dir / "ok.cubeao", p, randomProbes(p, 3, 4));
    const Bytes ok = readBytes(dir / "ok.cubeao");
    const auto path = dir / "forged.cubeao";
    // Writes `value`'s low `bytes` bytes at `at`, reseals, and expects `expected` in the open error.
    auto expectRefused = [&](std::size_t at, std::uint64_t value, int bytes, const std::string& expected) {
        Bytes b = ok;
        std::memcpy(&b[at], &value, bytes);
        reseal(b);
        writeBytes(path, b);
        const std::string msg = errorMessage([&] { CacheReader r(path); });
        EXPECT_TRUE(contains(msg, path.string() + ": " + expected)) << "byte " << at << ": " << msg;
    };
    const std::size_t e1 = 128 + 64;  // probe 1's table entry
    const std::uint64_t ao1 = 128 + 3 * 64 + aoSectionSize(p) + depthSectionSize(p);
    const std::string at1 = "probe 1: AO section at offset ";
    expectRefused(e1 + 16, std::uint64_t(1) << 63, 8,
                  at1 + "9223372036854775808 + 384 bytes runs past the end of the payload");
    expectRefused(e1 + 16, ~std::uint64_t(0) - 15, 8, at1 + "18446744073709551600 + 384 bytes runs past");
    expectRefused(e1 + 16, ao1 + 8, 8, at1 + std::to_string(ao1 + 8) + " is not 16-byte aligned");
    expectRefused(e1 + 16, ao1 - 16, 8, at1 + std::to_string(ao1 - 16) + " overlaps");
    expectRefused(e1 + 32, ao1 + 128, 8, "probe 1: depth section at offset " + std::to_string(ao1 + 128) + " overlaps");
    expectRefused(e1 + 24, 400, 8, "probe 1: AO section is 400 bytes, res 8 needs 384");
    expectRefused(e1 + 40, 0, 8, "probe 1: depth section is 0 bytes, depthRes 4 r16unorm needs 192");
    expectRefused(e1 + 0, 0x7fc00000, 4, "probe 1: position (nan, 2, 3) is not finite");
    expectRefused(e1 + 12, 0xbf800000, 4, "probe 1: maxDistance -1 is not finite and >= 0");
    expectRefused(e1 + 60, 1, 1, "probe 1: reserved bytes");
    expectRefused(e1 + 56, 0, 4, "probe 1: index 0 is also probe 0's");
    expectRefused(60, 4, 4, "header: payload offset 320, the table of 4 probes ends at 384");
    expectRefused(80, ~std::uint64_t(0) - 100, 8, "header: file size");
    expectRefused(64, 0, 8, "header: probe table offset 0");
    expectRefused(24, 6, 4, "header: bad bake parameters: res 6 is not a multiple of 4");
    // Every problem at once (STYLE.md): bad res and an unknown depth format in one message.
    Bytes b = ok;
    b[24] = 6;
    b[32] = 9;
    reseal(b);
    writeBytes(path, b);
    const std::string msg = errorMessage([&] { CacheReader r(path); });
    EXPECT_TRUE(contains(msg, "res 6") && contains(msg, "depth format 9")) << msg;
}

TEST(CacheFile, InterruptedWriteLeavesTheOldFile) {
    TempDir dir("cache");
    const CacheParams p = smallParams();
    const auto path = dir / "a.cubeao";
    writeCache(path, p, randomProbes(p, 2, 5));
    const Bytes before = readBytes(path);

    WriteOptions crash;
    crash.beforeRename = [] { throw Error("injected crash before rename"); };
    EXPECT_TRUE(contains(errorMessage([&] { writeCache(path, p, randomProbes(p, 3, 6), crash); }), "injected crash"));
    EXPECT_EQ(readBytes(path), before);
    EXPECT_TRUE(contains(errorMessage([&] { appendToCache(path, p, randomProbes(p, 1, 7, 10.0f), crash); }),
                         "injected crash"));
    EXPECT_EQ(readBytes(path), before);
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(dir.path())) names.push_back(e.path().filename());
    EXPECT_EQ(names, std::vector<std::string>{"a.cubeao"});  // no temporary file left behind
}

TEST(CacheFile, WriteFailuresNameTheFile) {
    TempDir dir("cache");
    const CacheParams p = smallParams();
    const auto missing = dir / "no-such-dir" / "a.cubeao";
    std::string msg = errorMessage([&] { writeCache(missing, p, randomProbes(p, 1, 8)); });
    EXPECT_TRUE(contains(msg, missing.string()) && contains(msg, "temporary file")) << msg;

    auto probes = randomProbes(p, 2, 9);
    probes[1].depth.pop_back();
    CacheParams bad = p;
    bad.res = 6;
    bad.radius = 0.0f;
    msg = errorMessage([&] { writeCache(dir / "b.cubeao", bad, probes); });
    EXPECT_TRUE(contains(msg, "res 6") && contains(msg, "radius 0")) << msg;
    probes[1].index = probes[0].index;
    msg = errorMessage([&] { writeCache(dir / "b.cubeao", p, probes); });
    EXPECT_TRUE(contains(msg, "probe 1: depth section has 191 bytes, depthRes 4 r16unorm needs 192")) << msg;
    EXPECT_TRUE(contains(msg, "probe 1: index 0 is also probe 0's")) << msg;
    EXPECT_FALSE(std::filesystem::exists(dir / "b.cubeao"));
}

TEST(CacheFile, ReaderKeepsTheFileItMappedAcrossARewrite) {
    TempDir dir("cache");
    const CacheParams p = smallParams();
    const auto first = randomProbes(p, 2, 10);
    writeCache(dir / "a.cubeao", p, first);
    const CacheReader r(dir / "a.cubeao");
    writeCache(dir / "a.cubeao", p, randomProbes(p, 1, 11));
    ASSERT_EQ(r.probeCount(), 2u);
    for (std::size_t i = 0; i < 2; ++i) expectSameProbe(r.probe(i), first[i]);
}

TEST(CacheFile, WrongSceneNewerVersionAndForeignFilesHaveTheirOwnMessages) {
    TempDir dir("cache");
    const CacheParams p = smallParams();
    const auto path = dir / "a.cubeao";
    writeCache(path, p, randomProbes(p, 1, 12));

    const std::string scene = errorMessage([&] { CacheReader(path).expectScene(0xfeedULL); });
    EXPECT_TRUE(contains(scene, "baked for scene 0x0123456789abcdef, not for this scene 0x000000000000feed")) << scene;

    Bytes b = readBytes(path);
    b[8] = std::uint8_t(kCacheFormatVersion + 1);  // the version is checked before any checksum
    writeBytes(dir / "newer.cubeao", b);
    const std::string newer = errorMessage([&] { CacheReader r(dir / "newer.cubeao"); });
    EXPECT_TRUE(contains(newer, "written by a newer cubeao (format " + std::to_string(kCacheFormatVersion + 1) +
                                    ", this build reads up to " + std::to_string(kCacheFormatVersion) + ")"))
        << newer;

    std::mt19937 rng(13);
    Bytes noise(1000);
    for (auto& x : noise) x = std::uint8_t(rng());
    noise[0] = 0x42;
    writeBytes(dir / "noise.bin", noise);
    const std::string random = errorMessage([&] { CacheReader r(dir / "noise.bin"); });
    EXPECT_TRUE(contains(random, "not a cubeao cache (magic: the file starts with 42 ")) << random;

    const Bytes png{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R'};
    writeBytes(dir / "image.png", png);
    const std::string image = errorMessage([&] { CacheReader r(dir / "image.png"); });
    EXPECT_TRUE(contains(image, "not a cubeao cache (magic: the file starts with 89 50 4E 47 0D 0A 1A 0A")) << image;

    writeBytes(dir / "empty.cubeao", {});
    EXPECT_TRUE(contains(errorMessage([&] { CacheReader r(dir / "empty.cubeao"); }),
                         "empty.cubeao: not a cubeao cache (the file is empty)"));
    EXPECT_TRUE(contains(errorMessage([&] { CacheReader r(dir.path()); }), "not a cubeao cache (a directory)"));
    EXPECT_TRUE(contains(errorMessage([&] { CacheReader r(dir / "missing.cubeao"); }),
                         "missing.cubeao: cannot open cache: No such file"));
}

TEST(CacheFile, AppendAddsProbesAndRefusesOtherParameters) {
    TempDir dir("cache");
    const CacheParams p = smallParams();
    const auto path = dir / "a.cubeao";
    const auto first = randomProbes(p, 2, 14);
    const auto more = randomProbes(p, 2, 15, 10.0f);
    appendToCache(path, p, first);  // a missing file is created
    appendToCache(path, p, more);
    {
        const CacheReader r(path);
        ASSERT_EQ(r.probeCount(), 4u);
        for (std::size_t i = 0; i < 2; ++i) expectSameProbe(r.probe(i), first[i]);
        for (std::size_t i = 0; i < 2; ++i) expectSameProbe(r.probe(2 + i), more[i]);
        EXPECT_NO_THROW(r.verifyAll());
    }
    const Bytes before = readBytes(path);
    CacheParams other = p;
    other.seed = 8;
    other.sceneHash = 0x42;
    std::string msg = errorMessage([&] { appendToCache(path, other, randomProbes(other, 1, 16, 20.0f)); });
    EXPECT_TRUE(contains(msg, "cannot append") && contains(msg, "seed 7 vs 8") &&
                contains(msg, "scene hash 0x0123456789abcdef vs 0x0000000000000042"))
        << msg;
    msg = errorMessage([&] { appendToCache(path, p, randomProbes(p, 1, 17)); });  // position of probe 0
    EXPECT_TRUE(contains(msg, "new probe 0 at (1, 2, 3) is already probe 0 of the cache")) << msg;
    auto sameIndex = randomProbes(p, 2, 17, 20.0f);
    sameIndex[1].index = 11;  // the index of the cache's probe 3
    msg = errorMessage([&] { appendToCache(path, p, sameIndex); });
    EXPECT_TRUE(contains(msg, "new probe 1 has index 11, as probe 3 of the cache")) << msg;
    sameIndex[1].index = 20;  // the index of new probe 0
    msg = errorMessage([&] { appendToCache(path, p, sameIndex); });
    EXPECT_TRUE(contains(msg, "new probe 1 has index 20, as probe 0 of the new probes")) << msg;
    EXPECT_EQ(readBytes(path), before);

    Bytes damaged = before;
    damaged[128 + 4 * 64 + 5] ^= 1;  // probe 0's AO section
    writeBytes(path, damaged);
    msg = errorMessage([&] { appendToCache(path, p, randomProbes(p, 1, 18, 30.0f)); });
    EXPECT_TRUE(contains(msg, "probe 0: checksum mismatch")) << msg;  // damage is never re-sealed
    EXPECT_EQ(readBytes(path), damaged);
}

TEST(CacheFile, MergeShardsAndRefuseMismatches) {
    TempDir dir("cache");
    const CacheParams p = smallParams();
    const auto a = randomProbes(p, 2, 19), b = randomProbes(p, 1, 20, 10.0f);
    writeCache(dir / "a.cubeao", p, a);
    writeCache(dir / "b.cubeao", p, b);
    mergeCaches(dir / "out.cubeao", {dir / "a.cubeao", dir / "b.cubeao"});
    {
        const CacheReader r(dir / "out.cubeao");
        EXPECT_EQ(r.params(), p);
        ASSERT_EQ(r.probeCount(), 3u);
        expectSameProbe(r.probe(0), a[0]);
        expectSameProbe(r.probe(1), a[1]);
        expectSameProbe(r.probe(2), b[0]);
        EXPECT_NO_THROW(r.verifyAll());
    }
    // Into one of its own inputs: the inputs stay mapped until the rename.
    mergeCaches(dir / "b.cubeao", {dir / "b.cubeao", dir / "a.cubeao"});
    EXPECT_EQ(CacheReader(dir / "b.cubeao").probeCount(), 3u);

    CacheParams other = p;
    other.radius = 0.5f;
    writeCache(dir / "c.cubeao", other, randomProbes(other, 1, 21, 20.0f));
    std::string msg = errorMessage([&] { mergeCaches(dir / "out2.cubeao", {dir / "a.cubeao", dir / "c.cubeao"}); });
    EXPECT_TRUE(contains(msg, (dir / "c.cubeao").string() + ": cannot merge with") &&
                contains(msg, "radius 0.25 vs 0.5"))
        << msg;
    CacheParams scene = p;
    scene.sceneHash = 1;
    writeCache(dir / "d.cubeao", scene, randomProbes(scene, 1, 22, 30.0f));
    msg = errorMessage([&] { mergeCaches(dir / "out2.cubeao", {dir / "a.cubeao", dir / "d.cubeao"}); });
    EXPECT_TRUE(contains(msg, (dir / "d.cubeao").string()) && contains(msg, "scene hash")) << msg;
    msg = errorMessage([&] { mergeCaches(dir / "out2.cubeao", {dir / "a.cubeao", dir / "a.cubeao"}); });
    EXPECT_TRUE(contains(msg, "probe 0 at (1, 2, 3) is also probe 0 of")) << msg;
    auto shifted = randomProbes(p, 1, 23, 40.0f);
    shifted[0].index = 1;  // a probe of a.cubeao at another position: the same probe, moved
    writeCache(dir / "e.cubeao", p, shifted);
    msg = errorMessage([&] { mergeCaches(dir / "out2.cubeao", {dir / "a.cubeao", dir / "e.cubeao"}); });
    EXPECT_TRUE(contains(msg, (dir / "e.cubeao").string() + ": probe 0 has index 1, as probe 1 of " +
                                  (dir / "a.cubeao").string()))
        << msg;
    EXPECT_TRUE(contains(errorMessage([&] { mergeCaches(dir / "out2.cubeao", {}); }), "at least one input"));
    EXPECT_FALSE(std::filesystem::exists(dir / "out2.cubeao"));
}

// Merge converts: inputs that differ in the AO format alone are merged into the format asked for
// (default: the first input's); the AO survives either way, and a non-traced cache is not made BC4.
TEST(CacheFile, MergeConvertsTheAoFormat) {
    TempDir dir("cache");
    CacheParams p = smallParams(16, 4);
    p.estimator = 2;
    p.hybridThreshold = 0.0f;
    CacheParams bc4 = p;
    bc4.aoFormat = AoFormat::Bc4;
    const auto a = tracedProbes(p, 2, 41), b = tracedProbes(p, 1, 42, 10.0f);
    writeCache(dir / "a5.cubeao", p, a);
    writeCache(dir / "b4.cubeao", bc4, b);
    mergeCaches(dir / "first.cubeao", {dir / "a5.cubeao", dir / "b4.cubeao"});
    mergeCaches(dir / "as4.cubeao", {dir / "a5.cubeao", dir / "b4.cubeao"}, {}, AoFormat::Bc4);
    {
        const CacheReader first(dir / "first.cubeao"), as4(dir / "as4.cubeao");
        EXPECT_EQ(first.params(), p);
        EXPECT_EQ(as4.params(), bc4);
        ASSERT_EQ(first.probeCount(), 3u);
        ASSERT_EQ(as4.probeCount(), 3u);
        const std::vector<ProbeRecord> all = {a[0], a[1], b[0]};
        for (std::size_t i = 0; i < 3; ++i) {
            expectSameProbe(first.probe(i), all[i]);
            EXPECT_EQ(Bytes(as4.probe(i).aoConfidence.begin(), as4.probe(i).aoConfidence.end()),
                      redHalves(all[i].aoConfidence));
        }
        first.verifyAll();
        as4.verifyAll();
    }
    // Back to BC5 in place: the file a BC5 merge of the same probes writes, byte for byte.
    mergeCaches(dir / "as4.cubeao", {dir / "as4.cubeao"}, {}, AoFormat::Bc5);
    EXPECT_EQ(readBytes(dir / "as4.cubeao"), readBytes(dir / "first.cubeao"));

    const CacheParams hybrid = smallParams(16, 4);
    writeCache(dir / "h.cubeao", hybrid, randomProbes(hybrid, 1, 43));
    const std::string msg = errorMessage([&] { mergeCaches(dir / "h4.cubeao", {dir / "h.cubeao"}, {}, AoFormat::Bc4); });
    EXPECT_TRUE(contains(msg, "cannot write bc4 AO") && contains(msg, "holds no confidence")) << msg;
    EXPECT_FALSE(std::filesystem::exists(dir / "h4.cubeao"));
}

}  // namespace
}  // namespace cubeao

// From a baked probe to the cache: bake settings → cache parameters, the CPU and GPU encoders on the
// same bake (BC5 blocks identical, distance cube within one code), the production read-back that
// keeps uncompressed data on the GPU, the AO PSNR target, and BakeCacheWriter's batches and refusals
// (bake/bake_cache.h; the CLI around it is in test_cli.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "cubeao/bake/bake.h"
#include "cubeao/bake/bake_cache.h"
#include "cubeao/bake/bake_driver.h"
#include "cubeao/bake/gpu_bake.h"
#include "cubeao/cache/bc4.h"
#include "cubeao/cache/depth_cube.h"
#include "cubeao/cache/probe_levels.h"
#include "cubeao/scene/import.h"
#include "bake_test_settings.h"
#include "gl_fixture.h"
#include "test_util.h"

namespace cubeao {
namespace {

namespace fs = std::filesystem;
using test::bakeSettings;
using test::contains;
using test::errorMessage;
using test::TempDir;

constexpr glm::vec3 kBoxProbe{3.0f, 1.4f, 2.5f};

const Scene& boxRoom() {
    static const Scene scene = loadScene("builtin:box-room");
    return scene;
}

// ---- settings → cache parameters ---------------------------------------------------------------

TEST(BakeSettingsCache, ParametersKeepWhatTheEstimatorUses) {
    BakeSettings s = bakeSettings(Estimator::HorizonSplit, 16, 0.5f, 32);
    EXPECT_EQ(s.depthRes, 4);
    EXPECT_EQ(s.depthFormat, DepthFormat::R16Unorm);
    CacheParams p = cacheParamsFor(s, 42);
    EXPECT_EQ(p.sceneHash, 42u);
    EXPECT_EQ(p.res, 16u);
    EXPECT_EQ(p.depthRes, 4u);
    EXPECT_EQ(p.estimator, 0u);
    EXPECT_EQ(p.spp, 0u) << "hsplit casts no rays";
    EXPECT_EQ(p.directions, 16u);
    EXPECT_EQ(p.hybridThreshold, 0.0f);
    EXPECT_EQ(p.radius, 0.5f);
    EXPECT_TRUE(cacheParamProblems(p).empty());

    s.estimator = Estimator::Traced;
    p = cacheParamsFor(s, 42);
    EXPECT_EQ(p.spp, 32u);
    EXPECT_EQ(p.directions, 0u);
    EXPECT_EQ(p.steps, 0u);
    s.estimator = Estimator::Hybrid;
    p = cacheParamsFor(s, 42);
    EXPECT_EQ(p.estimator, 3u);
    EXPECT_EQ(p.spp, 32u);
    EXPECT_EQ(p.directions, 16u);
    EXPECT_EQ(p.hybridThreshold, 0.95f);
}

TEST(BakeSettingsCache, ResolveChecksResolutionsAndDepthFormat) {
    BakeSettings s;
    s.res = 6;
    EXPECT_TRUE(contains(errorMessage([&] { resolveBakeSettings(s, 1.0f); }), "multiple of 4"));
    s.res = 8;
    s.depthRes = 9;
    EXPECT_TRUE(contains(errorMessage([&] { resolveBakeSettings(s, 1.0f); }), "--depth-res 9"));
    s.depthRes = 0;
    s.depthFormat = DepthFormat(7);
    EXPECT_TRUE(contains(errorMessage([&] { resolveBakeSettings(s, 1.0f); }), "depth format 7"));
    s.depthFormat = DepthFormat::R32Float;
    const BakeSettings r = resolveBakeSettings(s, 1.0f);
    EXPECT_EQ(r.depthRes, 2);
    EXPECT_EQ(r.depthFormat, DepthFormat::R32Float);
}

// ---- the CPU path encodes what it baked ----------------------------------------------------------

TEST(BakeEncode, CpuBakeEncodesWhatItBakedAndMeetsFortyDecibels) {
    const EmbreeScene rt(boxRoom());
    for (const Estimator e : {Estimator::HorizonSplit, Estimator::Traced}) {
        const BakeSettings s = bakeSettings(e, 32, 1.0f, 64);
        const BakedProbe p = bakeProbeCpu(rt, kBoxProbe, 3, s);
        std::vector<glm::vec2> aoConfidence(p.ao.size());
        for (std::size_t t = 0; t < p.ao.size(); ++t) aoConfidence[t] = {p.ao[t], p.confidence[t]};
        EXPECT_EQ(p.encoded.aoConfidence, bc::encodeBc5Cube(aoConfidence, s.res));
        const std::vector<float> coarse = depth::downsample(p.gbuffer.texels, s.res, s.depthRes, depth::kFilter);
        EXPECT_EQ(p.encoded.maxDistance, depth::maxDistance(coarse));
        EXPECT_EQ(p.encoded.depth, depth::encode(coarse, s.depthFormat, p.encoded.maxDistance));
        EXPECT_EQ(p.encoded.surfaceTexels, p.ao.size()) << "the room is closed: every texel shows a surface";
        // The target (there on Sibenik probes): AO PSNR ≥ 40 dB against the uncompressed bake.
        const double psnr = aoPsnr(p.encoded.aoSquaredError, p.encoded.surfaceTexels);
        std::printf("[ bake bc5 ] box room %s res 32: AO PSNR %.2f dB\n", estimatorName(e), psnr);
        EXPECT_GE(psnr, 40.0) << estimatorName(e);
        EXPECT_GT(p.timings.encodeMs, 0.0);
    }
}

// Levels of detail (bake --levels): level 0 is the bake without them, byte for byte; the coarser levels
// are probe_levels.h's from the bake's full-resolution AO and its level-0 distances.
TEST(BakeEncode, LevelsFollowLevelZeroAndComeFromTheFullResolutionAo) {
    const EmbreeScene rt(boxRoom());
    const BakeSettings one = bakeSettings(Estimator::Traced, 64, 1.0f, 16);
    BakeSettings three = one;
    three.levels = 3;  // 64², 32², 16²; distances 16², 8², 4²
    three = resolveBakeSettings(three, 1.0f);
    const BakedProbe a = bakeProbeCpu(rt, kBoxProbe, 3, one), b = bakeProbeCpu(rt, kBoxProbe, 3, three);
    ASSERT_EQ(b.encoded.aoConfidence.size(), bc::bc5Size(64) + bc::bc5Size(32) + bc::bc5Size(16));
    ASSERT_EQ(b.encoded.depth.size(), 6u * 2u * (256u + 64u + 16u));
    EXPECT_TRUE(std::equal(a.encoded.aoConfidence.begin(), a.encoded.aoConfidence.end(), b.encoded.aoConfidence.begin()));
    EXPECT_TRUE(std::equal(a.encoded.depth.begin(), a.encoded.depth.end(), b.encoded.depth.begin()));
    std::vector<glm::vec2> aoConfidence(b.ao.size());
    std::vector<float> distances(b.ao.size());
    for (std::size_t t = 0; t < b.ao.size(); ++t)
        aoConfidence[t] = {b.ao[t], b.confidence[t]}, distances[t] = b.gbuffer.texels[t].w;
    const std::vector<std::uint8_t> ao = levels::coarserAo(aoConfidence, distances, 64, 3);
    const std::vector<std::uint8_t> depth = levels::coarserDistances(a.encoded.depth, 16, three.depthFormat, 3);
    EXPECT_TRUE(std::equal(ao.begin(), ao.end(), b.encoded.aoConfidence.begin() + long(a.encoded.aoConfidence.size())));
    EXPECT_TRUE(std::equal(depth.begin(), depth.end(), b.encoded.depth.begin() + long(a.encoded.depth.size())));
    EXPECT_EQ(cacheParamsFor(three, 1u).levels, 3u);

    BakeSettings bad = bakeSettings(Estimator::Traced, 32, 1.0f, 16);
    bad.levels = 4;  // 32 → 4² faces: below 16²
    EXPECT_TRUE(contains(errorMessage([&] { resolveBakeSettings(bad, 1.0f); }), "--levels 4: expected 1..2 at res 32"));
    bad.levels = kAllLevels;
    EXPECT_EQ(resolveBakeSettings(bad, 1.0f).levels, 2);
}

// ---- GPU encoders against the CPU twin -----------------------------------------------------------

class BakeEncodeGl : public GlTest {};

void expectSameEncoding(const EncodedProbe& gpu, const EncodedProbe& cpu, DepthFormat f) {
    EXPECT_TRUE(gpu.aoConfidence == cpu.aoConfidence) << "BC5 blocks differ";
    EXPECT_EQ(gpu.maxDistance, cpu.maxDistance);
    EXPECT_EQ(gpu.surfaceTexels, cpu.surfaceTexels);
    EXPECT_NEAR(gpu.aoSquaredError, cpu.aoSquaredError, 1e-4 * cpu.aoSquaredError + 1e-9);
    ASSERT_EQ(gpu.depth.size(), cpu.depth.size());
    const std::size_t per = depthBytesPerTexel(f);
    std::size_t off = 0;
    for (std::size_t t = 0; t < cpu.depth.size() / per; ++t) {
        std::int64_t a = 0, b = 0;
        for (std::size_t k = 0; k < per; ++k) {
            a |= std::int64_t(gpu.depth[t * per + k]) << (8 * k);
            b |= std::int64_t(cpu.depth[t * per + k]) << (8 * k);
        }
        off += std::abs(a - b) > (f == DepthFormat::R16Unorm ? 1 : 0) ? 1 : 0;
    }
    EXPECT_EQ(off, 0u) << "depth texels more than one code apart";
}

TEST_F(BakeEncodeGl, GpuEncodersMatchTheCpuTwinOnTheSameBake) {
    for (const Estimator e : {Estimator::HorizonSplit, Estimator::Traced})
        for (const DepthFormat f : {DepthFormat::R16Unorm, DepthFormat::R16Float, DepthFormat::R32Float})
            for (const int depthRes : {0, 5}) {
                SCOPED_TRACE(std::string(estimatorName(e)) + " " + depthFormatName(f) + " depthRes " +
                             std::to_string(depthRes));
                BakeSettings s = bakeSettings(e, 32, 1.0f, 16);
                s.depthFormat = f;
                s.depthRes = depthRes == 0 ? s.depthRes : depthRes;
                GpuBaker baker(boxRoom(), s);
                baker.setReadback(BakeReadback::All);
                baker.setTimings(true);
                const BakedProbe p = baker.bake(kBoxProbe, 4);
                ASSERT_EQ(p.gbuffer.texels.size(), p.gbuffer.texelCount());
                expectSameEncoding(p.encoded, encodeProbeCpu(p.gbuffer, p.ao, p.confidence, s), f);
                EXPECT_GT(p.timings.encodeMs, 0.0);
            }
}

TEST_F(BakeEncodeGl, ProductionReadBackLeavesTheUncompressedProbeOnTheGpu) {
    const BakeSettings s = bakeSettings(Estimator::Gtao, 16, 1.0f, 16);
    GpuBaker baker(boxRoom(), s);
    const BakedProbe encoded = baker.bake(kBoxProbe, 1);  // default: BakeReadback::Encoded
    EXPECT_EQ(encoded.timings.gbufferMs + encoded.timings.aoMs + encoded.timings.encodeMs, 0.0)
        << "a production bake times no stage (timing one stalls the pipeline around it)";
    EXPECT_TRUE(encoded.gbuffer.texels.empty());
    EXPECT_TRUE(encoded.ao.empty() && encoded.confidence.empty());
    EXPECT_EQ(encoded.encoded.aoConfidence.size(), bc::bc5Size(16));
    baker.setReadback(BakeReadback::All);
    const BakedProbe all = baker.bake(kBoxProbe, 1);
    EXPECT_EQ(all.encoded.aoConfidence, encoded.encoded.aoConfidence);
    EXPECT_EQ(all.encoded.depth, encoded.encoded.depth);
    EXPECT_EQ(all.encoded.surfaceTexels, encoded.encoded.surfaceTexels);
}

// The GPU bake's levels are made from what it read back at full resolution: the same bytes as the CPU
// encoder makes of that read-back, on the production path (nothing else read back) as well.
TEST_F(BakeEncodeGl, GpuLevelsMatchTheCpuTwinOnTheSameBake) {
    BakeSettings s = bakeSettings(Estimator::Traced, 32, 1.0f, 16);
    s.levels = 2;
    GpuBaker baker(boxRoom(), s);
    const BakedProbe encoded = baker.bake(kBoxProbe, 5);
    baker.setReadback(BakeReadback::All);
    const BakedProbe all = baker.bake(kBoxProbe, 5);
    EXPECT_EQ(encoded.encoded.aoConfidence, all.encoded.aoConfidence);
    EXPECT_EQ(encoded.encoded.depth, all.encoded.depth);
    EXPECT_EQ(all.encoded.aoConfidence.size(), bc::bc5Size(32) + bc::bc5Size(16));
    expectSameEncoding(all.encoded, encodeProbeCpu(all.gbuffer, all.ao, all.confidence, s), s.depthFormat);
}

// The two devices' caches for the same probe: traced AO traces the same rays on both, so the decoded
// AO agrees up to grazing-ray flips; the distance cubes differ only where rasterisation and Embree
// pick different triangles at an edge.
TEST_F(BakeEncodeGl, GpuAndCpuBakesStoreTheSameProbeWithinTolerance) {
    const BakeSettings s = bakeSettings(Estimator::Traced, 16, 1.0f, 16);
    GpuBaker baker(boxRoom(), s);
    const EncodedProbe gpu = baker.bake(kBoxProbe, 2).encoded;
    const EncodedProbe cpu = bakeProbeCpu(EmbreeScene(boxRoom()), kBoxProbe, 2, s).encoded;
    std::vector<glm::vec2> a, b;
    ASSERT_TRUE(bc::decodeBc5Cube(gpu.aoConfidence.data(), gpu.aoConfidence.size(), s.res, a));
    ASSERT_TRUE(bc::decodeBc5Cube(cpu.aoConfidence.data(), cpu.aoConfidence.size(), s.res, b));
    double mae = 0.0;
    for (std::size_t t = 0; t < a.size(); ++t) mae += std::abs(a[t].x - b[t].x) / double(a.size());
    EXPECT_LE(mae, 0.01);
    std::vector<float> da, db;
    ASSERT_TRUE(depth::decode(gpu.depth, s.depthRes, s.depthFormat, gpu.maxDistance, da));
    ASSERT_TRUE(depth::decode(cpu.depth, s.depthRes, s.depthFormat, cpu.maxDistance, db));
    std::size_t off = 0;
    for (std::size_t t = 0; t < da.size(); ++t) off += std::abs(da[t] - db[t]) > 2e-4f * db[t] + 2.0f * cpu.maxDistance / 65535.0f;
    EXPECT_LE(off, da.size() / 100) << "distance texels that differ by more than a code";
    EXPECT_NEAR(gpu.maxDistance, cpu.maxDistance, 1e-4f * cpu.maxDistance);
}

// ---- the bake driver -----------------------------------------------------------------------------

// The loop every caller shares: a shard's probes less those the sink holds, in index order, each
// stored as its baker encoded it (the same bytes as bakeProbeCpu's), with --verify per probe.
TEST(BakeDriver, BakesTheShardLessTheSinkAndVerifies) {
    std::vector<glm::vec3> probes;
    for (int i = 0; i < 7; ++i) probes.push_back(glm::vec3(1.0f + 0.8f * float(i), 1.4f, 2.5f));
    BakeSettings s = bakeSettings(Estimator::Traced, 8, 1.0f, 8);
    s.device = BakeDevice::Cpu;
    MemoryProbeSink sink;
    sink.add({3, probes[3], 0.0f, {}, {}});  // already there: skipped
    ProbeBaker baker(boxRoom(), s);
    BakeJob job;
    job.probes = probes;
    job.shard = parseBakeShard("1/2");
    job.verify = VerifySpec{};
    job.progressLabel.clear();
    std::vector<std::uint32_t> seen;
    job.onProbe = [&](std::uint32_t index, const BakedProbe& p) {
        seen.push_back(index);
        EXPECT_EQ(p.ao.size(), p.gbuffer.texelCount());
    };
    const BakeResult r = bakeProbes(baker, job, sink);
    EXPECT_EQ(r.inShard, 3u);  // 1, 3, 5
    EXPECT_EQ(r.skipped, 1u);
    EXPECT_EQ(seen, (std::vector<std::uint32_t>{1, 5}));
    ASSERT_EQ(sink.records.size(), 3u);
    for (std::size_t k = 1; k < 3; ++k) {
        const ProbeRecord& rec = sink.records[k];
        const EncodedProbe direct = bakeProbeCpu(EmbreeScene(boxRoom()), rec.position, rec.index, s).encoded;
        EXPECT_EQ(rec.aoConfidence, direct.aoConfidence) << rec.index;
        EXPECT_EQ(rec.depth, direct.depth) << rec.index;
        EXPECT_EQ(rec.maxDistance, direct.maxDistance) << rec.index;
        EXPECT_EQ(rec.position, probes[rec.index]);
    }
    ASSERT_EQ(r.probes.size(), 2u);
    EXPECT_EQ(r.verifySpp, 32);
    EXPECT_EQ(r.verify.texels, 2u * 6u * 8u * 8u);
    EXPECT_GT(r.verify.mae, 0.0);
    EXPECT_NEAR(r.verify.mae, 0.5 * (r.probes[0].verify->mae + r.probes[1].verify->mae), 1e-12);
    EXPECT_EQ(r.twin.texels, 0u) << "no twin check on the CPU path: it would compare the bake with itself";
    EXPECT_TRUE(contains(errorMessage([] { parseBakeShard("2/2"); }), "expected I/N with 0 <= I < N"));
}

// ---- BakeCacheWriter -----------------------------------------------------------------------------

CacheParams smallParams() {
    CacheParams p;
    p.sceneHash = 7;
    p.res = 4;
    p.depthRes = 1;
    p.radius = 1.0f;
    return p;
}

std::vector<glm::vec3> probeSet(int n) {
    std::vector<glm::vec3> probes;
    for (int i = 0; i < n; ++i) probes.push_back(glm::vec3(float(i), 1.0f, 2.0f));
    return probes;
}

ProbeRecord record(const CacheParams& p, const std::vector<glm::vec3>& probes, std::uint32_t index) {
    return {index, probes[index], 1.0f, std::vector<std::uint8_t>(aoSectionSize(p), std::uint8_t(index)),
            std::vector<std::uint8_t>(depthSectionSize(p), 1)};
}

std::vector<std::uint8_t> fileBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

TEST(BakeCacheWriter, WritesBatchesAsPartsAndResumes) {
    TempDir dir("bakecache");
    const fs::path path = dir / "a.cubeao";
    const CacheParams p = smallParams();
    const auto probes = probeSet(5);
    {
        BakeCacheWriter w(path, p, probes, {2, 1e9});
        w.add(record(p, probes, 0));
        EXPECT_FALSE(fs::exists(BakeCacheWriter::partPath(path, 0))) << "nothing is written before the first batch";
        w.add(record(p, probes, 1));
        EXPECT_FALSE(fs::exists(path)) << "the output is written once, by finish()";
        const CacheReader part(BakeCacheWriter::partPath(path, 0));
        EXPECT_EQ(part.probeCount(), 2u) << "a full batch is a part file";
        w.add(record(p, probes, 2));
        EXPECT_TRUE(contains(errorMessage([&] { w.add(record(p, probes, 2)); }), "probe index 2 baked twice"));
        // No finish(): stands for an exception while baking probe 3; the destructor keeps probe 2.
    }
    EXPECT_EQ(CacheReader(BakeCacheWriter::partPath(path, 1)).probeCount(), 1u);

    BakeCacheWriter w(path, p, probes, {2, 1e9});
    EXPECT_EQ(w.probesAtStart(), 3u) << "the parts of the interrupted run are picked up";
    EXPECT_TRUE(w.has(0) && w.has(1) && w.has(2));
    EXPECT_FALSE(w.has(3));
    w.add(record(p, probes, 4));
    w.add(record(p, probes, 3));
    EXPECT_TRUE(fs::exists(BakeCacheWriter::partPath(path, 2))) << "new parts are numbered after the old ones";
    w.finish();
    EXPECT_EQ(w.appends(), 1u);
    EXPECT_FALSE(fs::exists(BakeCacheWriter::partPath(path, 0)) || fs::exists(BakeCacheWriter::partPath(path, 1)) ||
                 fs::exists(BakeCacheWriter::partPath(path, 2)))
        << "finish() removes the parts it merged";
    const CacheReader r(path);
    ASSERT_EQ(r.probeCount(), 5u);
    r.verifyAll();
    // Sorted by index: the very bytes one uninterrupted, unsharded bake writes.
    std::vector<ProbeRecord> all;
    for (std::uint32_t i = 0; i < 5; ++i) all.push_back(record(p, probes, i));
    writeCache(dir / "one.cubeao", p, all);
    EXPECT_EQ(fileBytes(path), fileBytes(dir / "one.cubeao"));
}

// Part numbers pass six digits after a million batches; a resumed bake still adopts those parts.
TEST(BakeCacheWriter, AdoptsPartsNumberedPastSixDigits) {
    TempDir dir("bakecache");
    const fs::path path = dir / "a.cubeao";
    const CacheParams p = smallParams();
    const auto probes = probeSet(3);
    writeCache(BakeCacheWriter::partPath(path, 1000000), p, std::vector<ProbeRecord>{record(p, probes, 1)});
    BakeCacheWriter w(path, p, probes, {2, 1e9});
    EXPECT_EQ(w.probesAtStart(), 1u);
    EXPECT_TRUE(w.has(1));
    EXPECT_FALSE(w.has(0));
}

// The point of the parts: a batch writes the batch, not every probe baked before it.
TEST(BakeCacheWriter, ABatchCostsInProportionToTheBatch) {
    TempDir dir("bakecache");
    const fs::path path = dir / "a.cubeao";
    const CacheParams p = smallParams();
    const auto probes = probeSet(12);
    BakeCacheWriter w(path, p, probes, {3, 1e9});
    for (std::uint32_t i = 0; i < 12; ++i) w.add(record(p, probes, i));
    ASSERT_EQ(w.parts().size(), 4u);
    for (const fs::path& part : w.parts()) EXPECT_EQ(fs::file_size(part), cacheFileSize(p, 3)) << part;
    w.finish();
    EXPECT_EQ(fs::file_size(path), cacheFileSize(p, 12));
}

// A finish() interrupted after its rename leaves parts whose probes the output holds: the next run
// removes them instead of refusing a probe "baked twice"; a part that overlaps only partly is damage.
TEST(BakeCacheWriter, ResumeAfterAnInterruptedFinish) {
    TempDir dir("bakecache");
    const fs::path path = dir / "a.cubeao";
    const CacheParams p = smallParams();
    const auto probes = probeSet(4);
    const std::vector<ProbeRecord> first{record(p, probes, 0), record(p, probes, 1)};
    writeCache(path, p, first);
    writeCache(BakeCacheWriter::partPath(path, 0), p, first);                                    // stale
    writeCache(BakeCacheWriter::partPath(path, 1), p, std::vector<ProbeRecord>{record(p, probes, 2)});  // not merged
    {
        BakeCacheWriter w(path, p, probes);
        EXPECT_FALSE(fs::exists(BakeCacheWriter::partPath(path, 0)));
        EXPECT_EQ(w.probesAtStart(), 3u);
        w.add(record(p, probes, 3));
        w.finish();
    }
    EXPECT_EQ(CacheReader(path).probeCount(), 4u);

    writeCache(BakeCacheWriter::partPath(path, 0), p, std::vector<ProbeRecord>{record(p, probes, 3)});
    writeCache(BakeCacheWriter::partPath(path, 1), p, std::vector<ProbeRecord>{record(p, probes, 3)});
    fs::remove(path);
    const std::string msg = errorMessage([&] { BakeCacheWriter w(path, p, probes); });
    EXPECT_TRUE(contains(msg, "part-000001: holds probe index 3, which the cache or an earlier part holds too")) << msg;
}

TEST(BakeCacheWriter, RefusesWhatIsNotTheSameBake) {
    TempDir dir("bakecache");
    const fs::path path = dir / "a.cubeao";
    const CacheParams p = smallParams();
    const auto probes = probeSet(3);
    {
        BakeCacheWriter w(path, p, probes);
        w.finish();  // nothing baked: an empty cache, so shards without probes still merge
    }
    EXPECT_EQ(CacheReader(path).probeCount(), 0u);
    appendToCache(path, p, std::vector<ProbeRecord>{record(p, probes, 1)});

    CacheParams other = p;
    other.seed = 9;
    std::string msg = errorMessage([&] { BakeCacheWriter w(path, other, probes); });
    EXPECT_TRUE(contains(msg, "other bake parameters") && contains(msg, "seed 0 vs 9") &&
                contains(msg, "choose another --out or delete the file"))
        << msg;
    auto moved = probes;
    moved[1].x += 0.5f;
    msg = errorMessage([&] { BakeCacheWriter w(path, p, moved); });
    EXPECT_TRUE(contains(msg, "holds probe index 1 at (1, 1, 2), the probe set puts it at (1.5, 1, 2)")) << msg;
    msg = errorMessage([&] { BakeCacheWriter w(path, p, probeSet(1)); });
    EXPECT_TRUE(contains(msg, "the probe set has 1 probes")) << msg;
    msg = errorMessage([&] { BakeCacheWriter w(dir.path(), p, probes); });
    EXPECT_TRUE(contains(msg, "--out is a directory")) << msg;
    const std::string text = dir.write("notes.cubeao", "hello");
    msg = errorMessage([&] { BakeCacheWriter w(text, p, probes); });
    EXPECT_TRUE(contains(msg, "not a cubeao cache") && contains(msg, "choose another --out")) << msg;
}

}  // namespace
}  // namespace cubeao

// The CPU bake path of bake.h: Embree primary rays for the cube G-buffer, horizon.h or Embree AO rays
// per texel, TBB over faces × rows. Every per-texel quantity depends only on the texel (its key, its
// G-buffer entry), so the result does not depend on the thread count or the schedule.
#include "cubeao/bake/bake.h"

#include <atomic>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>
#include <limits>

#include "common/ao_denoise.h"
#include "cubeao/bake/horizon.h"
#include "cubeao/cache/bc4.h"
#include "cubeao/cache/depth_cube.h"
#include "cubeao/cache/probe_levels.h"
#include "cubeao/core/error.h"

namespace cubeao {
namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Calls f(face, i, j, index) for every texel of a res² cube, in parallel over the 6·res rows.
template <class F>
void forEachTexel(int res, F&& f) {
    tbb::parallel_for(tbb::blocked_range<int>(0, cube::kFaces * res), [&](const tbb::blocked_range<int>& rows) {
        for (int row = rows.begin(); row < rows.end(); ++row) {
            const int face = row / res, j = row % res;
            for (int i = 0; i < res; ++i) f(face, i, j, cube::texelIndex(face, i, j, res));
        }
    });
}

std::uint64_t nonEmptyTexels(const CubeGBuffer& g) {
    std::uint64_t count = 0;
    for (const glm::vec4& t : g.texels) count += CubeGBuffer::empty(t) ? 0 : 1;
    return count;
}

// AO and confidence of every non-empty texel by a horizon estimator (HorizonSplit or Gtao); returns
// the G-buffer lookups made.
std::uint64_t horizonTexels(const CubeGBuffer& g, std::uint32_t probeIndex, const BakeSettings& s, Estimator estimator,
                            std::vector<float>& ao, std::vector<float>& confidence) {
    std::atomic<std::uint64_t> fetches{0};
    forEachTexel(g.res, [&](int face, int i, int j, std::size_t index) {
        const glm::vec4& texel = g.texels[index];
        if (CubeGBuffer::empty(texel)) return;
        const std::uint32_t key = texelKey(face, i, j, g.res, probeIndex, s.ao.seed);
        const glm::vec3 p = g.surfacePoint(face, i, j), n(texel);
        const HorizonEstimate e = estimator == Estimator::Gtao ? gtaoAo(g, p, n, s, key)
                                                               : horizonSplitAo(g, p, n, s, key);
        ao[index] = e.ao;
        confidence[index] = e.confidence;
        fetches.fetch_add(e.fetches, std::memory_order_relaxed);
    });
    return fetches.load();
}

}  // namespace

CubeGBuffer renderGBufferCpu(const EmbreeScene& scene, const glm::vec3& probe, int res) {
    if (res < 1) throw UsageError("cube G-buffer resolution " + std::to_string(res) + ": expected at least 1");
    CubeGBuffer g;
    g.res = res;
    g.probe = probe;
    g.texels.assign(g.texelCount(), glm::vec4(0.0f));
    const float inf = std::numeric_limits<float>::infinity();
    forEachTexel(res, [&](int face, int i, int j, std::size_t index) {
        const glm::vec3 dir = cube::texelDirection(face, i, j, res);
        const RayHit hit = scene.intersect(probe, dir, 0.0f, inf);
        if (!hit.hit) return;
        // Architecture is two-sided: keep the side the probe sees.
        const glm::vec3 n = glm::dot(hit.normal, dir) > 0.0f ? -hit.normal : hit.normal;
        g.texels[index] = glm::vec4(n, hit.t);
    });
    return g;
}

std::uint64_t traceTexelsCpu(const EmbreeScene& scene, const CubeGBuffer& g, std::uint32_t probeIndex,
                             const BakeSettings& settings, std::vector<float>& ao,
                             const std::vector<std::uint8_t>& only) {
    if (!only.empty() && only.size() != g.texelCount())
        throw Error("traceTexelsCpu: selection of " + std::to_string(only.size()) + " texels for a cube of " +
                    std::to_string(g.texelCount()));
    if (ao.size() != g.texelCount()) ao.assign(g.texelCount(), 1.0f);
    const auto selected = [&](std::size_t index) {
        return !CubeGBuffer::empty(g.texels[index]) && (only.empty() || only[index] != 0);
    };
    forEachTexel(g.res, [&](int face, int i, int j, std::size_t index) {
        if (!selected(index)) return;
        const std::uint32_t key = texelKey(face, i, j, g.res, probeIndex, settings.ao.seed);
        ao[index] = ambientOcclusion(scene, g.surfacePoint(face, i, j), glm::vec3(g.texels[index]), settings.ao, key).ao;
    });
    std::uint64_t traced = 0;
    for (std::size_t index = 0; index < g.texelCount(); ++index) traced += selected(index) ? 1 : 0;
    return traced * std::uint64_t(settings.ao.spp);
}

void denoiseAoCpu(const CubeGBuffer& g, int radius, float aoRadius, std::vector<float>& ao,
                  const std::vector<std::uint8_t>& only) {
    if (radius <= 0) return;
    if (ao.size() != g.texelCount() || (!only.empty() && only.size() != g.texelCount()))
        throw Error("denoiseAoCpu: " + std::to_string(ao.size()) + " AO values and " + std::to_string(only.size()) +
                    " selected for a cube of " + std::to_string(g.texelCount()) + " texels");
    struct Reader {
        const CubeGBuffer& g;
        const std::vector<float>& ao;
        glm::vec4 denoiseGBuffer(glm::ivec3 t) const { return g.texels[cube::texelIndex(t.z, t.x, t.y, g.res)]; }
        float denoiseAo(glm::ivec3 t) const { return ao[cube::texelIndex(t.z, t.x, t.y, g.res)]; }
    };
    const std::vector<float> before = ao;
    const Reader reader{g, before};
    forEachTexel(g.res, [&](int face, int i, int j, std::size_t index) {
        if (!only.empty() && only[index] == 0) return;
        ao[index] = kernel::aoDenoiseTexel(reader, glm::ivec3(i, j, face), g.res, g.probe, radius, aoRadius);
    });
}

BakedProbe bakeProbeCpu(const EmbreeScene& scene, const glm::vec3& probe, std::uint32_t probeIndex,
                        const BakeSettings& settings) {
    BakedProbe out;
    const Clock::time_point gbufferStart = Clock::now();
    out.gbuffer = renderGBufferCpu(scene, probe, settings.res);
    out.timings.gbufferMs = millisecondsSince(gbufferStart);

    const Clock::time_point aoStart = Clock::now();
    const CubeGBuffer& g = out.gbuffer;
    out.ao.assign(g.texelCount(), 1.0f);
    out.confidence.assign(g.texelCount(), 1.0f);
    const std::uint64_t surfaceTexels = nonEmptyTexels(g);
    switch (settings.estimator) {
        case Estimator::HorizonSplit:
        case Estimator::Gtao:
            out.fetches = horizonTexels(g, probeIndex, settings, settings.estimator, out.ao, out.confidence);
            break;
        case Estimator::Traced:
            out.rays = traceTexelsCpu(scene, g, probeIndex, settings, out.ao);
            out.tracedTexels = surfaceTexels;
            denoiseAoCpu(g, settings.denoise, settings.ao.radius, out.ao);
            break;
        case Estimator::Hybrid: {
            out.fetches = horizonTexels(g, probeIndex, settings, Estimator::HorizonSplit, out.ao, out.confidence);
            // Empty texels have confidence 1 and so are never selected; traced texels keep their
            // hsplit confidence, which shows where the hybrid traced.
            std::vector<std::uint8_t> trace(g.texelCount(), 0);
            for (std::size_t index = 0; index < trace.size(); ++index)
                trace[index] = out.confidence[index] < settings.hybridThreshold ? 1 : 0;
            out.rays = traceTexelsCpu(scene, g, probeIndex, settings, out.ao, trace);
            denoiseAoCpu(g, settings.denoise, settings.ao.radius, out.ao, trace);
            out.tracedTexels = out.rays / std::uint64_t(settings.ao.spp);
            break;
        }
    }
    out.timings.aoMs = millisecondsSince(aoStart);

    const Clock::time_point encodeStart = Clock::now();
    out.encoded = encodeProbeCpu(g, out.ao, out.confidence, settings);
    out.timings.encodeMs = millisecondsSince(encodeStart);  // includes the error measurement
    return out;
}

EncodedProbe encodeProbeCpu(const CubeGBuffer& g, const std::vector<float>& ao, const std::vector<float>& confidence,
                            const BakeSettings& settings) {
    if (ao.size() != g.texelCount() || confidence.size() != g.texelCount())
        throw Error("encodeProbeCpu: " + std::to_string(ao.size()) + " AO and " + std::to_string(confidence.size()) +
                    " confidence values for a cube of " + std::to_string(g.texelCount()) + " texels");
    EncodedProbe e;
    std::vector<glm::vec2> aoConfidence(g.texelCount());
    for (std::size_t t = 0; t < aoConfidence.size(); ++t) aoConfidence[t] = {ao[t], confidence[t]};
    e.aoConfidence = bc::encodeBc5Cube(aoConfidence, g.res);

    const std::vector<float> coarse = depth::downsample(g.texels, g.res, settings.depthRes, depth::kFilter);
    e.maxDistance = depth::maxDistance(coarse);
    e.depth = depth::encode(coarse, settings.depthFormat, e.maxDistance);

    std::vector<glm::vec2> decoded;
    bc::decodeBc5Cube(e.aoConfidence.data(), e.aoConfidence.size(), g.res, decoded);
    for (std::size_t t = 0; t < decoded.size(); ++t) {
        if (CubeGBuffer::empty(g.texels[t])) continue;
        const double d = double(decoded[t].x) - double(ao[t]);
        e.aoSquaredError += d * d;
        ++e.surfaceTexels;
    }
    appendLevels(e, aoConfidence, g, settings);
    return e;
}

void appendLevels(EncodedProbe& e, std::span<const glm::vec2> aoConfidence, const CubeGBuffer& g,
                  const BakeSettings& settings) {
    if (settings.levels <= 1) return;
    std::vector<float> distances(g.texelCount());
    for (std::size_t t = 0; t < distances.size(); ++t) distances[t] = g.texels[t].w;
    const std::vector<std::uint8_t> ao = levels::coarserAo(aoConfidence, distances, g.res, settings.levels);
    const std::vector<std::uint8_t> depth =
        levels::coarserDistances(e.depth, settings.depthRes, settings.depthFormat, settings.levels);
    e.aoConfidence.insert(e.aoConfidence.end(), ao.begin(), ao.end());
    e.depth.insert(e.depth.end(), depth.begin(), depth.end());
}

BakeSettings verifyReferenceSettings(const BakeSettings& bake, int spp) {
    if (spp < 0) throw UsageError("--verify-spp " + std::to_string(spp) + ": expected a positive number of rays");
    BakeSettings reference = bake;
    reference.ao.seed = bake.ao.seed ^ kVerifySeedSalt;
    reference.ao.spp = spp > 0 ? spp : kVerifyRayFactor * bake.ao.spp;
    reference.denoise = 0;  // the truth as well as rays tell it: what the filter costs is part of the error
    return reference;
}

VerifyResult verifyProbe(const EmbreeScene& scene, const BakedProbe& probe, std::uint32_t probeIndex,
                         const BakeSettings& settings) {
    const CubeGBuffer& g = probe.gbuffer;
    if (probe.ao.size() != g.texelCount())
        throw Error("verifyProbe: " + std::to_string(probe.ao.size()) + " AO values for a cube of " +
                    std::to_string(g.texelCount()) + " texels");
    std::vector<float> reference(g.texelCount(), 1.0f);
    std::vector<double> noise(g.texelCount(), 0.0);
    forEachTexel(g.res, [&](int face, int i, int j, std::size_t index) {
        const glm::vec4& texel = g.texels[index];
        if (CubeGBuffer::empty(texel)) return;
        const std::uint32_t key = texelKey(face, i, j, g.res, probeIndex, settings.ao.seed);
        const AoEstimate estimate = ambientOcclusion(scene, g.surfacePoint(face, i, j), glm::vec3(texel), settings.ao, key);
        reference[index] = estimate.ao;
        noise[index] = estimate.stdError;
    });
    denoiseAoCpu(g, settings.denoise, settings.ao.radius, reference);  // the twin filters as the bake did
    // Summed in texel order, not per thread, so the MAE is the same on any number of cores.
    VerifyResult result;
    double sum = 0.0, noiseSum = 0.0;
    for (std::size_t index = 0; index < g.texelCount(); ++index) {
        if (CubeGBuffer::empty(g.texels[index])) continue;
        sum += std::abs(double(probe.ao[index]) - double(reference[index]));
        noiseSum += noise[index];
        ++result.texels;
    }
    result.mae = result.texels ? sum / double(result.texels) : 0.0;
    result.noise = result.texels ? noiseSum / double(result.texels) : 0.0;
    return result;
}

}  // namespace cubeao

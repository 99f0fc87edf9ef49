#include "cubeao/reference/ao_reference.h"

#include <tbb/blocked_range2d.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>
#include <string>

#include "cubeao/core/error.h"
#include "cubeao/core/progress.h"
#include "cubeao/core/sampling.h"

namespace cubeao {

AoEstimate ambientOcclusion(const EmbreeScene& scene, const glm::vec3& p, const glm::vec3& n,
                            const AoSettings& settings, std::uint32_t key) {
    const float radius = settings.radius;
    const glm::vec3 org = p + scene.surfaceEpsilon() * n;
    const auto count = std::uint32_t(settings.spp);
    double sum = 0.0, sumSq = 0.0;
    for (std::uint32_t i = 0; i < count; ++i) {
        const glm::vec3 dir = sampling::cosineHemisphere(sampling::rotatedHammersley(i, count, key), n);
        float w = 0.0f;
        if (settings.falloff == Falloff::None) {
            w = scene.occluded(org, dir, 0.0f, radius) ? 1.0f : 0.0f;
        } else {
            const RayHit hit = scene.intersect(org, dir, 0.0f, radius);
            w = hit.hit ? occlusionWeight(settings.falloff, hit.t, radius) : 0.0f;
        }
        sum += w;
        sumSq += double(w) * w;
    }
    const double mean = sum / count;
    const double var = count > 1 ? std::max(0.0, (sumSq - sum * mean) / (count - 1)) : 0.0;
    return {float(1.0 - mean), float(std::sqrt(var / count))};
}

ReferenceFrame renderReferenceFrame(const EmbreeScene& scene, const PinholeCamera& cam, const AoSettings& settings,
                                    std::uint32_t frameIndex, Progress* progress, int replicas, int aa) {
    if (settings.spp < 1) throw UsageError("--spp must be at least 1");
    if (!(settings.radius > 0.0f)) throw UsageError("--radius must be positive");
    if (replicas < 1 || settings.spp % replicas != 0)
        throw UsageError("--replicas " + std::to_string(replicas) + ": must be at least 1 and divide --spp " +
                         std::to_string(settings.spp));
    if (aa < 1 || settings.spp % (aa * aa * replicas) != 0)
        throw UsageError("--aa " + std::to_string(aa) + ": --spp " + std::to_string(settings.spp) +
                         " must be a multiple of aa² × replicas = " + std::to_string(aa * aa * replicas));
    ReferenceFrame out;
    out.ao.width = cam.width;
    out.ao.height = cam.height;
    out.ao.pixels.assign(std::size_t(cam.width) * std::size_t(cam.height), 1.0f);
    // Per pixel: the independent-ray standard error (1 replica) or the variance of the mean (≥ 2).
    std::vector<float> spread(out.ao.pixels.size(), 0.0f);
    tbb::combinable<std::uint64_t> background([] { return std::uint64_t(0); });      // sub-samples
    tbb::combinable<std::uint64_t> emptyPixels([] { return std::uint64_t(0); });     // no sub-sample hit
    const std::uint32_t frameKey = frameIndex ^ settings.seed;
    const int subSamples = aa * aa;
    AoSettings perSub = settings;  // one sub-sample's rays
    perSub.spp = settings.spp / subSamples;
    AoSettings perReplica = perSub;
    perReplica.spp = perSub.spp / replicas;

    // One primary ray through image position (px, py) and its AO: the value, and its spread as above;
    // false when the ray sees no geometry.
    auto sample = [&](float px, float py, std::uint32_t key, float& ao, float& err) {
        const glm::vec3 dir = cam.rayDirectionAt(px, py);
        const RayHit hit = scene.intersect(cam.eye, dir, 0.0f, std::numeric_limits<float>::infinity());
        if (!hit.hit) return false;
        // Open architecture is two-sided: evaluate the side the camera sees.
        const glm::vec3 n = glm::dot(hit.normal, dir) > 0.0f ? -hit.normal : hit.normal;
        const glm::vec3 p = cam.eye + hit.t * dir;
        if (replicas == 1) {
            const AoEstimate e = ambientOcclusion(scene, p, n, perSub, key);
            ao = e.ao;
            err = e.stdError;
            return true;
        }
        double sum = 0.0, sumSq = 0.0;
        for (int k = 0; k < replicas; ++k) {
            const std::uint32_t replicaKey = k == 0 ? key : sampling::hashKey(key, std::uint32_t(k), 0x5eedu);
            const double v = ambientOcclusion(scene, p, n, perReplica, replicaKey).ao;
            sum += v;
            sumSq += v * v;
        }
        const double mean = sum / replicas;
        const double variance = std::max(0.0, (sumSq - sum * mean) / (replicas - 1));
        ao = float(mean);
        err = float(variance / replicas);
        return true;
    };

    tbb::parallel_for(tbb::blocked_range2d<int>(0, cam.height, 8, 0, cam.width, 8), [&](const auto& r) {
        for (int y = r.rows().begin(); y < r.rows().end(); ++y)
            for (int x = r.cols().begin(); x < r.cols().end(); ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(cam.width) + std::size_t(x);
                const std::uint32_t key = sampling::hashKey(std::uint32_t(x), std::uint32_t(y), frameKey);
                if (aa == 1) {
                    if (!sample(float(x) + 0.5f, float(y) + 0.5f, key, out.ao.pixels[i], spread[i])) {
                        ++background.local();
                        ++emptyPixels.local();
                    }
                    continue;
                }
                // N×N cells, one jittered primary ray in each, box filter. The pixel's spread: with
                // replicas, the replica variances of independent sub-samples add and divide by (N²)²; with
                // one replica, the standard error of the mean of the N² sub-sample values (their sample
                // variance / N²: an independent-sample bound, like the one-replica bound above, and
                // defined when a sub-sample traces a single AO ray).
                double sum = 0.0, sumSq = 0.0, replicaSpread = 0.0;
                int hits = 0;
                for (int s = 0; s < subSamples; ++s) {
                    const std::uint32_t subKey = sampling::hashKey(key, std::uint32_t(s), 0xaa5eedu);
                    const float jx = sampling::toUnitFloat(sampling::hashKey(subKey, 1u, 0u));
                    const float jy = sampling::toUnitFloat(sampling::hashKey(subKey, 2u, 0u));
                    float ao = 1.0f, err = 0.0f;
                    if (sample(float(x) + (float(s % aa) + jx) / float(aa), float(y) + (float(s / aa) + jy) / float(aa),
                               subKey, ao, err)) {
                        ++hits;
                        replicaSpread += double(err);
                    } else {
                        ++background.local();
                    }
                    sum += ao;
                    sumSq += double(ao) * ao;
                }
                const double mean = sum / subSamples;
                out.ao.pixels[i] = float(mean);
                if (replicas == 1) {
                    const double variance = std::max(0.0, (sumSq - sum * mean) / (subSamples - 1));
                    spread[i] = float(std::sqrt(variance / subSamples));
                } else {
                    spread[i] = float(replicaSpread / (double(subSamples) * double(subSamples)));
                }
                if (hits == 0) ++emptyPixels.local();
            }
        if (progress) progress->advance(std::uint64_t(r.rows().size()) * std::uint64_t(r.cols().size()));
    });

    const std::uint64_t bg = background.combine(std::plus<>());  // sub-samples that saw no geometry
    const std::uint64_t empty = emptyPixels.combine(std::plus<>());
    const std::uint64_t pixels = out.ao.pixels.size();
    double spreadSum = 0.0;
    for (float e : spread) spreadSum += e;
    const double meanSpread = pixels > empty ? spreadSum / double(pixels - empty) : 0.0;  // over pixels with geometry
    out.noise = replicas == 1 ? meanSpread : std::sqrt(meanSpread);
    const std::uint64_t samples = pixels * std::uint64_t(subSamples);
    out.backgroundFraction = samples ? double(bg) / double(samples) : 0.0;
    out.aoRays = (samples - bg) * std::uint64_t(perSub.spp);
    return out;
}

}  // namespace cubeao

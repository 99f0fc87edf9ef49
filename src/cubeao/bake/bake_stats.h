// What a bake collects from every probe it bakes (bake_driver.h), and the rates `bake` and `bench
// bake` both report from it under the same names.
#pragma once

#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "cubeao/bake/bake.h"

namespace cubeao {

struct BakeStats {
    // ms per probe, by stage. `total` is the wall clock around the whole bake of a probe; the stages
    // are the baker's own (BakedProbe::timings): on the GPU path only when timings were asked for
    // (ProbeBakerOptions::timings), 0 otherwise.
    std::vector<double> total, gbuffer, ao, encode, error, readback;
    std::vector<double> encodeToAo;                                   // encode ms / AO ms, probes with AO time
    std::uint64_t surface = 0, traced = 0, rays = 0, fetches = 0;     // texels, texels, rays, G-buffer lookups
    double rayMs = 0.0;                                               // AO ms (else total ms) of the probes that cast rays
    double squaredError = 0.0;                                        // BC5 AO squared error, summed over texels

    void add(const BakedProbe& p, double ms) {
        total.push_back(ms);
        gbuffer.push_back(p.timings.gbufferMs);
        ao.push_back(p.timings.aoMs);
        encode.push_back(p.timings.encodeMs);
        error.push_back(p.timings.errorMs);
        readback.push_back(p.timings.readbackMs);
        if (p.timings.aoMs > 0.0) encodeToAo.push_back(p.timings.encodeMs / p.timings.aoMs);
        surface += p.encoded.surfaceTexels;
        traced += p.tracedTexels;
        rays += p.rays;
        fetches += p.fetches;
        if (p.rays) rayMs += p.timings.aoMs > 0.0 ? p.timings.aoMs : ms;  // no stage timings: the whole probe
        squaredError += p.encoded.aoSquaredError;
    }

    std::size_t probes() const { return total.size(); }
    // Per surface texel: rays, traced and fetches only ever count surface texels, so 0 for none.
    double perTexel(std::uint64_t v) const { return surface ? double(v) / double(surface) : 0.0; }
    // Rays per second of AO time (of bake time where stages were not timed), over the probes that
    // cast rays (0 for none).
    double raysPerS() const { return rayMs > 0.0 ? double(rays) / (rayMs * 1e-3) : 0.0; }

    // The quality and throughput fields both commands print under the same names.
    nlohmann::json ratesJson() const {
        return {{"ao_psnr", aoPsnr(squaredError, surface)},
                {"traced_fraction", perTexel(traced)},
                {"rays_per_s", raysPerS()},
                {"rays_per_texel", perTexel(rays)},
                {"fetches_per_texel", perTexel(fetches)}};
    }
};

}  // namespace cubeao

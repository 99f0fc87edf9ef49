// BC4 reference encoder and decoder (format in bc4.h). GLSL twin of the encoder:
// shaders/bake/bc5_encode.comp; tests/test_bc.cpp checks that the two produce identical blocks.
//
// The encoder works in integer "units" of 1/8925 = 1/(255·35): every level of both modes,
// (a·red_0 + b·red_1)/(255·7) and /(255·5), is then a whole number of units, so levels, errors and
// the least-squares solve are exact integer arithmetic and give the same result on any CPU or GPU.
// Inputs are rounded to units once (error ≤ 1/17850, far below the 1/510 that even an ideal 8-level
// block leaves on a smooth ramp). Squared errors of a block fit in 32 bits: 16 · 8925² < 2^31.
//
// Per mode (8 levels: lo = red_1 < hi = red_0; 6 levels + 0 and 1: lo = red_0 <= hi = red_1):
//  1. starts: the block's range [min, max] mapped onto levels k0..k1 of the ramp for every
//     0 <= k0 < k1 <= last (sweepRange); in the 6-level mode also with the values nearest 0 or 1
//     left to the explicit 0 and 1 (sixLevelEnds);
//  2. from the best start, up to kLeastSquaresRounds rounds: each texel takes its nearest level,
//     then the endpoints that minimise the squared error for those codes (2×2 normal equations);
//  3. steepest descent over the 8 neighbours (lo ± 1, hi ± 1), at most kDescentSteps moves.
// The mode with the smaller error wins (the 8-level mode on a tie); an exact fit stops early.
// Without the starts of step 1, a ramp of 4 evenly spaced values ends in a local minimum some
// 20 dB worse. On the test images (tests/test_bc.cpp) the result is within ~0.4 dB of an
// exhaustive search over all 65536 endpoint pairs on random 4×4 noise, and 10-20 dB better than
// libsquish's range fit on smooth ramps. Step 3 costs ~25% of the time and gives up to 5 dB on
// smooth data.
#include "cubeao/cache/bc4.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace cubeao::bc {

namespace {

constexpr int kUnits = 8925;  // 1.0 in units: 255 · 35
constexpr int kLeastSquaresRounds = 2;
constexpr int kDescentSteps = 8;

struct Endpoints {
    int lo = 0, hi = 0;  // unorm8; 8-level mode: lo < hi, 6-level mode: lo <= hi
};

// One texel's best code, its position on the ramp (0 = lo; -1 for the explicit 0 and 1 of the
// 6-level mode) and its squared error in units².
struct TexelFit {
    int code = 0;
    int step = 0;
    std::uint32_t error = 0;
};

int quantise(float v) {
    if (!(v > 0.0f)) return 0;  // also NaN
    if (v >= 1.0f) return kUnits;
    return int(std::nearbyint(v * float(kUnits)));  // round half to even, as GLSL roundEven
}

// The levels base + k·span, k = 0..last, of one mode and pair of endpoints, in units.
struct Ramp {
    bool eight = true;
    int base = 0, span = 0, last = 7;
    float inverseSpan = 0.0f;  // for a first guess only (nearestStep)
};

Ramp makeRamp(bool eight, Endpoints e) {
    const int span = (e.hi - e.lo) * (eight ? 5 : 7);
    return {eight, e.lo * 35, span, eight ? 7 : 5, span > 0 ? 1.0f / float(span) : 0.0f};
}

// Nearest level, ties going up. The float guess is within one level of it (the quotient is below
// 256 with a relative error of a few ulp, in C++ and GLSL alike), and one exact integer comparison
// on each side settles it, so CPU and GPU agree although their divisions may round differently.
// This spares an integer division per texel and candidate, which llvmpipe does lane by lane.
int nearestStep(const Ramp& r, int q) {
    const int d = q - r.base;
    if (d <= 0 || r.span == 0) return 0;
    int k = std::min(int(float(d) * r.inverseSpan + 0.5f), r.last);
    const auto distance = [&](int step) { return std::abs(d - step * r.span); };  // V-shaped in step
    if (k < r.last && distance(k + 1) <= distance(k))
        ++k;
    else if (k > 0 && distance(k - 1) < distance(k))
        --k;
    return k;
}

TexelFit fitTexel(const Ramp& r, int q) {
    const int k = nearestStep(r, q), d = q - (r.base + k * r.span);
    if (r.eight) return {k == 0 ? 1 : k == 7 ? 0 : 8 - k, k, std::uint32_t(d * d)};  // code i: red_0 weight 8 − i
    TexelFit fit{k == 0 ? 0 : k == 5 ? 1 : k + 1, k, std::uint32_t(d * d)};           // code i: red_1 weight i − 1
    const std::uint32_t toZero = std::uint32_t(q * q), toOne = std::uint32_t((kUnits - q) * (kUnits - q));
    if (toZero < fit.error) fit = {6, -1, toZero};
    if (toOne < fit.error) fit = {7, -1, toOne};
    return fit;
}

std::uint32_t blockError(bool eight, Endpoints e, const int q[16]) {
    const Ramp r = makeRamp(eight, e);
    std::uint32_t sum = 0;
    for (int t = 0; t < 16; ++t) sum += fitTexel(r, q[t]).error;
    return sum;
}

bool valid(bool eight, Endpoints e) { return e.lo >= 0 && e.hi <= 255 && (eight ? e.lo < e.hi : e.lo <= e.hi); }

// Clamps to unorm8, orders, and separates equal endpoints in the 8-level mode.
Endpoints normalise(bool eight, Endpoints e) {
    e.lo = std::clamp(e.lo, 0, 255);
    e.hi = std::clamp(e.hi, 0, 255);
    if (e.lo > e.hi) std::swap(e.lo, e.hi);
    if (eight && e.lo == e.hi) {
        if (e.hi < 255)
            ++e.hi;
        else
            --e.lo;
    }
    return e;
}

// num / den rounded to nearest, half away from zero (den > 0); exact for the magnitudes here.
int roundDiv(int num, int den) { return num >= 0 ? (2 * num + den) / (2 * den) : -((-2 * num + den) / (2 * den)); }

// Least-squares endpoints for the codes the texels take with e: q ≈ scale·((last − k)·lo + k·hi)
// over the ramp texels (scale = units per unorm8 step per level). False when the system is singular.
bool leastSquares(bool eight, Endpoints e, const int q[16], Endpoints& out) {
    const int last = eight ? 7 : 5, scale = eight ? 5 : 7;
    const Ramp r = makeRamp(eight, e);
    int saa = 0, sab = 0, sbb = 0, saq = 0, sbq = 0;  // |sums| ≤ 16·7·8925 < 2^20
    for (int t = 0; t < 16; ++t) {
        const int k = fitTexel(r, q[t]).step;
        if (k < 0) continue;
        const int a = last - k, b = k;
        saa += a * a, sab += a * b, sbb += b * b, saq += a * q[t], sbq += b * q[t];
    }
    const int det = saa * sbb - sab * sab;  // ≤ 784²
    if (det <= 0) return false;
    // Cramer's rule; products ≤ 784 · 999600 < 2^30.
    out = normalise(eight, {roundDiv(sbb * saq - sab * sbq, scale * det), roundDiv(saa * sbq - sab * saq, scale * det)});
    return true;
}

struct ModeFit {
    Endpoints e;
    std::uint32_t error = 0;
};

// Starts that map [qmin, qmax] onto levels k0..k1 of the ramp, not always all of them: four evenly
// spaced values, say, sit exactly on levels 1, 3, 5, 7 of a ramp that starts below qmin. k0 = 0,
// k1 = last (the plain range fit) comes first.
void sweepRange(bool eight, int qmin, int qmax, const int q[16], ModeFit& best) {
    const int last = eight ? 7 : 5, range = qmax - qmin;
    for (int n = last; n >= 1; --n)  // the range spans n level steps, starting at level k0
        for (int k0 = 0; k0 + n <= last; ++k0) {
            const Endpoints e = normalise(eight, {roundDiv(qmin * n - k0 * range, 35 * n),
                                                  roundDiv(qmin * n + (last - k0) * range, 35 * n)});
            const std::uint32_t error = blockError(eight, e, q);
            if (error < best.error) best = {e, error};
            if (range == 0) return;  // every (k0, n) gives the same endpoints
        }
}

// Ends of the ramp for the 6-level mode. The plain ones leave out only exact 0s and 1s; the split
// ones also leave out values the explicit 0 (1) serves better than the ramp would: the low end is
// the smallest u with every smaller value ≤ u/2 (at least one of them nonzero), the high end likewise.
struct RampEnds {
    int low, high, splitLow, splitHigh;
};

RampEnds sixLevelEnds(const int q[16]) {
    RampEnds r{kUnits, 0, kUnits, 0};
    for (int t = 0; t < 16; ++t) {
        if (q[t] == 0 || q[t] == kUnits) continue;
        r.low = std::min(r.low, q[t]);
        r.high = std::max(r.high, q[t]);
        int below = 0, above = kUnits;  // nearest values below and above q[t], other than 0 and 1
        for (int s = 0; s < 16; ++s) {
            if (q[s] > 0 && q[s] < q[t]) below = std::max(below, q[s]);
            if (q[s] < kUnits && q[s] > q[t]) above = std::min(above, q[s]);
        }
        if (below > 0 && 2 * below <= q[t]) r.splitLow = std::min(r.splitLow, q[t]);
        if (above < kUnits && 2 * (kUnits - above) <= kUnits - q[t]) r.splitHigh = std::max(r.splitHigh, q[t]);
    }
    if (r.low > r.high) r.low = r.high = 0;  // only 0s and 1s: any ramp will do
    if (r.splitLow > r.high) r.splitLow = r.low;
    if (r.splitHigh < r.low) r.splitHigh = r.high;
    return r;
}

ModeFit fitMode(bool eight, const int q[16]) {
    ModeFit best{{}, ~std::uint32_t(0)};
    if (eight) {
        int qmin = kUnits, qmax = 0;
        for (int t = 0; t < 16; ++t) qmin = std::min(qmin, q[t]), qmax = std::max(qmax, q[t]);
        sweepRange(true, qmin, qmax, q, best);
    } else {
        const RampEnds r = sixLevelEnds(q);
        sweepRange(false, r.low, r.high, q, best);
        if (r.splitLow != r.low && r.splitLow <= r.high) sweepRange(false, r.splitLow, r.high, q, best);
        if (r.splitHigh != r.high && r.low <= r.splitHigh) sweepRange(false, r.low, r.splitHigh, q, best);
        if ((r.splitLow != r.low || r.splitHigh != r.high) && r.splitLow <= r.splitHigh)
            sweepRange(false, r.splitLow, r.splitHigh, q, best);
    }
    if (best.error == 0) return best;

    for (int round = 0; round < kLeastSquaresRounds; ++round) {
        Endpoints e;
        if (!leastSquares(eight, best.e, q, e)) break;
        const std::uint32_t error = blockError(eight, e, q);
        if (error >= best.error) break;
        best = {e, error};
    }
    for (int step = 0; step < kDescentSteps; ++step) {
        ModeFit next = best;
        for (int dl = -1; dl <= 1; ++dl)
            for (int dh = -1; dh <= 1; ++dh) {
                const Endpoints e{best.e.lo + dl, best.e.hi + dh};
                if ((dl == 0 && dh == 0) || !valid(eight, e)) continue;
                const std::uint32_t error = blockError(eight, e, q);
                if (error < next.error) next = {e, error};
            }
        if (next.error >= best.error) break;
        best = next;
    }
    return best;
}

std::uint64_t packBlock(bool eight, Endpoints e, const int q[16]) {
    const std::uint64_t red0 = std::uint64_t(eight ? e.hi : e.lo), red1 = std::uint64_t(eight ? e.lo : e.hi);
    const Ramp r = makeRamp(eight, e);
    std::uint64_t block = red0 | red1 << 8;
    for (int t = 0; t < 16; ++t) block |= std::uint64_t(fitTexel(r, q[t]).code) << (16 + 3 * t);
    return block;
}

bool validRes(int res) { return res > 0 && res <= kMaxRes && res % kBlockSize == 0; }

void checkRes(int res) {
    if (!validRes(res))
        throw std::invalid_argument("BC5 cube: face resolution " + std::to_string(res) + " is not a multiple of 4 in [4, " +
                                    std::to_string(kMaxRes) + "]");
}

}  // namespace

std::uint64_t encodeBc4Block(const float values[16]) {
    int q[16];
    for (int t = 0; t < 16; ++t) q[t] = quantise(values[t]);
    const ModeFit eight = fitMode(true, q);
    if (eight.error == 0) return packBlock(true, eight.e, q);
    const ModeFit six = fitMode(false, q);
    return six.error < eight.error ? packBlock(false, six.e, q) : packBlock(true, eight.e, q);
}

void decodeBc4Block(std::uint64_t block, float out[16]) {
    const int red0 = int(block & 0xFF), red1 = int(block >> 8 & 0xFF);
    float levels[8] = {float(red0) / 255.0f, float(red1) / 255.0f};
    if (red0 > red1) {
        for (int i = 2; i < 8; ++i) levels[i] = float((8 - i) * red0 + (i - 1) * red1) / 1785.0f;  // 255 · 7
    } else {
        for (int i = 2; i < 6; ++i) levels[i] = float((6 - i) * red0 + (i - 1) * red1) / 1275.0f;  // 255 · 5
        levels[6] = 0.0f;
        levels[7] = 1.0f;
    }
    for (int t = 0; t < 16; ++t) out[t] = levels[block >> (16 + 3 * t) & 7];
}

std::size_t bc5Size(int res) {
    checkRes(res);
    const std::size_t blocksPerSide = std::size_t(res / kBlockSize);
    return 6 * blocksPerSide * blocksPerSide * kBc5Bytes;
}

std::vector<std::uint8_t> encodeBc5Cube(const std::vector<glm::vec2>& aoConfidence, int res) {
    const std::size_t size = bc5Size(res), texels = 6 * std::size_t(res) * std::size_t(res);
    if (aoConfidence.size() != texels)
        throw std::invalid_argument("BC5 cube: " + std::to_string(aoConfidence.size()) + " texels given, " +
                                    std::to_string(texels) + " expected for res " + std::to_string(res));
    std::vector<std::uint8_t> out(size);
    std::uint8_t* dst = out.data();
    const int blocksPerSide = res / kBlockSize;
    for (int face = 0; face < 6; ++face)
        for (int by = 0; by < blocksPerSide; ++by)
            for (int bx = 0; bx < blocksPerSide; ++bx) {
                float red[16], green[16];
                for (int y = 0; y < 4; ++y)
                    for (int x = 0; x < 4; ++x) {
                        const glm::vec2 v = aoConfidence[(std::size_t(face) * std::size_t(res) + std::size_t(4 * by + y)) *
                                                             std::size_t(res) + std::size_t(4 * bx + x)];
                        red[4 * y + x] = v.x;
                        green[4 * y + x] = v.y;
                    }
                for (const std::uint64_t block : {encodeBc4Block(red), encodeBc4Block(green)})
                    for (int b = 0; b < 8; ++b) *dst++ = std::uint8_t(block >> (8 * b));
            }
    return out;
}

bool decodeBc5Cube(const std::uint8_t* data, std::size_t size, int res, std::vector<glm::vec2>& out) {
    if (!validRes(res) || data == nullptr || size != bc5Size(res)) return false;
    out.resize(6 * std::size_t(res) * std::size_t(res));
    const int blocksPerSide = res / kBlockSize;
    const std::uint8_t* src = data;
    for (int face = 0; face < 6; ++face)
        for (int by = 0; by < blocksPerSide; ++by)
            for (int bx = 0; bx < blocksPerSide; ++bx) {
                float channels[2][16];
                for (float* channel : channels) {
                    std::uint64_t block = 0;
                    for (int b = 0; b < 8; ++b) block |= std::uint64_t(*src++) << (8 * b);
                    decodeBc4Block(block, channel);
                }
                for (int y = 0; y < 4; ++y)
                    for (int x = 0; x < 4; ++x)
                        out[(std::size_t(face) * std::size_t(res) + std::size_t(4 * by + y)) * std::size_t(res) +
                            std::size_t(4 * bx + x)] = {channels[0][4 * y + x], channels[1][4 * y + x]};
            }
    return true;
}

}  // namespace cubeao::bc

// BC4 (RGTC1, unsigned) blocks, written once for the CPU encoder and decoder (src/cubeao/cache/bc4.cpp,
// public API and the block format in src/cubeao/cache/bc4.h) and the GPU bake's passes
// (shaders/bake/bc5_encode.comp, shaders/bake/bc5_error.comp); tests/cache/test_bc.cpp checks that both
// compilations give the same blocks, bit for bit.
//
// Levels (EXT_texture_compression_rgtc = OpenGL 4.5 core, appendix C.1): with R0 = red_0/255,
// R1 = red_1/255, code 0 → R0, 1 → R1, and
//   red_0 >  red_1: i = 2..7 → ((8−i)·R0 + (i−1)·R1) / 7   (8 levels)
//   red_0 <= red_1: i = 2..5 → ((6−i)·R0 + (i−1)·R1) / 5, 6 → 0, 7 → 1
// A block is 64 bits, little-endian, here as two 32-bit words (x: bits 0-31, y: bits 32-63): red_0,
// red_1, then texel t = 4y + x's code at bits 16 + 3t.
//
// The encoder works in integer "units" of 1/8925 = 1/(255·35): every level of both modes,
// (a·red_0 + b·red_1)/(255·7) and /(255·5), is then a whole number of units (bc4LevelUnits), so
// levels, errors and the least-squares solve are exact integer arithmetic and give the same result
// on any CPU or GPU. Inputs are rounded to units once (error ≤ 1/17850, far below the 1/510 that even
// an ideal 8-level block leaves on a smooth ramp). Squared errors of a block fit in 32 bits:
// 16 · 8925² < 2^31.
//
// Per mode (8 levels: lo = red_1 < hi = red_0; 6 levels + 0 and 1: lo = red_0 <= hi = red_1), on the
// ramp of levels lo .. hi in order ("steps" k = 0..last):
//  1. starts: the block's range [min, max] mapped onto steps k0..k1 of the ramp for every
//     0 <= k0 < k1 <= last (bc4SweepRange); in the 6-level mode also with the values nearest 0 or 1
//     left to the explicit 0 and 1 (bc4SixLevelEnds);
//  2. from the best start, up to kBc4LeastSquaresRounds rounds: each texel takes its nearest level,
//     then the endpoints that minimise the squared error for those codes (2×2 normal equations);
//  3. steepest descent over the 8 neighbours (lo ± 1, hi ± 1), at most kBc4DescentSteps moves.
// The mode with the smaller error wins (the 8-level mode on a tie); an exact fit stops early.
// Without the starts of step 1, a ramp of 4 evenly spaced values ends in a local minimum some
// 20 dB worse. On the test images (tests/cache/test_bc.cpp) the result is within ~0.4 dB of an
// exhaustive search over all 65536 endpoint pairs on random 4×4 noise, and 10-20 dB better than
// libsquish's range fit on smooth ramps. Step 3 costs ~25% of the time and gives up to 5 dB on
// smooth data.
//
// A block's texels are passed as `const int q[16]` (units, row-major q[4y + x]): a pointer in C++, a
// copy in GLSL that the compiler removes when it inlines (every call here is inlined).
#pragma once

#include "glsl_cpp.h"

CUBEAO_KERNEL_BEGIN

CUBEAO_CONST int kBc4BlockSize = 4;     // texels per block side
CUBEAO_CONST int kBc4Texels = 16;
CUBEAO_CONST int kBc4Units = 8925;      // 1.0 in units: 255 · 35
CUBEAO_CONST int kBc4LeastSquaresRounds = 2;
CUBEAO_CONST int kBc4DescentSteps = 8;

// Level `code` (0..7) of a block with endpoints red0, red1 (unorm8), in units: exact.
CUBEAO_FN int bc4LevelUnits(int red0, int red1, int code) {
    if (code == 0) return 35 * red0;
    if (code == 1) return 35 * red1;
    if (red0 > red1) return 5 * ((8 - code) * red0 + (code - 1) * red1);
    if (code == 6) return 0;
    if (code == 7) return kBc4Units;
    return 7 * ((6 - code) * red0 + (code - 1) * red1);
}

// The decoded level as float: the nearest float to the exact rational where division is correctly
// rounded (C++; GLSL's may be off in the last bit). units / 8925 is the same rational as the
// format's red_0 / 255, n / (255·7) or n / (255·5), so this is the float the formulas give.
CUBEAO_FN float bc4Level(int red0, int red1, int code) {
    return float(bc4LevelUnits(red0, red1, code)) / float(kBc4Units);
}

// Code of texel t (0..15) in a block's two words.
CUBEAO_FN int bc4Code(uvec2 words, int t) {
    int bit = 16 + 3 * t;  // ≥ 16: the shifts below stay in 1..31
    uint v = bit < 32 ? (words.x >> uint(bit)) | (words.y << uint(32 - bit)) : words.y >> uint(bit - 32);
    return int(v & 7u);
}

// An input value in units; clamped to [0, 1], and NaN counts as 0 in C++ (GLSL leaves comparisons
// with NaN undefined: there a NaN gives an unspecified level). Rounds half to even.
CUBEAO_FN int bc4Quantise(float v) {
    if (!(v > 0.0f)) return 0;
    if (v >= 1.0f) return kBc4Units;
    return int(roundEven(v * float(kBc4Units)));
}

// Endpoints (lo, hi) of a mode → (red_0, red_1): the 8-level mode stores hi first.
CUBEAO_FN ivec2 bc4Reds(bool eight, ivec2 e) { return eight ? ivec2(e.y, e.x) : e; }

// Step k of the ramp (0 = lo .. last = hi) → code: 8-level codes 1, 7, 6, .., 2, 0; 6-level 0, 2, .., 5, 1.
CUBEAO_FN int bc4CodeOfStep(bool eight, int k) {
    if (eight) return k == 0 ? 1 : k == 7 ? 0 : 8 - k;
    return k == 0 ? 0 : k == 5 ? 1 : k + 1;
}

// The ramp of one mode and endpoints: levels base + k·span, k = 0..last, in units (the levels of
// bc4LevelUnits in step order: they are evenly spaced).
struct Bc4Ramp {
    bool eight;
    int base;
    int span;
    int last;
    float inverseSpan;  // for a first guess only (bc4NearestStep)
};

CUBEAO_FN Bc4Ramp bc4MakeRamp(bool eight, ivec2 e) {
    ivec2 reds = bc4Reds(eight, e);
    int base = bc4LevelUnits(reds.x, reds.y, bc4CodeOfStep(eight, 0));
    int span = bc4LevelUnits(reds.x, reds.y, bc4CodeOfStep(eight, 1)) - base;
    return Bc4Ramp(eight, base, span, eight ? 7 : 5, span > 0 ? 1.0f / float(span) : 0.0f);
}

// Nearest step, ties going up. The float guess is within one step of it (the quotient is below 256
// with a relative error of a few ulp, in C++ and GLSL alike), and one exact integer comparison on
// each side settles it, so CPU and GPU agree although their divisions may round differently. This
// spares an integer division per texel and candidate, which llvmpipe does lane by lane.
CUBEAO_FN int bc4NearestStep(Bc4Ramp r, int v) {
    int d = v - r.base;
    if (d <= 0 || r.span == 0) return 0;
    int k = min(int(float(d) * r.inverseSpan + 0.5f), r.last);
    if (k < r.last && abs(d - (k + 1) * r.span) <= abs(d - k * r.span))  // V-shaped in k
        ++k;
    else if (k > 0 && abs(d - (k - 1) * r.span) < abs(d - k * r.span))
        --k;
    return k;
}

// One texel's best code, its step on the ramp (-1 for the explicit 0 and 1 of the 6-level mode) and
// its squared error in units².
struct Bc4TexelFit {
    int code;
    int step;
    uint error;
};

CUBEAO_FN Bc4TexelFit bc4FitTexel(Bc4Ramp r, int v) {
    int k = bc4NearestStep(r, v), d = v - (r.base + k * r.span);
    if (r.eight) return Bc4TexelFit(bc4CodeOfStep(true, k), k, uint(d * d));
    Bc4TexelFit fit = Bc4TexelFit(bc4CodeOfStep(false, k), k, uint(d * d));
    uint toZero = uint(v * v), toOne = uint((kBc4Units - v) * (kBc4Units - v));
    if (toZero < fit.error) fit = Bc4TexelFit(6, -1, toZero);
    if (toOne < fit.error) fit = Bc4TexelFit(7, -1, toOne);
    return fit;
}

CUBEAO_FN uint bc4BlockError(bool eight, ivec2 e, const int q[16]) {
    Bc4Ramp r = bc4MakeRamp(eight, e);
    uint sum = 0u;
    for (int t = 0; t < 16; ++t) sum += bc4FitTexel(r, q[t]).error;
    return sum;
}

CUBEAO_FN bool bc4Valid(bool eight, ivec2 e) { return e.x >= 0 && e.y <= 255 && (eight ? e.x < e.y : e.x <= e.y); }

// Clamps to unorm8, orders, and separates equal endpoints in the 8-level mode.
CUBEAO_FN ivec2 bc4Normalise(bool eight, ivec2 e) {
    e = clamp(e, 0, 255);
    if (e.x > e.y) e = ivec2(e.y, e.x);
    if (eight && e.x == e.y) {
        if (e.y < 255)
            ++e.y;
        else
            --e.x;
    }
    return e;
}

// num / den rounded to nearest, half away from zero (den > 0); exact for the magnitudes here. GLSL
// integer division is only defined for non-negative operands: divide magnitudes.
CUBEAO_FN int bc4RoundDiv(int num, int den) {
    return num >= 0 ? (2 * num + den) / (2 * den) : -((-2 * num + den) / (2 * den));
}

// Least-squares endpoints for the codes the texels take with e: q ≈ scale·((last − k)·lo + k·hi)
// over the ramp texels (scale = units per unorm8 step per level). False (result = e) when the system
// is singular.
CUBEAO_FN bool bc4LeastSquares(bool eight, ivec2 e, const int q[16], CUBEAO_OUT(ivec2) result) {
    int last = eight ? 7 : 5, scale = eight ? 5 : 7;
    Bc4Ramp r = bc4MakeRamp(eight, e);
    int saa = 0, sab = 0, sbb = 0, saq = 0, sbq = 0;  // |sums| ≤ 16·7·8925 < 2^20
    for (int t = 0; t < 16; ++t) {
        int k = bc4FitTexel(r, q[t]).step;
        if (k < 0) continue;
        int a = last - k, b = k;
        saa += a * a;
        sab += a * b;
        sbb += b * b;
        saq += a * q[t];
        sbq += b * q[t];
    }
    int det = saa * sbb - sab * sab;  // ≤ 784²
    result = e;
    if (det <= 0) return false;
    // Cramer's rule; products ≤ 784 · 999600 < 2^30.
    result = bc4Normalise(eight, ivec2(bc4RoundDiv(sbb * saq - sab * sbq, scale * det),
                                       bc4RoundDiv(saa * sbq - sab * saq, scale * det)));
    return true;
}

struct Bc4ModeFit {
    ivec2 e;  // (lo, hi) unorm8
    uint error;
};

// Starts that map [qmin, qmax] onto steps k0..k1 of the ramp, not always all of them: four evenly
// spaced values, say, sit exactly on steps 1, 3, 5, 7 of a ramp that starts below qmin. k0 = 0,
// k1 = last (the plain range fit) comes first.
CUBEAO_FN void bc4SweepRange(bool eight, int qmin, int qmax, const int q[16], CUBEAO_INOUT(Bc4ModeFit) best) {
    int last = eight ? 7 : 5, range = qmax - qmin;
    for (int n = last; n >= 1; --n)  // the range spans n steps, starting at step k0
        for (int k0 = 0; k0 + n <= last; ++k0) {
            ivec2 e = bc4Normalise(eight, ivec2(bc4RoundDiv(qmin * n - k0 * range, 35 * n),
                                                bc4RoundDiv(qmin * n + (last - k0) * range, 35 * n)));
            uint error = bc4BlockError(eight, e, q);
            if (error < best.error) best = Bc4ModeFit(e, error);
            if (range == 0) return;  // every (k0, n) gives the same endpoints
        }
}

// Ends of the ramp for the 6-level mode. The plain ones leave out only exact 0s and 1s; the split
// ones also leave out values the explicit 0 (1) serves better than the ramp would: the low end is
// the smallest u with every smaller value ≤ u/2 (at least one of them nonzero), the high end likewise.
struct Bc4RampEnds {
    int low;
    int high;
    int splitLow;
    int splitHigh;
};

CUBEAO_FN Bc4RampEnds bc4SixLevelEnds(const int q[16]) {
    Bc4RampEnds r = Bc4RampEnds(kBc4Units, 0, kBc4Units, 0);
    for (int t = 0; t < 16; ++t) {
        if (q[t] == 0 || q[t] == kBc4Units) continue;
        r.low = min(r.low, q[t]);
        r.high = max(r.high, q[t]);
        int below = 0, above = kBc4Units;  // nearest values below and above q[t], other than 0 and 1
        for (int s = 0; s < 16; ++s) {
            if (q[s] > 0 && q[s] < q[t]) below = max(below, q[s]);
            if (q[s] < kBc4Units && q[s] > q[t]) above = min(above, q[s]);
        }
        if (below > 0 && 2 * below <= q[t]) r.splitLow = min(r.splitLow, q[t]);
        if (above < kBc4Units && 2 * (kBc4Units - above) <= kBc4Units - q[t]) r.splitHigh = max(r.splitHigh, q[t]);
    }
    if (r.low > r.high) {  // only 0s and 1s: any ramp will do
        r.low = 0;
        r.high = 0;
    }
    if (r.splitLow > r.high) r.splitLow = r.low;
    if (r.splitHigh < r.low) r.splitHigh = r.high;
    return r;
}

CUBEAO_FN Bc4ModeFit bc4FitMode(bool eight, const int q[16]) {
    Bc4ModeFit best = Bc4ModeFit(ivec2(0), 0xFFFFFFFFu);
    if (eight) {
        int qmin = kBc4Units, qmax = 0;
        for (int t = 0; t < 16; ++t) {
            qmin = min(qmin, q[t]);
            qmax = max(qmax, q[t]);
        }
        bc4SweepRange(true, qmin, qmax, q, best);
    } else {
        Bc4RampEnds r = bc4SixLevelEnds(q);
        bc4SweepRange(false, r.low, r.high, q, best);
        if (r.splitLow != r.low && r.splitLow <= r.high) bc4SweepRange(false, r.splitLow, r.high, q, best);
        if (r.splitHigh != r.high && r.low <= r.splitHigh) bc4SweepRange(false, r.low, r.splitHigh, q, best);
        if ((r.splitLow != r.low || r.splitHigh != r.high) && r.splitLow <= r.splitHigh)
            bc4SweepRange(false, r.splitLow, r.splitHigh, q, best);
    }
    if (best.error == 0u) return best;

    for (int round = 0; round < kBc4LeastSquaresRounds; ++round) {
        ivec2 e;
        if (!bc4LeastSquares(eight, best.e, q, e)) break;
        uint error = bc4BlockError(eight, e, q);
        if (error >= best.error) break;
        best = Bc4ModeFit(e, error);
    }
    for (int step = 0; step < kBc4DescentSteps; ++step) {
        Bc4ModeFit next = best;
        for (int dl = -1; dl <= 1; ++dl)
            for (int dh = -1; dh <= 1; ++dh) {
                ivec2 e = best.e + ivec2(dl, dh);
                if ((dl == 0 && dh == 0) || !bc4Valid(eight, e)) continue;
                uint error = bc4BlockError(eight, e, q);
                if (error < next.error) next = Bc4ModeFit(e, error);
            }
        if (next.error >= best.error) break;
        best = next;
    }
    return best;
}

// The block's two little-endian 32-bit words.
CUBEAO_FN uvec2 bc4PackBlock(bool eight, ivec2 e, const int q[16]) {
    ivec2 reds = bc4Reds(eight, e);
    Bc4Ramp r = bc4MakeRamp(eight, e);
    uint codes0 = 0u, codes1 = 0u;  // 24 bits each: texels 0-7, 8-15
    for (int t = 0; t < 8; ++t) {
        codes0 |= uint(bc4FitTexel(r, q[t]).code) << uint(3 * t);
        codes1 |= uint(bc4FitTexel(r, q[t + 8]).code) << uint(3 * t);
    }
    return uvec2(uint(reds.x) | uint(reds.y) << 8u | (codes0 & 0xFFFFu) << 16u, codes0 >> 16u | codes1 << 8u);
}

// The block, of all the candidates tried, that minimises the squared error against q.
CUBEAO_FN uvec2 bc4EncodeBlock(const int q[16]) {
    Bc4ModeFit eight = bc4FitMode(true, q);
    if (eight.error == 0u) return bc4PackBlock(true, eight.e, q);
    Bc4ModeFit six = bc4FitMode(false, q);
    return six.error < eight.error ? bc4PackBlock(false, six.e, q) : bc4PackBlock(true, eight.e, q);
}

CUBEAO_KERNEL_END

#version 450 core
// BC5 (RGTC2, unsigned) encoder for a probe's (AO, confidence): red = AO, green = confidence.
// Format: EXT_texture_compression_rgtc, "RGTC Compressed Texture Image Formats" (OpenGL 4.5 core,
// appendix C.1): per channel a 64-bit BC4 block, little-endian, red_0 | red_1 << 8 | codes from bit
// 16, texel (x, y) at bit 16 + 3·(4y + x); red_0 > red_1 selects the 8-level ramp, otherwise 6 levels
// plus explicit 0 (code 6) and 1 (code 7).
//
// GLSL twin of the C++ reference encoder, src/cubeao/cache/bc4.cpp (the algorithm and the reasons are
// described there): the same integer arithmetic in units of 1/8925, the same candidate order and tie
// rules, hence the same blocks (tests/test_bc.cpp checks this bit for bit). One exception: GLSL leaves
// comparisons with NaN undefined, so a NaN input gives an unspecified level here (C++: 0).
//
// One invocation per block and channel: global id (2·bx + channel, by, face). Block order: faces, then
// block rows bottom-up, then blocks left to right (src/cubeao/cache/bc4.h).
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 1) readonly buffer AoIn { vec2 aoConfidence[]; };  // cube::texelIndex order
layout(std430, binding = 3) writeonly buffer BlocksOut { uvec4 blocks[]; };  // red (xy), green (zw)

uniform int res;  // a multiple of 4

const int kUnits = 8925;  // 1.0 in units: 255 · 35
const int kLeastSquaresRounds = 2;
const int kDescentSteps = 8;

int q[16];  // this invocation's block, in units

struct TexelFit {
    int code;
    int step;  // position on the ramp; -1 for the explicit 0 and 1
    uint error;
};

struct ModeFit {
    ivec2 e;  // (lo, hi) unorm8
    uint error;
};

int quantise(float v) {
    if (!(v > 0.0)) return 0;
    if (v >= 1.0) return kUnits;
    return int(roundEven(v * float(kUnits)));
}

struct Ramp {
    bool eight;
    int base, span, last;
    float inverseSpan;
};

Ramp makeRamp(bool eight, ivec2 e) {
    int span = (e.y - e.x) * (eight ? 5 : 7);
    return Ramp(eight, e.x * 35, span, eight ? 7 : 5, span > 0 ? 1.0 / float(span) : 0.0);
}

// A float guess, then exact integer comparisons: the same level as in C++ whatever the rounding of
// the division (see bc4.cpp).
int nearestStep(Ramp r, int v) {
    int d = v - r.base;
    if (d <= 0 || r.span == 0) return 0;
    int k = min(int(float(d) * r.inverseSpan + 0.5), r.last);
    if (k < r.last && abs(d - (k + 1) * r.span) <= abs(d - k * r.span))
        ++k;
    else if (k > 0 && abs(d - (k - 1) * r.span) < abs(d - k * r.span))
        --k;
    return k;
}

TexelFit fitTexel(Ramp r, int v) {
    int k = nearestStep(r, v), d = v - (r.base + k * r.span);
    if (r.eight) return TexelFit(k == 0 ? 1 : k == 7 ? 0 : 8 - k, k, uint(d * d));
    TexelFit fit = TexelFit(k == 0 ? 0 : k == 5 ? 1 : k + 1, k, uint(d * d));
    uint toZero = uint(v * v), toOne = uint((kUnits - v) * (kUnits - v));
    if (toZero < fit.error) fit = TexelFit(6, -1, toZero);
    if (toOne < fit.error) fit = TexelFit(7, -1, toOne);
    return fit;
}

uint blockError(bool eight, ivec2 e) {
    Ramp r = makeRamp(eight, e);
    uint sum = 0u;
    for (int t = 0; t < 16; ++t) sum += fitTexel(r, q[t]).error;
    return sum;
}

bool valid(bool eight, ivec2 e) { return e.x >= 0 && e.y <= 255 && (eight ? e.x < e.y : e.x <= e.y); }

ivec2 normalise(bool eight, ivec2 e) {
    e = clamp(e, 0, 255);
    if (e.x > e.y) e = e.yx;
    if (eight && e.x == e.y) {
        if (e.y < 255)
            ++e.y;
        else
            --e.x;
    }
    return e;
}

// GLSL integer division is only defined for non-negative operands: divide magnitudes.
int roundDiv(int num, int den) { return num >= 0 ? (2 * num + den) / (2 * den) : -((-2 * num + den) / (2 * den)); }

bool leastSquares(bool eight, ivec2 e, out ivec2 result) {
    int last = eight ? 7 : 5, scale = eight ? 5 : 7;
    Ramp r = makeRamp(eight, e);
    int saa = 0, sab = 0, sbb = 0, saq = 0, sbq = 0;
    for (int t = 0; t < 16; ++t) {
        int k = fitTexel(r, q[t]).step;
        if (k < 0) continue;
        int a = last - k, b = k;
        saa += a * a;
        sab += a * b;
        sbb += b * b;
        saq += a * q[t];
        sbq += b * q[t];
    }
    int det = saa * sbb - sab * sab;
    result = e;
    if (det <= 0) return false;
    result = normalise(eight, ivec2(roundDiv(sbb * saq - sab * sbq, scale * det), roundDiv(saa * sbq - sab * saq, scale * det)));
    return true;
}

void sweepRange(bool eight, int qmin, int qmax, inout ModeFit best) {
    int last = eight ? 7 : 5, range = qmax - qmin;
    for (int n = last; n >= 1; --n)
        for (int k0 = 0; k0 + n <= last; ++k0) {
            ivec2 e = normalise(eight, ivec2(roundDiv(qmin * n - k0 * range, 35 * n),
                                             roundDiv(qmin * n + (last - k0) * range, 35 * n)));
            uint error = blockError(eight, e);
            if (error < best.error) best = ModeFit(e, error);
            if (range == 0) return;
        }
}

// (low, high, splitLow, splitHigh) as RampEnds in bc4.cpp.
ivec4 sixLevelEnds() {
    ivec4 r = ivec4(kUnits, 0, kUnits, 0);
    for (int t = 0; t < 16; ++t) {
        if (q[t] == 0 || q[t] == kUnits) continue;
        r.x = min(r.x, q[t]);
        r.y = max(r.y, q[t]);
        int below = 0, above = kUnits;
        for (int s = 0; s < 16; ++s) {
            if (q[s] > 0 && q[s] < q[t]) below = max(below, q[s]);
            if (q[s] < kUnits && q[s] > q[t]) above = min(above, q[s]);
        }
        if (below > 0 && 2 * below <= q[t]) r.z = min(r.z, q[t]);
        if (above < kUnits && 2 * (kUnits - above) <= kUnits - q[t]) r.w = max(r.w, q[t]);
    }
    if (r.x > r.y) r.xy = ivec2(0);
    if (r.z > r.y) r.z = r.x;
    if (r.w < r.x) r.w = r.y;
    return r;
}

ModeFit fitMode(bool eight) {
    ModeFit best = ModeFit(ivec2(0), 0xFFFFFFFFu);
    if (eight) {
        int qmin = kUnits, qmax = 0;
        for (int t = 0; t < 16; ++t) {
            qmin = min(qmin, q[t]);
            qmax = max(qmax, q[t]);
        }
        sweepRange(true, qmin, qmax, best);
    } else {
        ivec4 r = sixLevelEnds();
        sweepRange(false, r.x, r.y, best);
        if (r.z != r.x && r.z <= r.y) sweepRange(false, r.z, r.y, best);
        if (r.w != r.y && r.x <= r.w) sweepRange(false, r.x, r.w, best);
        if ((r.z != r.x || r.w != r.y) && r.z <= r.w) sweepRange(false, r.z, r.w, best);
    }
    if (best.error == 0u) return best;
    for (int round = 0; round < kLeastSquaresRounds; ++round) {
        ivec2 e;
        if (!leastSquares(eight, best.e, e)) break;
        uint error = blockError(eight, e);
        if (error >= best.error) break;
        best = ModeFit(e, error);
    }
    for (int step = 0; step < kDescentSteps; ++step) {
        ModeFit next = best;
        for (int dl = -1; dl <= 1; ++dl)
            for (int dh = -1; dh <= 1; ++dh) {
                ivec2 e = best.e + ivec2(dl, dh);
                if ((dl == 0 && dh == 0) || !valid(eight, e)) continue;
                uint error = blockError(eight, e);
                if (error < next.error) next = ModeFit(e, error);
            }
        if (next.error >= best.error) break;
        best = next;
    }
    return best;
}

// The two little-endian 32-bit words of the block.
uvec2 packBlock(bool eight, ivec2 e) {
    uint red0 = uint(eight ? e.y : e.x), red1 = uint(eight ? e.x : e.y);
    Ramp r = makeRamp(eight, e);
    uint codes0 = 0u, codes1 = 0u;  // 24 bits each: texels 0-7, 8-15
    for (int t = 0; t < 8; ++t) {
        codes0 |= uint(fitTexel(r, q[t]).code) << (3 * t);
        codes1 |= uint(fitTexel(r, q[t + 8]).code) << (3 * t);
    }
    return uvec2(red0 | red1 << 8 | (codes0 & 0xFFFFu) << 16, codes0 >> 16 | codes1 << 8);
}

void main() {
    int blocksPerSide = res / 4;
    ivec3 id = ivec3(gl_GlobalInvocationID);
    if (id.x >= 2 * blocksPerSide || id.y >= blocksPerSide) return;
    int bx = id.x >> 1, channel = id.x & 1, by = id.y, face = id.z;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            int texel = (face * res + 4 * by + y) * res + 4 * bx + x;
            q[4 * y + x] = quantise(aoConfidence[texel][channel]);
        }
    ModeFit eight = fitMode(true);
    uvec2 words;
    if (eight.error == 0u) {
        words = packBlock(true, eight.e);
    } else {
        ModeFit six = fitMode(false);
        words = six.error < eight.error ? packBlock(false, six.e) : packBlock(true, eight.e);
    }
    int block = (face * blocksPerSide + by) * blocksPerSide + bx;
    if (channel == 0)
        blocks[block].xy = words;
    else
        blocks[block].zw = words;
}

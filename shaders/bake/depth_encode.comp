#version 450 core
// A probe's distance cube for the cache (DESIGN.md §4 "Storage"; docs/FORMAT.md "Distance cube"):
// GLSL twin of src/cubeao/cache/depth_cube.cpp (depth::downsample with Filter::Min, maxDistance,
// encodeTexel), which gives the same bytes (r16unorm: within one code, GLSL division is not
// correctly rounded everywhere).
//   PASS 0: coarse texel (I, J, face) = the smallest non-zero G-buffer distance of the fine texels it
//           covers, 0 when all are empty; the largest coarse value → maxBits (the r16unorm scale).
//   PASS 1: one output word per r32float texel, or per two r16 texels (texel 2k in the low half:
//           little-endian u16s). 6·depthRes² is even, so pairs never straddle the end.
#if PASS == 0
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2DArray gbuffer;  // (normal, distance) per texel, 6 layers
uniform int res;
#else
layout(local_size_x = 64) in;
#endif

layout(std430, binding = 5) buffer Coarse { float coarse[]; };  // cube::texelIndex order at depthRes
layout(std430, binding = 6) buffer MaxDistance { uint maxBits; };   // floatBitsToUint of a value ≥ 0
layout(std430, binding = 7) writeonly buffer Words { uint words[]; };

uniform int depthRes;
uniform int format;  // DepthFormat: 1 r16unorm, 2 r16float, 3 r32float

#if PASS == 0
shared uint groupMax;

void main() {
    if (gl_LocalInvocationIndex == 0u) groupMax = 0u;
    barrier();
    ivec3 c = ivec3(gl_GlobalInvocationID);
    if (c.x < depthRes && c.y < depthRes) {
        int i0 = c.x * res / depthRes, i1 = (c.x + 1) * res / depthRes;
        int j0 = c.y * res / depthRes, j1 = (c.y + 1) * res / depthRes;
        float m = 0.0;
        for (int j = j0; j < j1; ++j)
            for (int i = i0; i < i1; ++i) {
                float d = texelFetch(gbuffer, ivec3(i, j, c.z), 0).w;
                if (d > 0.0 && (m == 0.0 || d < m)) m = d;
            }
        coarse[(c.z * depthRes + c.y) * depthRes + c.x] = m;
        atomicMax(groupMax, floatBitsToUint(m));  // non-negative floats order like their bits
    }
    barrier();
    if (gl_LocalInvocationIndex == 0u) atomicMax(maxBits, groupMax);
}

#else
// IEEE half, round to nearest even, integers only (depth::floatToHalf: the same steps).
uint floatToHalf(float f) {
    uint u = floatBitsToUint(f) & 0x7FFFFFFFu;
    if (u > 0x7F800000u) return 0x7E00u;
    if (u >= 0x47800000u) return 0x7C00u;
    if (u < 0x38800000u) return uint(roundEven(uintBitsToFloat(u) * 16777216.0));  // exact scale
    return (u + 0xC8000FFFu + ((u >> 13) & 1u)) >> 13;
}

uint encodeTexel(float d, float maxDistance) {
    if (!(d > 0.0)) return 0u;
    if (format == 1) {
        if (!(maxDistance > 0.0)) return 0u;
        return max(uint(roundEven(min(d / maxDistance, 1.0) * 65535.0)), 1u);
    }
    if (format == 2) return clamp(floatToHalf(d), 1u, 0x7BFFu);
    return floatBitsToUint(d);
}

void main() {
    uint k = gl_GlobalInvocationID.x;
    uint texels = 6u * uint(depthRes * depthRes);
    float maxDistance = uintBitsToFloat(maxBits);
    if (format == 3) {
        if (k < texels) words[k] = encodeTexel(coarse[k], maxDistance);
    } else if (2u * k < texels) {
        words[k] = encodeTexel(coarse[2u * k], maxDistance) | encodeTexel(coarse[2u * k + 1u], maxDistance) << 16;
    }
}
#endif

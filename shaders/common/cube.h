// Cube-map conventions for every probe lookup, on the GPU and the CPU: face order, texel ↔ direction.
// They follow the OpenGL cube-map selection table (GL 4.5 core, §8.13.1, table 8.19), so a GL cube map
// and our own lookups agree. Faces +X −X +Y −Y +Z −Z (GL_TEXTURE_CUBE_MAP_POSITIVE_X + f); a face point
// sc ∈ [−1, 1]² is (s, t) before the table's (·+1)/2. Texel (i, j) of a res × res face covers
// s ∈ [i, i+1)/res, t ∈ [j, j+1)/res and is pixel (i, j) of the framebuffer that rasterises the face.
// C++ conveniences on top (texel indices, solid angles, the face projection): src/cubeao/core/cube.h.
#pragma once

#include "glsl_cpp.h"

CUBEAO_KERNEL_BEGIN

CUBEAO_CONST int kCubeFaces = 6;

// Major axis with a fixed tie rule (x before y before z), so CPU and GPU pick the same face for
// directions exactly on a cube edge. Returns the face, sc out.
CUBEAO_FN int cubeFaceOf(vec3 d, CUBEAO_OUT(vec2) sc) {
    vec3 a = abs(d);
    if (a.x >= a.y && a.x >= a.z) {
        sc = (d.x >= 0.0f ? vec2(-d.z, -d.y) : vec2(d.z, -d.y)) / a.x;
        return d.x >= 0.0f ? 0 : 1;
    }
    if (a.y >= a.z) {
        sc = (d.y >= 0.0f ? vec2(d.x, d.z) : vec2(d.x, -d.z)) / a.y;
        return d.y >= 0.0f ? 2 : 3;
    }
    sc = (d.z >= 0.0f ? vec2(d.x, -d.y) : vec2(-d.x, -d.y)) / a.z;
    return d.z >= 0.0f ? 4 : 5;
}

// Inverse of cubeFaceOf: an (unnormalised) direction whose major component is ±1.
CUBEAO_FN vec3 cubeFaceDirection(int face, vec2 sc) {
    switch (face) {
        case 0: return vec3(1.0f, -sc.y, -sc.x);
        case 1: return vec3(-1.0f, -sc.y, sc.x);
        case 2: return vec3(sc.x, 1.0f, sc.y);
        case 3: return vec3(sc.x, -1.0f, -sc.y);
        case 4: return vec3(sc.x, -sc.y, 1.0f);
        default: return vec3(-sc.x, -sc.y, -1.0f);
    }
}

CUBEAO_FN vec2 cubeTexelCentre(ivec2 texel, int res) { return 2.0f * (vec2(texel) + 0.5f) / float(res) - 1.0f; }

CUBEAO_FN vec3 cubeTexelDirection(int face, ivec2 texel, int res) {
    return normalize(cubeFaceDirection(face, cubeTexelCentre(texel, res)));
}

// The texel a face point falls in (clamped: sc = 1 belongs to the last texel).
CUBEAO_FN ivec2 cubeTexelOf(vec2 sc, int res) {
    return clamp(ivec2(floor((sc + 1.0f) * 0.5f * float(res))), ivec2(0), ivec2(res - 1));
}

// The texel a direction falls in, as (i, j, face): the layer of a 6-layer array texture.
CUBEAO_FN ivec3 cubeTexelOfDirection(vec3 d, int res) {
    vec2 sc;
    int face = cubeFaceOf(d, sc);
    ivec2 t = cubeTexelOf(sc, res);
    return ivec3(t.x, t.y, face);
}

// Linear index of texel (i, j, face) in a six-face array: faces in order, rows bottom-up, texels
// left to right (the layout of every per-texel buffer of the bake).
CUBEAO_FN uint cubeTexelIndex(ivec3 texel, int res) {
    return (uint(texel.z) * uint(res) + uint(texel.y)) * uint(res) + uint(texel.x);
}

// Inverse of cubeTexelIndex: texel (i, j, face) of a linear index.
CUBEAO_FN ivec3 cubeTexelOfIndex(uint index, int res) {
    uint faceSize = uint(res) * uint(res);
    return ivec3(int(index % uint(res)), int((index % faceSize) / uint(res)), int(index / faceSize));
}

CUBEAO_KERNEL_END

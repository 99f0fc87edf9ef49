// Cube-map conventions: the GLSL twin of src/cubeao/bake/cube.h (GL 4.5 §8.13.1, table 8.19; keep the
// two in step, tests/test_cube_gl.cpp checks them). Faces +X −X +Y −Y +Z −Z, sc ∈ [−1, 1]².
#pragma once

// Major axis with the tie rule x, then y, then z (as the C++ twin). Returns the face; sc out.
int cubeFaceOf(vec3 d, out vec2 sc) {
    vec3 a = abs(d);
    if (a.x >= a.y && a.x >= a.z) {
        sc = (d.x >= 0.0 ? vec2(-d.z, -d.y) : vec2(d.z, -d.y)) / a.x;
        return d.x >= 0.0 ? 0 : 1;
    }
    if (a.y >= a.z) {
        sc = (d.y >= 0.0 ? vec2(d.x, d.z) : vec2(d.x, -d.z)) / a.y;
        return d.y >= 0.0 ? 2 : 3;
    }
    sc = (d.z >= 0.0 ? vec2(d.x, -d.y) : vec2(-d.x, -d.y)) / a.z;
    return d.z >= 0.0 ? 4 : 5;
}

vec3 cubeFaceDirection(int face, vec2 sc) {
    switch (face) {
        case 0: return vec3(1.0, -sc.y, -sc.x);
        case 1: return vec3(-1.0, -sc.y, sc.x);
        case 2: return vec3(sc.x, 1.0, sc.y);
        case 3: return vec3(sc.x, -1.0, -sc.y);
        case 4: return vec3(sc.x, -sc.y, 1.0);
        default: return vec3(-sc.x, -sc.y, -1.0);
    }
}

vec2 cubeTexelCentre(ivec2 texel, int res) { return 2.0 * (vec2(texel) + 0.5) / float(res) - 1.0; }

vec3 cubeTexelDirection(int face, ivec2 texel, int res) {
    return normalize(cubeFaceDirection(face, cubeTexelCentre(texel, res)));
}

ivec2 cubeTexelOf(vec2 sc, int res) { return clamp(ivec2(floor((sc + 1.0) * 0.5 * float(res))), ivec2(0), ivec2(res - 1)); }

// The texel a direction falls in, as (i, j, face): the layer of a 6-layer array texture.
ivec3 cubeTexelOfDirection(vec3 d, int res) {
    vec2 sc;
    int face = cubeFaceOf(d, sc);
    return ivec3(cubeTexelOf(sc, res), face);
}

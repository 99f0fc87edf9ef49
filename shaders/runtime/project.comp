#version 450 core
// Probe projection (DESIGN.md §4 "Projection", thesis 003 ch. 5): AO of every camera pixel from the
// baked probes. Per pixel: the world point and normal from the camera G-buffer, the K candidate
// probes of its world cell (src/cubeao/runtime/probe_grid.h), per candidate the depth test against
// its distance cube (src/cubeao/cache/depth_cube.h `visible`), quality = confidence / world area of
// one probe texel on the surface, and the soft best-two blend. The CPU twin is
// src/cubeao/runtime/projection.cpp (projectAo); keep the two in step.
layout(local_size_x = 8, local_size_y = 8) in;

#include "camera.glsl"
#include "cube.glsl"

layout(binding = 0) uniform sampler2D depthTex;         // view depth, 0 = no geometry
layout(binding = 1) uniform sampler2D normalTex;        // view-space normal facing the camera
// Probe atlases (probe_projection.h ProbeAtlasLayout): a probe is a tile, layer 6·page + face.
layout(binding = 2) uniform sampler2DArray aoTex;       // BC5: r = AO, g = confidence; res² tiles
layout(binding = 3) uniform sampler2DArray distanceTex; // distance cube; value · scale = distance; depthRes² tiles
layout(r32f, binding = 0) writeonly uniform image2D aoOut;

layout(std430, binding = 5) readonly buffer Probes { vec4 probes[]; };  // xyz position, w distance scale
layout(std430, binding = 6) readonly buffer Grid { uint candidates[]; };  // K per cell, ~0u = none
layout(std430, binding = 4) buffer Counters { uint uncovered; uint fetchesLow; uint fetchesHigh; };

uniform mat4 worldFromView;
uniform vec3 gridOrigin;
uniform float cellSize;
uniform ivec3 gridDims;
uniform int candidatesPerCell;
uniform int res;
uniform int depthRes;
uniform int tilesX;
uniform int tilesPerPage;
uniform float depthTolerance;
uniform float depthSlope;
uniform float minFacing;

const float kMaxTan = 8.0;  // depth_cube.h kMaxTan

shared uint groupUncovered, groupFetches;

// Texel of direction sc on `face` of `probe` in an atlas of size² tiles.
ivec3 atlasTexel(uint probe, int face, vec2 sc, int size) {
    int tile = int(probe) % tilesPerPage;
    ivec2 corner = ivec2(tile % tilesX, tile / tilesX) * size;
    return ivec3(corner + cubeTexelOf(sc, size), 6 * (int(probe) / tilesPerPage) + face);
}

// depth_cube.h visible(): a point whose seen side faces away is hidden; an empty texel hides
// nothing (the projection still skips it: the probe saw no surface there); relative plus
// slope-scaled bias.
bool depthVisible(float stored, float dist, float cosine) {
    if (!(cosine > 0.0)) return false;
    if (!(stored > 0.0)) return false;
    float c = min(abs(cosine), 1.0), s = sqrt(1.0 - c * c);
    float tanTheta = c * kMaxTan > s ? s / c : kMaxTan;
    return dist <= stored * (1.0 + depthTolerance + depthSlope * (2.0 / float(depthRes)) * tanTheta);
}

void main() {
    if (gl_LocalInvocationIndex == 0u) {
        groupUncovered = 0u;
        groupFetches = 0u;
    }
    barrier();
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    uint fetches = 0u;
    if (onScreen(px)) {
        float depth = texelFetch(depthTex, px, 0).r;
        float ao = 1.0;  // no geometry: open, as in the reference
        fetches += 1u;
        if (depth > 0.0) {
            vec3 x = (worldFromView * vec4(viewPosition(px, depth), 1.0)).xyz;
            vec3 n = normalize(mat3(worldFromView) * texelFetch(normalTex, px, 0).xyz);
            fetches += 1u;
            ivec3 cell = clamp(ivec3(floor((x - gridOrigin) / cellSize)), ivec3(0), gridDims - 1);
            uint base = uint((cell.z * gridDims.y + cell.y) * gridDims.x + cell.x) * uint(candidatesPerCell);
            vec2 best[3] = vec2[3](vec2(0.0, 1.0), vec2(0.0, 1.0), vec2(0.0, 1.0));  // (quality, ao), best first
            for (int k = 0; k < candidatesPerCell; ++k) {
                uint probe = candidates[base + uint(k)];
                if (probe == 0xffffffffu) break;
                vec3 d = x - probes[probe].xyz;
                float dist = length(d);
                float cosine = -dot(n, d) / dist;
                vec2 sc;
                int face = cubeFaceOf(d, sc);
                float stored = texelFetch(distanceTex, atlasTexel(probe, face, sc, depthRes), 0).r * probes[probe].w;
                fetches += 1u;
                if (!depthVisible(stored, dist, cosine)) continue;
                float r2 = 1.0 + dot(sc, sc), texel = 2.0 / float(res);
                float area = texel * texel / (r2 * sqrt(r2)) * dist * dist / max(cosine, minFacing);
                vec2 v = texelFetch(aoTex, atlasTexel(probe, face, sc, res), 0).rg;
                fetches += 1u;
                vec2 r = vec2(v.g / area, v.r);
                if (!(r.x > 0.0)) continue;
                if (r.x > best[0].x) {
                    best[2] = best[1];
                    best[1] = best[0];
                    best[0] = r;
                } else if (r.x > best[1].x) {
                    best[2] = best[1];
                    best[1] = r;
                } else if (r.x > best[2].x) {
                    best[2] = r;
                }
            }
            if (best[0].x > 0.0) {
                float w0 = best[0].x - best[2].x, w1 = best[1].x - best[2].x;
                ao = w0 + w1 > 0.0 ? (w0 * best[0].y + w1 * best[1].y) / (w0 + w1) : (best[0].y + best[1].y + best[2].y) / 3.0;
            } else {
                atomicAdd(groupUncovered, 1u);  // fallback: open (counted as uncovered_fraction)
            }
        }
        imageStore(aoOut, px, vec4(ao));
    }
    atomicAdd(groupFetches, fetches);
    barrier();
    if (gl_LocalInvocationIndex == 0u) {
        atomicAdd(uncovered, groupUncovered);
        uint before = atomicAdd(fetchesLow, groupFetches);
        if (before + groupFetches < before) atomicAdd(fetchesHigh, 1u);
    }
}

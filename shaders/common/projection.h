// Projecting baked probes onto a surface point (DESIGN.md §4 "Projection", thesis 003 ch. 5), once for
// the run-time pass (shaders/runtime/project.comp) and its CPU twin (src/cubeao/runtime/projection.h,
// which explains the quality and the blend): the depth test against a probe's distance cube, the
// world area of one probe texel on the surface, and the per-point loop over candidate probes with the
// soft best-two blend.
//
// The loop reads probes through seven functions its includer provides; in GLSL they are globals the
// shader defines (declared below), in C++ they are members of a reader object passed first
// (projectCandidates is then a template over the reader's type):
//   uint projectionCandidate(int k)                         probe index of candidate k, kNoProbe = end
//   uint projectionSlot(uint probe)                          where its texels are (run-time residency),
//                                                            kNoSlot = not resident
//   int projectionLevel(uint probe)                          the level of detail of those texels (0: full
//                                                            resolution; k: faces of res >> k, depthRes >> k)
//   float projectionQualityScale(uint probe)                 multiplies its quality (1 when settled)
//   vec3 projectionProbePosition(uint probe)
//   float projectionDistance(uint probe, uint slot, int face, vec2 sc)  decoded distance-cube texel, 0 = empty
//   vec2 projectionAoConfidence(uint probe, uint slot, int face, vec2 sc)  (AO, confidence) texel
// The slot is read once per candidate and handed to the texel reads (one table read, not three).
// Texels are those cubeTexelOf(sc, resolution at the level) picks on `face` (cube.h). A probe held at a
// coarser level ranks by its coarser texels' footprint (probeTexelArea at res >> level) and is tested
// with that level's depth bias, so the blend moves weight to a finer probe where one sees the point;
// when its full resolution arrives, the quality scale takes its weight there over a few frames
// instead of at once (a level change is a blend, like a probe change).
#pragma once

#include "cube.h"
#include "depth_test.h"
#include "glsl_cpp.h"
#include "runtime_layout.h"
#include "texel_area.h"

#ifdef __cplusplus

#define CUBEAO_READER_FN template <class Reader> inline
#define CUBEAO_READER(r) const Reader& r,
#define CUBEAO_READ(r) r.
#else
#define CUBEAO_READER_FN
#define CUBEAO_READER(r)
#define CUBEAO_READ(r)
#endif

CUBEAO_KERNEL_BEGIN

// Whether the probe sees the point: its seen side faces the probe, the probe saw a surface that way
// (an empty texel holds no AO for the point either), that surface is the point's, and the point lifted
// off its surface is not behind what the probe saw (depth_test.h).
// `stored` is the texel in the point's direction, `lifted` the texel in the direction of the point lifted
// off its surface (depthLiftedPoint), `liftedDistance` that point's distance (no lifted half when
// p.depthOffset is 0).
CUBEAO_FN bool probeSeesPoint(float stored, float distance, float cosine, float lifted, float liftedDistance,
                              ProjectionParams p) {
    if (!(cosine > 0.0f) || !(stored > 0.0f)) return false;
    return depthVisible(stored, distance, cosine, lifted, liftedDistance, p.depthTolerance, p.depthSlope, p.depthOffset,
                        p.depthRes);
}

// AO at a point and how many probes gave it: 0 (nobody saw the point: ao = 1, open, the caller's
// fallback), 1, 2, or 3 when three tie for first. `missing` is the first candidate passed over
// because it was not resident before any resident one that sees the point (kNoProbe if none; the
// point then took candidates ranked after it: the "fallback probe" path); probe0/probe1 are the two probes with the largest weights (kNoProbe
// where fewer were used). The last three are the residency's feedback: what pixels use and want.
struct ProjectedAo {
    float ao;
    int used;
    uint missing;
    uint probe0;
    uint probe1;
};

#ifndef __cplusplus
uint projectionCandidate(int k);
uint projectionSlot(uint probe);
int projectionLevel(uint probe);
float projectionQualityScale(uint probe);
vec3 projectionProbePosition(uint probe);
float projectionDistance(uint probe, uint slot, int face, vec2 sc);
vec2 projectionAoConfidence(uint probe, uint slot, int face, vec2 sc);
#endif

// AO at world point x with unit normal n (turned to the camera) from up to `count` candidates: per
// candidate the depth test, quality = confidence / probeTexelArea, then the best two blended with
// weights q1 − q3 and q2 − q3 (q3: the third best, 0 if none), continuous when the ranking changes.
CUBEAO_READER_FN ProjectedAo projectCandidates(CUBEAO_READER(reader) int count, vec3 x, vec3 n, ProjectionParams p) {
    vec2 best[3];  // (quality, AO), best first; quality 0 = empty slot
    best[0] = vec2(0.0f, 1.0f);
    best[1] = best[0];
    best[2] = best[0];
    uint id0 = kNoProbe, id1 = kNoProbe;  // the probes of best[0] and best[1]
    uint missing = kNoProbe;
    for (int k = 0; k < count; ++k) {
        uint probe = CUBEAO_READ(reader) projectionCandidate(k);
        if (probe == kNoProbe) break;
        uint slot = CUBEAO_READ(reader) projectionSlot(probe);
        if (slot == kNoSlot) {
            // Only a candidate ranked before every resident one that sees the point is wanted here.
            if (missing == kNoProbe && !(best[0].x > 0.0f)) missing = probe;
            continue;
        }
        vec3 d = x - CUBEAO_READ(reader) projectionProbePosition(probe);
        float distance = length(d);
        float cosine = -dot(n, d) / distance;
        vec2 sc;
        int face = cubeFaceOf(d, sc);
        ProjectionParams q = p;  // at the probe's level
        int level = CUBEAO_READ(reader) projectionLevel(probe);
        q.res = p.res >> level;
        q.depthRes = max(p.depthRes >> level, 1);
        float stored = CUBEAO_READ(reader) projectionDistance(probe, slot, face, sc);
        float liftedStored = 0.0f, liftedDistance = 0.0f;  // read only with a lift: no second fetch without
        if (q.depthOffset > 0.0f) {
            vec3 lifted = depthLiftedPoint(d, n, distance, q.depthOffset, q.depthRes);  // from the probe
            vec2 liftedSc;
            int liftedFace = cubeFaceOf(lifted, liftedSc);
            liftedStored = CUBEAO_READ(reader) projectionDistance(probe, slot, liftedFace, liftedSc);
            liftedDistance = length(lifted);
        }
        if (!probeSeesPoint(stored, distance, cosine, liftedStored, liftedDistance, q)) continue;
        vec2 v = CUBEAO_READ(reader) projectionAoConfidence(probe, slot, face, sc);
        vec2 r = vec2(CUBEAO_READ(reader) projectionQualityScale(probe) * v.y /
                          probeTexelArea(sc, distance, cosine, q.res, p.minFacing),
                      v.x);
        if (!(r.x > 0.0f)) continue;
        if (r.x > best[0].x) {
            best[2] = best[1];
            best[1] = best[0];
            best[0] = r;
            id1 = id0;
            id0 = probe;
        } else if (r.x > best[1].x) {
            best[2] = best[1];
            best[1] = r;
            id1 = probe;
        } else if (r.x > best[2].x) {
            best[2] = r;
        }
    }
    if (!(best[0].x > 0.0f)) return ProjectedAo(1.0f, 0, missing, kNoProbe, kNoProbe);
    float w0 = best[0].x - best[2].x, w1 = best[1].x - best[2].x;
    // Three or more tie for first: their mean is as continuous as any choice.
    if (!(w0 + w1 > 0.0f)) return ProjectedAo((best[0].y + best[1].y + best[2].y) / 3.0f, 3, missing, id0, id1);
    return ProjectedAo((w0 * best[0].y + w1 * best[1].y) / (w0 + w1), int(w0 > 0.0f) + int(w1 > 0.0f), missing, id0,
                       w1 > 0.0f ? id1 : kNoProbe);
}

// The grid cell (clamped into the grid) holding world point x: the cell whose candidates the
// projection tries (src/cubeao/runtime/probe_grid.h; cells x-fastest).
CUBEAO_FN ivec3 candidateCellOf(vec3 x, vec3 origin, float cellSize, ivec3 dims) {
    return clamp(ivec3(floor((x - origin) / cellSize)), ivec3(0), dims - 1);
}

// The other way, for the C++ grids that fill the lists: the cell of x-fastest index `index`, and a
// cell's centre.
CUBEAO_FN ivec3 candidateCellCoordinates(uint index, ivec3 dims) {
    uint dx = uint(dims.x), dy = uint(dims.y);
    return ivec3(int(index % dx), int((index / dx) % dy), int(index / (dx * dy)));
}
CUBEAO_FN vec3 candidateCellCentre(ivec3 cell, vec3 origin, float cellSize) {
    return origin + (vec3(cell) + 0.5f) * cellSize;
}

CUBEAO_KERNEL_END

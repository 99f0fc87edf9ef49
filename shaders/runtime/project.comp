#version 450 core
// Probe projection (DESIGN.md §4 "Projection", thesis 003 ch. 5): AO of every camera pixel from the
// baked probes. Per pixel: the world point and normal from the camera G-buffer, the K candidate
// probes of its world cell (src/cubeao/runtime/probe_grid.h), and projectCandidates of
// common/projection.h (depth test, quality, soft best-two blend), whose C++ compilation is the CPU twin
// (src/cubeao/runtime/projection.h). This file only supplies the reads: atlas textures and buffers.
//
// Residency (src/cubeao/runtime/probe_residency.h): a probe's texels sit in atlas tile
// probes[id].tile, or nowhere (kNoSlot): the loop then passes it over and takes the next resident
// candidate (a cell with none resident skips the loop: residentCount, cell_residency.comp). When
// none of the cell's candidates is resident and sees the point, it tries the second list, the
// resident probes nearest the point's coarse cell (src/cubeao/runtime/nearest_lists.h).
// A pixel none of those sees gets `uncoveredAo` (kUncoveredAo when a screen-space fallback fills it
// afterwards, 1 = open without one). Every 4th pixel in x and y counts, weighted, the probes it
// blended and a better-ranked candidate it had to pass over (its demand), which the residency reads
// back frames later (sampled feedback, as virtual texturing does): it loads what pixels ask for and
// keeps what they use.
//
// Built with PROJECT_DIAGNOSTICS (probe_projection.h setDiagnostics) the pass also writes, per pixel,
// what the viewer's diagnostic modes show (tools/cubeao-view/view_modes.h) into an RGBA32F image:
//   r = probe0's id (the probe with the largest blend weight), −1 where none (sky, uncovered)
//   g = probe0's texel footprint at the point: world units per texel, sqrt(probeTexelArea)
//   b = probe0's confidence texel there (0..1)
//   a = path: 0 no geometry (sky), 1 probe, 2 fallback probe (a better-ranked candidate was not
//       resident, or the second list shaded it), 3 uncovered (screen-space fallback, or open without one)
// It is computed after projectCandidates from probe0 alone, reading the tables and textures directly
// rather than through the counted reads, so that the AO, the counters and the feedback are the
// production kernel's, bit for bit.
#include "camera.h"
#include "cube.h"
#include "pass_counters.glsl"
#include "projection.h"
#include "runtime_layout.h"

layout(local_size_x = kPixelGroupSize, local_size_y = kPixelGroupSize) in;

layout(binding = kGBufferDepthUnit) uniform sampler2D depthTex;
layout(binding = kGBufferNormalUnit) uniform sampler2D normalTex;
// Probe atlases (probe_projection.h ProbeAtlasLayout): a slot is a tile, layer 6·page + face.
layout(binding = kProbeAoUnit) uniform sampler2DArray aoTex;              // res² tiles
layout(binding = kProbeDistanceUnit) uniform sampler2DArray distanceTex;  // depthRes² tiles
// The coarse tier (ProbeEntry::level > 0): (res >> level)² and (depthRes >> level)² tiles. Declared only
// for a residency with a tier (probe_projection.cpp projectDefines); without one no level is above 0.
#ifdef PROJECT_COARSE_TIER
layout(binding = kProbeCoarseAoUnit) uniform sampler2DArray coarseAoTex;
layout(binding = kProbeCoarseDistanceUnit) uniform sampler2DArray coarseDistanceTex;
#else
#define coarseAoTex aoTex
#define coarseDistanceTex distanceTex
#endif
layout(r32f, binding = kAoImageUnit) writeonly uniform image2D aoOut;
#ifdef PROJECT_DIAGNOSTICS
layout(rgba32f, binding = kDiagnosticsImageUnit) writeonly uniform image2D diagnosticsOut;
#endif

layout(std430, binding = kProbeTableBuffer) readonly buffer ProbeTable { ProbeEntry probes[]; };
layout(std430, binding = kCandidateBuffer) readonly buffer Candidates { uint candidates[]; };
layout(std430, binding = kResidentCandidateBuffer) readonly buffer ResidentCandidates { uint residentCandidates[]; };
layout(std430, binding = kCellResidentCountBuffer) readonly buffer CellResidentCounts { uint residentCount[]; };
layout(std430, binding = kProbeFeedbackBuffer) buffer Feedback { uint demand[]; };

// The pass's fixed parameters (projection.h ProjectBlock, filled by probe_projection.cpp).
layout(std140, binding = kProjectBlock) uniform ProjectUniforms { ProjectBlock pass; };

uint cellBase = 0u;  // first candidate slot of the pixel's cell
bool secondList = false;  // projectionCandidate reads the second list (from residentBase)
uint residentBase = 0u;
uint fetches = 0u;   // texture fetches of this invocation

// Texel of direction sc on `face` of packed atlas tile `tile` (runtime_layout.h) in an atlas of size² tiles.
ivec3 atlasTexel(uint tile, int face, vec2 sc, int size) {
    ivec3 corner = atlasTileCorner(tile, size);
    return ivec3(corner.xy + cubeTexelOf(sc, size), corner.z + face);
}

void demandProbe(uint probe, uint weight) {
    if (probe != kNoProbe) atomicAdd(demand[probe], weight);
}

// The reads projectCandidates makes (common/projection.h); its "slot" is the packed tile here.
uint projectionCandidate(int k) {
    return secondList ? residentCandidates[residentBase + uint(k)] : candidates[cellBase + uint(k)];
}
uint projectionSlot(uint probe) { return probes[probe].tile; }
int projectionLevel(uint probe) { return int(probes[probe].level); }
float projectionQualityScale(uint probe) { return probes[probe].qualityScale; }
vec3 projectionProbePosition(uint probe) { return probes[probe].position; }
float projectionDistance(uint probe, uint slot, int face, vec2 sc) {
    fetches += 1u;
    int level = int(probes[probe].level);
    ivec3 at = atlasTexel(slot, face, sc, max(pass.params.depthRes >> level, 1));
    float stored = level == 0 ? texelFetch(distanceTex, at, 0).r : texelFetch(coarseDistanceTex, at, 0).r;
    return stored * probes[probe].distanceScale;
}
vec2 projectionAoConfidence(uint probe, uint slot, int face, vec2 sc) {
    fetches += 1u;
    int level = int(probes[probe].level);
    ivec3 at = atlasTexel(slot, face, sc, pass.params.res >> level);
    return level == 0 ? texelFetch(aoTex, at, 0).rg : texelFetch(coarseAoTex, at, 0).rg;  // r = AO, g = confidence
}

#ifdef PROJECT_DIAGNOSTICS
// The diagnostics texel of a point with geometry (see the top of the file).
vec4 probeDiagnostics(ProjectedAo projected, bool fallbackPath, vec3 x, vec3 n) {
    if (projected.used == 0) return vec4(-1.0, 0.0, 0.0, 3.0);
    uint probe = projected.probe0;
    uint slot = probes[probe].tile;  // resident: projectCandidates just read it
    vec3 d = x - probes[probe].position;
    float distance = length(d);
    float cosine = -dot(n, d) / distance;
    vec2 sc;
    int face = cubeFaceOf(d, sc);
    int res = pass.params.res >> int(probes[probe].level);
    float footprint = sqrt(probeTexelArea(sc, distance, cosine, res, pass.params.minFacing));
    ivec3 at = atlasTexel(slot, face, sc, res);
    float confidence = probes[probe].level == 0u ? texelFetch(aoTex, at, 0).g : texelFetch(coarseAoTex, at, 0).g;
    return vec4(float(probe), footprint, confidence, fallbackPath ? 2.0 : 1.0);
}
#endif

void main() {
    uint stripe = counterStripe();  // pass_counters.glsl: no shared memory, no barrier
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (onScreen(px)) {
        float depth = texelFetch(depthTex, px, 0).r;
        float ao = 1.0;  // no geometry: open, as in the reference
#ifdef PROJECT_DIAGNOSTICS
        vec4 diagnostics = vec4(-1.0, 0.0, 0.0, 0.0);
#endif
        fetches += 1u;
        if (depth > 0.0) {
            vec3 x = (camera.worldFromView * vec4(viewPosition(px, depth), 1.0)).xyz;
            vec3 n = normalize(mat3(camera.worldFromView) * texelFetch(normalTex, px, 0).xyz);
            fetches += 1u;
            ivec3 cell = candidateCellOf(x, pass.gridOrigin, pass.cellSize, pass.gridDims);
            uint cellIndex = uint((cell.z * pass.gridDims.y + cell.y) * pass.gridDims.x + cell.x);
            cellBase = cellIndex * uint(pass.candidatesPerCell);
            // A cell none of whose candidates is resident (cell_residency.comp): what the loop would
            // find, without reading them one by one: nothing, and its first candidate as the one wanted.
            ProjectedAo projected = residentCount[cellIndex] == 0u
                                        ? ProjectedAo(1.0, 0, candidates[cellBase], kNoProbe, kNoProbe)
                                        : projectCandidates(pass.candidatesPerCell, x, n, pass.params);
            bool fallbackPath = projected.missing != kNoProbe;
            if (projected.used == 0 && pass.residentPerCell > 0) {
                // No resident candidate of the cell sees the point: the resident probes nearest it.
                ivec3 coarse = candidateCellOf(x, pass.residentOrigin, pass.residentCellSize, pass.residentDims);
                residentBase = uint((coarse.z * pass.residentDims.y + coarse.y) * pass.residentDims.x + coarse.x) *
                               uint(pass.residentPerCell);
                secondList = true;
                ProjectedAo more = projectCandidates(pass.residentPerCell, x, n, pass.params);
                secondList = false;
                if (more.used > 0) {
                    more.missing = projected.missing;  // what the pixel wanted is still the cell's candidate
                    projected = more;
                    fallbackPath = true;
                }
            }
            ao = projected.ao;
#ifdef PROJECT_DIAGNOSTICS
            diagnostics = probeDiagnostics(projected, fallbackPath, x, n);
#endif
            atomicAdd(counters[stripe].geometry, 1u);
            if (projected.used == 0) {
                ao = pass.uncoveredAo;
                atomicAdd(counters[stripe].uncovered, 1u);
            } else if (fallbackPath) {
                atomicAdd(counters[stripe].fallbackProbe, 1u);
            }
            if ((px.x & 3) == 0 && (px.y & 3) == 0) {
                // Weight 2 for the probe the point wants most: the missing one ranked first, else
                // the best it used; 1 for its blend partner. A probe every pixel blends cannot then
                // outweigh one the pixels would rather have.
                demandProbe(projected.missing != kNoProbe ? projected.missing : projected.probe0, 2u);
                if (projected.missing != kNoProbe) demandProbe(projected.probe0, 1u);
                demandProbe(projected.probe1, 1u);
            }
        }
        imageStore(aoOut, px, vec4(ao));
#ifdef PROJECT_DIAGNOSTICS
        imageStore(diagnosticsOut, px, diagnostics);
#endif
    }
    countFetches(stripe, fetches);
}

#version 450 core
// How many of each candidate cell's K probes are resident (src/cubeao/runtime/probe_projection.h), run
// whenever the pool or the cells change. A pixel in a cell with none goes straight to the second list
// (project.comp): under a budget that cannot hold a frame's candidates (10,000 probes, a quarter of
// Sibenik's) most pixels are in such cells, and walking their K candidates one table read at a time
// only to pass each over was a quarter of the projection on llvmpipe.
#include "runtime_layout.h"

layout(local_size_x = 64) in;

layout(std430, binding = kProbeTableBuffer) readonly buffer ProbeTable { ProbeEntry probes[]; };
layout(std430, binding = kCandidateBuffer) readonly buffer Candidates { uint candidates[]; };
layout(std430, binding = kCellResidentCountBuffer) writeonly buffer CellResidentCounts { uint residentCount[]; };

// The candidate grid's cell count and K (ProjectBlock, the projection's own block).
layout(std140, binding = kProjectBlock) uniform ProjectUniforms { ProjectBlock pass; };

void main() {
    // A grid can have more cells than one dispatch has invocations along x: stride over them.
    for (uint c = gl_GlobalInvocationID.x; c < pass.cellCount; c += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        uint resident = 0u;
        for (int k = 0; k < pass.candidatesPerCell; ++k) {
            uint probe = candidates[c * uint(pass.candidatesPerCell) + uint(k)];
            if (probe == kNoProbe) break;
            if (probes[probe].tile != kNoSlot) resident += 1u;
        }
        residentCount[c] = resident;
    }
}

// Counting into the striped PassCounters (runtime_layout.h kCounterStripes): the stripe of this
// invocation's work group, and a 64-bit fetch count added with its carry. GLSL only.
#pragma once

#include "runtime_layout.h"

layout(std430, binding = kPassCountersBuffer) buffer Counters { PassCounters counters[kCounterStripes]; };

uint counterStripe() { return (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) % kCounterStripes; }

void countFetches(uint stripe, uint fetches) {
    if (fetches == 0u) return;
    uint before = atomicAdd(counters[stripe].fetchesLow, fetches);
    if (before + fetches < before) atomicAdd(counters[stripe].fetchesHigh, 1u);  // carry
}

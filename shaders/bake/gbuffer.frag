#version 450 core
// Cube G-buffer, fragment stage: the triangle's geometric normal (from a per-triangle table, exact
// like Embree's Ng, not interpolated) turned to face the probe, and the distance from the probe to
// the surface point at the texel centre (perspective-correct interpolation of the world position).
#include "bake_layout.h"

layout(std430, binding = kBakeTriangleNormalsBuffer) readonly buffer TriangleNormals { vec4 triangleNormal[]; };
layout(std140, binding = kBakeBlock) uniform BakeUniforms { BakeBlock bake; };
in vec3 fWorld;
layout(location = 0) out vec4 gbuffer;  // (normal, distance)

void main() {
    vec3 d = fWorld - bake.probe;
    vec3 n = triangleNormal[gl_PrimitiveID].xyz;
    gbuffer = vec4(dot(n, d) > 0.0 ? -n : n, length(d));
}

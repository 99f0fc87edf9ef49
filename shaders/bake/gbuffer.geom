#version 450 core
// Cube G-buffer, layered: one geometry-shader invocation per cube face routes the triangle to
// layer gl_Layer, skipping faces whose frustum it cannot touch (all three vertices beyond one side
// plane), so each triangle is rasterised only where it can cover texels.
#include "bake_layout.h"

layout(triangles, invocations = 6) in;
layout(triangle_strip, max_vertices = 3) out;

layout(std140, binding = kBakeBlock) uniform BakeUniforms { BakeBlock bake; };
in vec3 vWorld[];
out vec3 fWorld;

void main() {
    int face = gl_InvocationID;
    vec4 c[3];
    for (int k = 0; k < 3; ++k) c[k] = bake.clipFromWorld[face] * vec4(vWorld[k], 1.0);
    vec3 x = vec3(c[0].x, c[1].x, c[2].x), y = vec3(c[0].y, c[1].y, c[2].y), w = vec3(c[0].w, c[1].w, c[2].w);
    if (all(greaterThan(x, w)) || all(lessThan(x, -w)) || all(greaterThan(y, w)) || all(lessThan(y, -w)) ||
        all(lessThanEqual(w, vec3(0.0))))
        return;
    for (int k = 0; k < 3; ++k) {
        gl_Layer = face;
        gl_PrimitiveID = gl_PrimitiveIDIn;
        fWorld = vWorld[k];
        gl_Position = c[k];
        EmitVertex();
    }
    EndPrimitive();
}

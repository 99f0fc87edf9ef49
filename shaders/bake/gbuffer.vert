#version 450 core
// Cube G-buffer, vertex stage: world positions in; the face projection happens here (six passes) or
// in gbuffer.geom (LAYERED: one draw, six layers).
#include "bake_layout.h"

layout(location = 0) in vec3 position;

#ifdef LAYERED
out vec3 vWorld;
void main() { vWorld = position; }
#else
layout(std140, binding = kBakeBlock) uniform BakeUniforms { BakeBlock bake; };  // the face's in clipFromWorld[0]
out vec3 fWorld;
void main() {
    fWorld = position;
    gl_Position = bake.clipFromWorld[0] * vec4(position, 1.0);
}
#endif

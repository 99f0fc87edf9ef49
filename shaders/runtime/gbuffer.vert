#version 450 core
// Camera G-buffer, vertex stage (src/cubeao/runtime/camera_gbuffer.h): world positions in, view-space
// position out for the fragment stage, reversed-Z clip position (camera_view.h clipFromView).
#include "runtime_layout.h"

layout(location = 0) in vec3 position;
layout(std140, binding = kGBufferBlock) uniform GBufferUniforms { GBufferBlock transforms; };
out vec3 fView;

void main() {
    vec4 v = transforms.viewFromWorld * vec4(position, 1.0);
    fView = v.xyz;
    gl_Position = transforms.clipFromView * v;
}

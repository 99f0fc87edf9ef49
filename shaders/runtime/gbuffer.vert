#version 450 core
// Camera G-buffer, vertex stage (src/cubeao/runtime/camera_gbuffer.h): world positions in, view-space
// position out for the fragment stage, reversed-Z clip position (camera_view.h clipFromView).
layout(location = 0) in vec3 position;
uniform mat4 viewFromWorld;
uniform mat4 clipFromView;
out vec3 fView;

void main() {
    vec4 v = viewFromWorld * vec4(position, 1.0);
    fView = v.xyz;
    gl_Position = clipFromView * v;
}

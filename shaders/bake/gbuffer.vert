#version 450 core
// Cube G-buffer, vertex stage: world positions in; the face projection happens here (six passes) or
// in gbuffer.geom (LAYERED: one draw, six layers).
layout(location = 0) in vec3 position;

#ifdef LAYERED
out vec3 vWorld;
void main() { vWorld = position; }
#else
uniform mat4 clipFromWorld;
out vec3 fWorld;
void main() {
    fWorld = position;
    gl_Position = clipFromWorld * vec4(position, 1.0);
}
#endif

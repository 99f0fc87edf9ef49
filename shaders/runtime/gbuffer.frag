#version 450 core
// Camera G-buffer, fragment stage: view depth of the surface at the pixel centre (perspective-correct
// interpolation of the view position) and the triangle's geometric normal in view space, turned to
// face the camera (open architecture is two-sided, as in the reference and the bake).
#include "runtime_layout.h"

layout(std430, binding = kTriangleNormalsBuffer) readonly buffer TriangleNormals { vec4 triangleNormal[]; };  // world space
layout(std140, binding = kGBufferBlock) uniform GBufferUniforms { GBufferBlock transforms; };
in vec3 fView;
layout(location = 0) out float depth;
layout(location = 1) out vec4 normal;

void main() {
    vec3 n = mat3(transforms.viewFromWorld) * triangleNormal[gl_PrimitiveID].xyz;
    depth = -fView.z;
    normal = vec4(dot(n, fView) > 0.0 ? -n : n, 0.0);
}

// One lit pixel of the preview composite (src/cubeao/runtime/composite.h): i = i_s · [(1 − α) + α · ao],
// i_s = albedo · (ambient + diffuse · max(0, n·l)), Lambert under one directional light plus ambient.
// shaders/runtime/composite.comp and the CPU twin compositePixel both call it.
#pragma once

#include "glsl_cpp.h"

CUBEAO_KERNEL_BEGIN

// View-space unit normal and direction towards the light; the colour clamped to [0, 1].
CUBEAO_FN vec3 compositeColour(vec3 normal, vec3 light, float ao, vec3 albedo, float ambient, float diffuse,
                               float alpha) {
    vec3 direct = albedo * (ambient + diffuse * max(0.0f, dot(normal, light)));
    return clamp(direct * ((1.0f - alpha) + alpha * ao), vec3(0.0f), vec3(1.0f));
}

CUBEAO_KERNEL_END

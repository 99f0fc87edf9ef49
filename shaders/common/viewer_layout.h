// What the viewer's drawing of a view mode (shaders/viewer/view.frag, tools/cubeao-view/view_modes.cpp)
// reads besides its textures, whose units the C++ side injects as defines with the mode numbers.
#pragma once

#include "glsl_cpp.h"

CUBEAO_KERNEL_BEGIN

// Uniform block binding, apart from the run-time's (runtime_layout.h) and the bake's (bake_layout.h).
CUBEAO_CONST int kViewBlock = 7;

// One draw's parameters (std140), set before each draw.
struct ViewBlock {
    ivec4 viewportRect;    // x, y, width, height of the viewport drawn into
    int mode;              // MODE_* (a ViewMode), MODE_UNAVAILABLE where its input is missing
    float footprintScale;  // world units per texel at the middle of the footprint ramp
    int hasAo;             // 1: aoTex is bound (the diagnostic modes shade by it when it is)
    int encodeSrgb;        // 1: write sRGB-encoded colour (a plain RGBA8 framebuffer)
};

CUBEAO_KERNEL_END

#ifdef __cplusplus
#include <cstddef>  // offsetof

static_assert(sizeof(cubeao::kernel::ViewBlock) == 32 && offsetof(cubeao::kernel::ViewBlock, mode) == 16 &&
                  offsetof(cubeao::kernel::ViewBlock, encodeSrgb) == 28,
              "ViewBlock must keep std140 offsets (view.frag reads it as a uniform block)");
#endif

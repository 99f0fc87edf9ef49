// Mathematical constants for every kernel and shader. Digits beyond float precision are harmless:
// both languages round to the nearest float.
#pragma once

#include "glsl_cpp.h"

CUBEAO_KERNEL_BEGIN

CUBEAO_CONST float kPi = 3.14159265358979323846f;
CUBEAO_CONST float kTwoPi = 6.28318530717958647692f;
CUBEAO_CONST float kInvPi = 0.31830988618379067154f;

CUBEAO_KERNEL_END

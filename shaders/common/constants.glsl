// Mathematical constants for every shader: #include "constants.glsl" (resolved by the shader loader,
// src/cubeao/gl/shader.h). Digits beyond float precision are harmless: GLSL rounds to the nearest float.
const float kPi = 3.14159265358979323846;
const float kTwoPi = 6.28318530717958647692;
const float kInvPi = 0.31830988618379067154;

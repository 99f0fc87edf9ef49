#version 450 core
// GTAO in screen space, the baseline: every pixel through the frame of ssao.glsl, with the estimator
// of gtao_march.glsl (which the probe projection's fallback, gtao_fill.comp, runs too).
#include "ssao.glsl"
#include "gtao_march.glsl"

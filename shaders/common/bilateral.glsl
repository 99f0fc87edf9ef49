// Weight of a blur tap: GLSL twin of bilateralWeight() in src/cubeao/runtime/blur.cpp (read blur.h for
// the formula and its sources: paper 000 eq. 3.2.2, paper 002 listing 3.16).
#pragma once

float bilateralWeight(vec3 centreNormal, vec3 centrePoint, float centreDepth, vec3 tapNormal, vec3 tapPoint,
                      float normalPower, float depthTolerance) {
    float normalTerm = pow(max(0.0, 0.5 * (dot(centreNormal, tapNormal) + 1.0)), normalPower);
    float planeDistance = abs(dot(centreNormal, tapPoint - centrePoint));
    float depthTerm = max(0.0, 1.0 - planeDistance / (depthTolerance * centreDepth));
    return normalTerm * depthTerm;
}

#version 450 core
// The viewer's view modes (tools/cubeao-view/view_modes.h): one fragment per window pixel, the frame's
// texel under it fetched nearest, coloured by mode. The C++ side injects the texture units (*_UNIT) and
// the mode numbers (MODE_*, the enum's values; MODE_UNAVAILABLE for a mode whose input is missing).
//
// Colour is built in display space (sRGB-encoded): the ramps are defined there and interpolate evenly
// there. AO and the composite are shown as their values (display byte = 255 · value), as the PNG
// previews of `cubeao render` and engines' AO maps store them: an sRGB encode would lift AO 0.8 to
// 0.91 and leave the occlusion the viewer exists to show barely visible. "Shading by AO" multiplies a
// display colour by the AO. The result is written as is for a plain RGBA8 framebuffer, or decoded
// to linear when the framebuffer encodes by itself (viewer.encodeSrgb 0).
#include "viewer_layout.h"

layout(binding = SHADED_UNIT) uniform sampler2D shadedTex;            // RGBA8, linear
layout(binding = AO_UNIT) uniform sampler2D aoTex;                    // R32F, 1 = open
layout(binding = DIAGNOSTICS_UNIT) uniform sampler2D diagnosticsTex;  // RGBA32F, project.comp's layout
layout(binding = BASELINE_UNIT) uniform sampler2D baselineTex;        // R32F
layout(binding = REFERENCE_UNIT) uniform sampler2D referenceTex;      // R32F

layout(std140, binding = kViewBlock) uniform ViewUniforms { ViewBlock viewer; };

out vec4 colour;

const vec3 kSky = vec3(0.07, 0.09, 0.22);          // no geometry: dark blue
const vec3 kAmber = vec3(1.00, 0.68, 0.12);        // fallback probe
const vec3 kMagenta = vec3(0.93, 0.22, 0.80);      // screen space
const vec3 kDiffDarker = vec3(0.23, 0.30, 0.75);   // diverging ramp ends (Moreland's cool-warm)
const vec3 kDiffBrighter = vec3(0.71, 0.02, 0.15);
const float kDiffFullScale = 0.25;                 // |AO − reference| at full saturation

// The texel of `tex` under this fragment: the image fills the viewport, row 0 at its top (textures
// are stored top row first, camera_view.h; GL's window row 0 is the bottom).
ivec2 texelOf(sampler2D tex) {
    ivec2 size = textureSize(tex, 0);
    vec2 uv = (gl_FragCoord.xy - vec2(viewer.viewportRect.xy)) / vec2(viewer.viewportRect.zw);
    uv.y = 1.0 - uv.y;
    return clamp(ivec2(floor(uv * vec2(size))), ivec2(0), size - 1);
}

vec3 srgbDecode(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), step(vec3(0.04045), c));
}

// Polynomial fits of matplotlib's viridis and plasma (Matt Zucker, CC0), t in [0, 1], display space.
vec3 viridis(float t) {
    const vec3 c0 = vec3(0.2777273272234177, 0.005407344544966578, 0.3340998053353061);
    const vec3 c1 = vec3(0.1050930431085774, 1.404613529898575, 1.384590162594685);
    const vec3 c2 = vec3(-0.3308618287255563, 0.214847559468213, 0.09509516302823659);
    const vec3 c3 = vec3(-4.634230498983486, -5.799100973351585, -19.33244095627987);
    const vec3 c4 = vec3(6.228269936347081, 14.17993336680509, 56.69055260068105);
    const vec3 c5 = vec3(4.776384997670288, -13.74514537774601, -65.35303263337234);
    const vec3 c6 = vec3(-5.435455855934631, 4.645852612178535, 26.3124352495832);
    return clamp(c0 + t * (c1 + t * (c2 + t * (c3 + t * (c4 + t * (c5 + t * c6))))), 0.0, 1.0);
}

vec3 plasma(float t) {
    const vec3 c0 = vec3(0.05873234392399702, 0.02333670892565664, 0.5433401826748754);
    const vec3 c1 = vec3(2.176514634195958, 0.2383834171260182, 0.7539604599784036);
    const vec3 c2 = vec3(-2.689460476458034, -7.455851135738909, 3.110799939717086);
    const vec3 c3 = vec3(6.130348345893603, 42.3461881477227, -28.51885465332158);
    const vec3 c4 = vec3(-11.10743619062271, -82.66631109428045, 60.13984767418263);
    const vec3 c5 = vec3(10.02306557647065, 71.41361770095349, -54.07218655560067);
    const vec3 c6 = vec3(-3.658713842777788, -22.93153465461149, 18.19190778539828);
    return clamp(c0 + t * (c1 + t * (c2 + t * (c3 + t * (c4 + t * (c5 + t * c6))))), 0.0, 1.0);
}

vec3 hsv(float h, float s, float v) {
    vec3 k = clamp(abs(mod(h * 6.0 + vec3(0.0, 4.0, 2.0), 6.0) - 3.0) - 1.0, 0.0, 1.0);
    return v * mix(vec3(1.0), k, s);
}

// A well-mixed 32-bit hash (lowbias32, Chris Wellons).
uint hash(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

// Hues step by the golden ratio from id to id, which keeps a few dozen probes' hues well apart; the
// hash varies saturation and value, so that two probes whose hues do come close still differ.
vec3 probeColour(uint id) {
    uint h = hash(id);
    float hue = fract(float(id) * 0.6180339887);
    float saturation = 0.45 + 0.40 * float(h & 0xffu) / 255.0;
    float value = 0.72 + 0.28 * float((h >> 8) & 0xffu) / 255.0;
    return hsv(hue, saturation, value);
}

// Display grey of an AO: the value itself (see the top of the file).
float aoGrey(float ao) { return clamp(ao, 0.0, 1.0); }

// How much a diagnostic colour is darkened by the AO: `strength` 0 = not at all, 1 = like the AO grey.
float aoShade(float strength) {
    if (viewer.hasAo == 0) return 1.0;
    return mix(1.0, aoGrey(texelFetch(aoTex, texelOf(aoTex), 0).r), strength);
}

vec3 diagnosticColour(vec4 d) {
    int path = int(d.a + 0.5);
    if (path == 0) return kSky;
    if (viewer.mode == MODE_PATH) {
        if (path == 2) return kAmber * aoShade(0.6);
        if (path == 3) return kMagenta * aoShade(0.6);
        return vec3(viewer.hasAo != 0 ? aoShade(1.0) : 0.75);  // probe: the neutral grey of the AO
    }
    if (path == 3) return vec3(0.42) * aoShade(0.7);  // uncovered: no probe, no value; a dim neutral grey
    if (viewer.mode == MODE_PROBE_ID) return probeColour(uint(d.r + 0.5)) * aoShade(0.75);
    if (viewer.mode == MODE_FOOTPRINT) {
        // Fine (≤ 1/8 of the scale) → coarse (≥ 8×), logarithmic: the scale itself is the middle.
        float t = clamp(0.5 + log2(max(d.g, 1e-20) / viewer.footprintScale) / 6.0, 0.0, 1.0);
        return viridis(t) * aoShade(0.7);
    }
    return plasma(clamp(d.b, 0.0, 1.0)) * aoShade(0.7);  // MODE_CONFIDENCE
}

vec3 displayColour() {
    if (viewer.mode == MODE_SHADED) return clamp(texelFetch(shadedTex, texelOf(shadedTex), 0).rgb, 0.0, 1.0);
    if (viewer.mode == MODE_AO) return vec3(aoGrey(texelFetch(aoTex, texelOf(aoTex), 0).r));
    if (viewer.mode == MODE_BASELINE) return vec3(aoGrey(texelFetch(baselineTex, texelOf(baselineTex), 0).r));
    if (viewer.mode == MODE_REFERENCE_DIFF) {
        float diff = texelFetch(aoTex, texelOf(aoTex), 0).r - texelFetch(referenceTex, texelOf(referenceTex), 0).r;
        float t = clamp(diff / kDiffFullScale, -1.0, 1.0);
        return mix(vec3(1.0), t < 0.0 ? kDiffDarker : kDiffBrighter, abs(t));
    }
    if (viewer.mode == MODE_UNAVAILABLE) {  // diagonal stripes: clearly not an image
        float stripe = mod(floor((gl_FragCoord.x + gl_FragCoord.y) / 12.0), 2.0);
        return mix(vec3(0.16, 0.16, 0.17), vec3(0.24, 0.24, 0.26), stripe);
    }
    return diagnosticColour(texelFetch(diagnosticsTex, texelOf(diagnosticsTex), 0));
}

void main() {
    vec3 c = displayColour();
    colour = vec4(viewer.encodeSrgb != 0 ? c : srgbDecode(c), 1.0);
}

// The viewer's view modes (issue 14): what the window shows of a frame. Each mode is one full-screen
// triangle drawn by shaders/viewer/view.vert + view.frag from the frame's textures: the shaded
// composite, the AO, the probe projection's per-pixel diagnostics (ProbeProjectionPass::setDiagnostics:
// probe id, texel footprint, confidence, path), a screen-space baseline's AO, or the difference to a
// reference AO. Row 0 of the textures is the image top (camera_view.h); the shader flips them upright.
// AO and the composite are shown as their values (display byte = 255 · value, like `cubeao render`'s
// PNG previews), the colour ramps in display space, for a plain RGBA8 framebuffer
// (setSrgbFramebuffer when the caller draws into an sRGB one with GL_FRAMEBUFFER_SRGB on).
#pragma once

#include <optional>
#include <span>
#include <string_view>

#include "cubeao-view/view_mode.h"
#include "cubeao/gl/handles.h"
#include "cubeao/gl/uniform_block.h"

namespace cubeao::viewer {

// The frame's textures (GL names, 0 = not available), all of the frame's size: single-level textures
// (immutable storage) or otherwise complete ones; they are read with texelFetch, so their filters do
// not matter.
struct ViewInputs {
    GLuint shaded = 0;       // RGBA8 composite, linear (FramePipeline::shadedTexture)
    GLuint ao = 0;           // R32F blurred AO, 1 = open (FramePipeline::aoTexture)
    GLuint diagnostics = 0;  // RGBA32F from ProbeProjectionPass::diagnosticsTexture
    GLuint baselineAo = 0;   // R32F AO of a screen-space baseline, same size
    GLuint reference = 0;    // R32F reference AO of this frame (Embree, from `cubeao reference` EXRs)
    // World units per probe texel that count as "fine enough" (e.g. the AO radius / 16): the middle
    // of the footprint ramp; an eighth of it and below is the finest colour, eight times it the coarsest.
    float footprintScale = 1.0f;
};

// What a mode reads: whether it can be drawn from `in`. Shaded: shaded; Ao: ao; ProbeId, Footprint,
// Confidence, Path: diagnostics (AO, when given, shades them so the geometry stays readable); Baseline:
// baselineAo; ReferenceDiff: ao and reference.
bool viewModeAvailable(ViewMode mode, const ViewInputs& in);

class ViewModes {  // needs a current GL 4.5 context
public:
    ViewModes();

    // Draws `mode` as a full-screen triangle into the bound draw framebuffer's viewport (x, y, w, h),
    // the image scaled to fill it (nearest texel). A mode whose input is missing draws grey
    // "not available" stripes and returns false. The caller's scissor test applies. Leaves the
    // viewport, depth test, blending and culling as it found them; binds its program and texture
    // units 0–4.
    bool draw(ViewMode mode, const ViewInputs& in, int x, int y, int width, int height);

    // True when the draw framebuffer encodes sRGB itself (an sRGB framebuffer with GL_FRAMEBUFFER_SRGB
    // enabled): the shader then writes linear colour. Default false: a plain RGBA8 framebuffer.
    void setSrgbFramebuffer(bool srgb) { srgbFramebuffer_ = srgb; }
    GLuint program() const { return program_.id(); }  // for the layout test

private:
    gl::Program program_;
    gl::VertexArray vertexArray_;  // empty: the vertex shader makes the triangle from gl_VertexID
    gl::UniformBlock block_;  // kernel::ViewBlock, per draw
    bool srgbFramebuffer_ = false;
};

}  // namespace cubeao::viewer

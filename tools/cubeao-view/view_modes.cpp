#include "cubeao-view/view_modes.h"

#include <array>
#include <string>

#include "common/viewer_layout.h"
#include "cubeao/core/error.h"
#include "cubeao/gl/shader.h"
#include "cubeao/gl/state.h"

namespace cubeao::viewer {
namespace {

// Texture units of view.frag (injected as defines: one source of truth). The viewer draws after the
// frame's passes, which bind their own units again each frame.
constexpr int kShadedUnit = 0, kAoUnit = 1, kDiagnosticsUnit = 2, kBaselineUnit = 3, kReferenceUnit = 4;
constexpr int kUnavailable = -1;  // MODE_UNAVAILABLE

}  // namespace

bool viewModeAvailable(ViewMode mode, const ViewInputs& in) {
    switch (mode) {
        case ViewMode::Shaded: return in.shaded != 0;
        case ViewMode::Ao: return in.ao != 0;
        case ViewMode::ProbeId:
        case ViewMode::Footprint:
        case ViewMode::Confidence:
        case ViewMode::Path: return in.diagnostics != 0;
        case ViewMode::Baseline: return in.baselineAo != 0;
        case ViewMode::ReferenceDiff: return in.ao != 0 && in.reference != 0;
    }
    return false;
}

ViewModes::ViewModes() {
    const auto define = [](const char* name, int value) {
        return std::pair<std::string, std::string>(name, std::to_string(value));
    };
    const gl::ShaderDefines defines = {
        define("SHADED_UNIT", kShadedUnit),
        define("AO_UNIT", kAoUnit),
        define("DIAGNOSTICS_UNIT", kDiagnosticsUnit),
        define("BASELINE_UNIT", kBaselineUnit),
        define("REFERENCE_UNIT", kReferenceUnit),
        define("MODE_SHADED", int(ViewMode::Shaded)),
        define("MODE_AO", int(ViewMode::Ao)),
        define("MODE_PROBE_ID", int(ViewMode::ProbeId)),
        define("MODE_FOOTPRINT", int(ViewMode::Footprint)),
        define("MODE_CONFIDENCE", int(ViewMode::Confidence)),
        define("MODE_PATH", int(ViewMode::Path)),
        define("MODE_BASELINE", int(ViewMode::Baseline)),
        define("MODE_REFERENCE_DIFF", int(ViewMode::ReferenceDiff)),
        define("MODE_UNAVAILABLE", kUnavailable),
    };
    program_ = gl::compileRenderProgram("viewer/view.vert", "viewer/view.frag", defines);
    vertexArray_ = gl::VertexArray::create();
}

bool ViewModes::draw(ViewMode mode, const ViewInputs& in, int x, int y, int width, int height) {
    const bool available = viewModeAvailable(mode, in);
    const kernel::ViewBlock block{{x, y, width, height},
                                  available ? int(mode) : kUnavailable,
                                  in.footprintScale > 0.0f ? in.footprintScale : 1.0f,
                                  in.ao != 0 ? 1 : 0,
                                  srgbFramebuffer_ ? 0 : 1};
    // Every unit gets its texture or none: the shader only reads those the mode needs.
    glBindTextureUnit(kShadedUnit, in.shaded);
    glBindTextureUnit(kAoUnit, in.ao);
    glBindTextureUnit(kDiagnosticsUnit, in.diagnostics);
    glBindTextureUnit(kBaselineUnit, in.baselineAo);
    glBindTextureUnit(kReferenceUnit, in.reference);

    {
        const gl::SavedState saved;  // the panel and the next frame draw on the state they set
        glDisable(GL_DEPTH_TEST), glDisable(GL_BLEND), glDisable(GL_CULL_FACE);
        glViewport(x, y, width, height);
        glUseProgram(program_.id());
        block_.upload(block, kernel::kViewBlock);  // in order: a draw before this one keeps its own
        glBindVertexArray(vertexArray_.id());
        glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    return available;
}

}  // namespace cubeao::viewer

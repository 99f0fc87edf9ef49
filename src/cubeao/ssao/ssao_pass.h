// The screen-space baselines as run-time AO passes (runtime/ao_pass.h): one compute program per
// method, shaders/ssao/{alchemy,hbao,gtao}.comp on the frame of shaders/common/ssao.glsl. What each
// computes and its parameters: ssao_settings.h.
#pragma once

#include "common/runtime_layout.h"
#include "cubeao/gl/handles.h"
#include "cubeao/gl/uniform_block.h"
#include "cubeao/runtime/ao_pass.h"
#include "cubeao/ssao/ssao_settings.h"

namespace cubeao {

// The block of a screen-space AO program's parameters that `settings` fix for its lifetime:
// SsaoPass's, and the GTAO fallback's (gtao_fallback.h), so a filled pixel is estimated exactly as
// the gtao pass estimates it.
kernel::SsaoBlock ssaoBlock(const SsaoSettings& settings);

class SsaoPass final : public AoPass {
public:
    // `settings` must be resolved (resolveSsaoSettings). Compiles the method's program: needs a
    // current GL 4.5 context.
    explicit SsaoPass(const SsaoSettings& settings);

    const char* name() const override { return ssaoMethodName(settings_.method); }
    void run(const CameraGBuffer& gbuffer, const CameraView& view, std::uint32_t frame, GLuint aoImage) override;
    double fetchesPerPixel() const override;
    const SsaoSettings& settings() const { return settings_; }

private:
    SsaoSettings settings_;
    gl::Program program_;
    gl::UniformBlock block_;   // kernel::SsaoBlock, fixed
    gl::UniformBlock camera_;  // kernel::CameraBlock, per frame
    gl::Buffer fetchCount_;
    double pixels_ = 0.0;  // of the last run
};

}  // namespace cubeao

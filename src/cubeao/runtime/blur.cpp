#include "cubeao/runtime/blur.h"

#include <algorithm>
#include <string>
#include <vector>

#include "common/bilateral.h"
#include "common/runtime_layout.h"
#include "cubeao/core/error.h"
#include "cubeao/gl/shader.h"

namespace cubeao {

BlurSettings probeBlurSettings(int res, int height, float tanHalfFovY) {
    BlurSettings s;
    const double pixelsPerTexel = double(height) / (double(std::max(res, 1)) * double(tanHalfFovY));
    if (pixelsPerTexel <= 3.0) s.radius = 1;  // also when the field of view is degenerate (inf, NaN: 2)
    return s;
}

void validateBlurSettings(const BlurSettings& s) {
    std::vector<std::string> problems;
    if (s.radius < 0 || s.radius > 32) problems.push_back("--blur " + std::to_string(s.radius) + ": expected 0..32 taps");
    if (!(s.normalPower >= 0.0f)) problems.push_back("blur normal power k_n must be ≥ 0");
    if (!(s.depthTolerance > 0.0f)) problems.push_back("blur depth tolerance τ must be positive");
    if (!problems.empty()) {
        std::string message = "bad blur settings:";
        for (const auto& p : problems) message += "\n  " + p;
        throw UsageError(message);
    }
}

float bilateralWeight(const glm::vec3& centreNormal, const glm::vec3& centrePoint, float centreDepth,
                      const glm::vec3& tapNormal, const glm::vec3& tapPoint, const BlurSettings& s) {
    return kernel::bilateralWeight(centreNormal, centrePoint, centreDepth, tapNormal, tapPoint, s.normalPower,
                                   s.depthTolerance);
}

float spatialWeight(int tap, int radius) { return kernel::bilateralSpatialWeight(tap, radius); }

namespace {

// One pass along (dx, dy): the twin of shaders/runtime/blur.comp.
Image blurPass(const Image& in, const CameraGBufferImage& g, const CameraView& view, const BlurSettings& s, int dx, int dy) {
    Image out = in;
    for (int y = 0; y < g.height; ++y)
        for (int x = 0; x < g.width; ++x) {
            const float zc = g.depth[g.index(x, y)];
            if (!(zc > 0.0f)) continue;
            const glm::vec3 nc = g.normal[g.index(x, y)], pc = view.viewPosition(x, y, zc);
            float sum = in.at(x, y), weights = 1.0f;
            for (int i = -s.radius; i <= s.radius; ++i) {
                const int sx = x + i * dx, sy = y + i * dy;
                if (i == 0 || sx < 0 || sy < 0 || sx >= g.width || sy >= g.height) continue;
                const float zs = g.depth[g.index(sx, sy)];
                if (!(zs > 0.0f)) continue;
                const float w = spatialWeight(i, s.radius) *
                                bilateralWeight(nc, pc, zc, g.normal[g.index(sx, sy)], view.viewPosition(sx, sy, zs), s);
                sum += w * in.at(sx, sy);
                weights += w;
            }
            out.at(x, y) = sum / weights;
        }
    return out;
}

}  // namespace

Image blurAoCpu(const Image& ao, const CameraGBufferImage& g, const CameraView& view, const BlurSettings& s) {
    if (ao.width != g.width || ao.height != g.height) throw Error("blurAoCpu: AO image and G-buffer differ in size");
    if (s.radius == 0) return ao;
    return blurPass(blurPass(ao, g, view, s, 1, 0), g, view, s, 0, 1);
}

Blur::Blur(const BlurSettings& settings) {
    program_ = gl::compileComputeProgram("runtime/blur.comp");
    setSettings(settings);
}

void Blur::setSettings(const BlurSettings& settings) {
    validateBlurSettings(settings);
    settings_ = settings;
}

void Blur::run(const CameraGBuffer& gbuffer, const CameraView& view, GLuint input, GLuint output) {
    const int w = gbuffer.width(), h = gbuffer.height();
    if (settings_.radius == 0) {
        glCopyImageSubData(input, GL_TEXTURE_2D, 0, 0, 0, 0, output, GL_TEXTURE_2D, 0, 0, 0, 0, w, h, 1);
        return;
    }
    if (w != width_ || h != height_) {
        intermediate_ = gl::Texture::create(GL_TEXTURE_2D);
        glTextureStorage2D(intermediate_.id(), 1, GL_R32F, w, h);
        width_ = w, height_ = h;
    }
    glUseProgram(program_.id());
    camera_.upload(view.block(w, h), kernel::kCameraBlock);
    glBindTextureUnit(kernel::kGBufferDepthUnit, gbuffer.depthTexture());
    glBindTextureUnit(kernel::kGBufferNormalUnit, gbuffer.normalTexture());
    const GLuint groupsX = kernel::pixelGroups(w), groupsY = kernel::pixelGroups(h);
    const GLuint passes[2][2] = {{input, intermediate_.id()}, {intermediate_.id(), output}};
    for (int pass = 0; pass < 2; ++pass) {
        // GL orders the update after the first dispatch, which still reads the first axis.
        const glm::ivec2 axis = pass == 0 ? glm::ivec2(1, 0) : glm::ivec2(0, 1);
        block_.upload(kernel::BlurBlock{axis, settings_.radius, settings_.normalPower, settings_.depthTolerance},
                      kernel::kBlurBlock);
        glBindTextureUnit(kernel::kAoInputUnit, passes[pass][0]);
        glBindImageTexture(kernel::kAoImageUnit, passes[pass][1], 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
        glDispatchCompute(groupsX, groupsY, 1);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }
}

}  // namespace cubeao

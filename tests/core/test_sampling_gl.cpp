// The GLSL sampling header (shaders/common/sampling.h) against its C++ twin
// (src/cubeao/core/sampling.h): the GPU bake must trace the rays the Embree twin traces.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include <glm/vec4.hpp>

#include "cubeao/gl/handles.h"
#include "cubeao/gl/shader.h"
#include "cubeao/core/sampling.h"
#include "gl_fixture.h"

namespace {

using namespace cubeao;

TEST_F(GlTest, SamplingHeaderMatchesTheCppTwin) {
    constexpr GLuint kCount = 256, kSpp = 64;  // 4 keys × 64 samples
    const std::string src = R"(#version 450 core
#include "sampling.h"
layout(local_size_x = 64) in;
layout(std430, binding = 0) writeonly buffer Out { vec4 values[]; };  // u, v, hash bits, 0 | direction
void main() {
    uint i = gl_GlobalInvocationID.x, s = i % SPP, key = hashKey(i / SPP, 7u, 3u);
    vec2 u = rotatedHammersley(s, SPP, key);
    vec3 n = normalize(vec3(0.3, -0.5, float(i / SPP) - 1.5));
    values[2u * i] = vec4(u, uintBitsToFloat(hash32(i)), 0.0);
    values[2u * i + 1u] = vec4(cosineHemisphere(u, n), 0.0);
})";
    const gl::Program program =
        gl::buildProgram({{GL_COMPUTE_SHADER, src, "sampling_test.comp"}}, {{"SPP", std::to_string(kSpp) + "u"}});
    const gl::Buffer buffer = gl::Buffer::create();
    glNamedBufferStorage(buffer.id(), 2 * kCount * sizeof(glm::vec4), nullptr, 0);
    glUseProgram(program.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffer.id());
    glDispatchCompute(kCount / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> gpu(2 * kCount);
    glGetNamedBufferSubData(buffer.id(), 0, GLsizeiptr(gpu.size() * sizeof(glm::vec4)), gpu.data());
    ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));

    for (GLuint i = 0; i < kCount; ++i) {
        const std::uint32_t sample = i % kSpp, key = sampling::hashKey(i / kSpp, 7u, 3u);
        const glm::vec2 u = sampling::rotatedHammersley(sample, kSpp, key);
        const glm::vec3 n = glm::normalize(glm::vec3(0.3f, -0.5f, float(i / kSpp) - 1.5f));
        const glm::vec3 d = sampling::cosineHemisphere(u, n);
        std::uint32_t bits = 0;
        std::memcpy(&bits, &gpu[2 * i].z, sizeof bits);
        EXPECT_EQ(bits, sampling::hash32(i)) << i;  // integer arithmetic: exact
        // GLSL division may be off by 2.5 ulp; sin/cos/sqrt differ from libm by a few ulp.
        EXPECT_NEAR(gpu[2 * i].x, u.x, 1e-6f) << i;
        EXPECT_NEAR(gpu[2 * i].y, u.y, 1e-6f) << i;
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(gpu[2 * i + 1][k], d[k], 1e-5f) << i << " component " << k;
    }
}

}  // namespace

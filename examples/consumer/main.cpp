// The cubeao run-time in an engine, in brief (docs/INTEGRATION.md shows this file): open a probe cache,
// build the frame pipeline (camera G-buffer -> probe projection -> blur -> composite) over the scene's
// triangles, render one frame and print its mean AO.
//
//   cubeao-consumer CACHE.cubeao MESH.obj
//
// The cache holds probes, not geometry: the triangles come from the engine, in the coordinates the cache
// was baked in. Here they are read from the triangle OBJ the cache was baked from.
// Exit codes: 0 done, 1 error, 2 usage, 77 no OpenGL 4.5 context on this machine.
#include <cstdint>
#include <cstdio>
#include <exception>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/runtime/runtime.h"  // the one cubeao header an engine needs

namespace {

struct Mesh {
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices;  // three per triangle
};

// The engine's own mesh in a real program. Reads "v x y z" and triangle "f a b c" lines (1-based,
// "a/t/n" allowed) and skips everything else.
Mesh readObj(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read " + path);
    Mesh mesh;
    for (std::string line; std::getline(in, line);) {
        std::istringstream words(line);
        std::string tag;
        words >> tag;
        if (tag == "v") {
            glm::vec3 p;
            words >> p.x >> p.y >> p.z;
            mesh.positions.push_back(p);
        } else if (tag == "f") {
            for (std::string corner; words >> corner;) mesh.indices.push_back(std::uint32_t(std::stoul(corner) - 1));
        }
    }
    return mesh;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: %s CACHE.cubeao MESH.obj\n", argv[0]);
        return 2;
    }
    try {
        // Every cubeao GL call needs a current OpenGL 4.5 context on the calling thread. An engine makes
        // its own current; this program makes a headless one (EGL, no window).
        std::string whyNot;
        const std::optional<cubeao::gl::HeadlessContext> context = cubeao::gl::HeadlessContext::tryCreate(&whyNot);
        if (!context) {
            std::fprintf(stderr, "no OpenGL 4.5 context: %s\n", whyNot.c_str());
            return 77;
        }

        // The cache is mapped, not read: probes stream to the GPU as the camera needs them. It must
        // outlive the projection pass.
        const cubeao::CacheReader cache(argv[1]);
        const Mesh mesh = readObj(argv[2]);

        // The probe projection as the pipeline's AO method, in at most 64 MiB of GPU memory.
        cubeao::ProbeProjectionSettings settings;
        settings.residency.gpuBudgetBytes = std::size_t(64) << 20;
        auto probes = std::make_unique<cubeao::ProbeProjectionPass>(cache, mesh.positions, mesh.indices, settings);
        const cubeao::ProbeProjectionPass& projection = *probes;  // the pipeline owns it from here
        cubeao::CompositeSettings composite;
        composite.lightDirection = cubeao::defaultLightDirection({0.0f, 1.0f, 0.0f});
        cubeao::FramePipeline pipeline(mesh.positions, mesh.indices, std::move(probes), cubeao::BlurSettings{},
                                       composite);

        // One frame of one camera. render() issues the GPU work and returns without waiting for it.
        cubeao::CameraPath camera;
        camera.frames.push_back({.eye = {-1.6f, 1.6f, 1.6f}, .target = {0.7f, 0.4f, 0.0f}});
        const cubeao::CameraView view =
            cubeao::CameraView::fromPinhole(cubeao::PinholeCamera(camera, 0, 160, 90), camera.nearPlane);
        pipeline.render(view, 0);

        // An engine samples pipeline.aoTexture() (R32F, 1 = open) or shadedTexture() in its own passes.
        // Here the AO is read back, which waits for the frame.
        std::vector<float> ao(std::size_t(pipeline.width()) * std::size_t(pipeline.height()));
        glGetTextureImage(pipeline.aoTexture(), 0, GL_RED, GL_FLOAT, GLsizei(ao.size() * sizeof(float)), ao.data());
        double sum = 0.0;
        for (float v : ao) sum += v;
        const cubeao::ProbeProjectionPass::PixelShares shares = projection.pixelShares();
        std::printf("mean AO %.4f over %dx%d pixels; %zu probes, %zu resident; uncovered %.3f; on %s; shaders %s\n",
                    sum / double(ao.size()), pipeline.width(), pipeline.height(), cache.probeCount(),
                    projection.residency().stats().resident, shares.uncovered, context->renderer().c_str(),
                    cubeao::gl::shaderDir().c_str());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
}

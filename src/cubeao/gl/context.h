// A headless OpenGL 4.5 core context on EGL, made current with no surface (EGL_KHR_surfaceless_context):
// bake, tests and benchmarks render only into FBOs, so no window system is needed.
//
// Displays are tried in the order that works on both kinds of machine we run on
// (../shared/gpu/README.md): the EGL device platform, each device in turn (the only one that works on
// the NVIDIA benchmark machine), then Mesa's surfaceless platform (llvmpipe on CI). The default display
// is not tried: without X it fails with EGL_NOT_INITIALIZED. CUBEAO_EGL_PLATFORM=device|surfaceless
// restricts the search to one platform.
#pragma once

#include "cubeao/gl/gl.h"

#include <cstddef>
#include <optional>
#include <string>

namespace cubeao::gl {

enum class EglPlatform { Device, Surfaceless };

// Zero-initialised settings are the defaults.
struct ContextSettings {
    // Which platform to use; unset = CUBEAO_EGL_PLATFORM if set, else all in the order above.
    std::optional<EglPlatform> platform;
    // true: neither a debug context nor GL debug output. Only for benchmarks on a real GPU, where
    // the driver's extra validation in a debug context can cost time.
    bool noDebugContext = false;
};

class HeadlessContext {
public:
    // The first display that gives a current 4.5 core context, or nullopt with a readable reason for
    // every display tried in *whyNot (e.g. "device 0: eglInitialize failed (EGL_NOT_INITIALIZED)").
    static std::optional<HeadlessContext> tryCreate(std::string* whyNot = nullptr,
                                                    const ContextSettings& settings = {});
    // As tryCreate, but throws cubeao::Error with the reason.
    static HeadlessContext create(const ContextSettings& settings = {});

    ~HeadlessContext();
    HeadlessContext(HeadlessContext&& other) noexcept;
    HeadlessContext& operator=(HeadlessContext&& other) noexcept;
    HeadlessContext(const HeadlessContext&) = delete;
    HeadlessContext& operator=(const HeadlessContext&) = delete;

    // The context is current on the creating thread; call this to use it on another one.
    void makeCurrent() const;

    EglPlatform platform() const { return platform_; }
    const std::string& platformName() const { return platformName_; }  // "EGL device 0 (/dev/dri/renderD128)"
    const std::string& renderer() const { return renderer_; }          // GL_RENDERER
    const std::string& version() const { return version_; }            // GL_VERSION
    int majorVersion() const { return major_; }
    int minorVersion() const { return minor_; }
    bool debugOutput() const { return debugOutput_; }  // GL debug messages are routed to spdlog

private:
    HeadlessContext() = default;
    friend struct ContextBuilder;  // context.cpp: fills the fields of a new context
    void destroy() noexcept;

    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLContext context_ = EGL_NO_CONTEXT;
    EglPlatform platform_ = EglPlatform::Device;
    std::string platformName_;
    std::string renderer_;
    std::string version_;
    int major_ = 0;
    int minor_ = 0;
    bool debugOutput_ = false;
};

// Routes GL debug output of the current context to spdlog (errors → error, performance → debug;
// notifications and the shader compiler's own messages off). Called for every context we create.
void installDebugOutput(bool debugContext);

// GL errors (GL_DEBUG_TYPE_ERROR) the debug output of any context reported since the process started,
// and the first one's text ("GL error #ID: MESSAGE"; "" for none). A command that ends with errors
// fails with the first (tools/cubeao/main.cpp) rather than report results computed after one.
std::size_t debugErrorCount();
std::string firstDebugError();

// Parses CUBEAO_EGL_PLATFORM-style text ("device", "surfaceless"); nullopt for anything else.
std::optional<EglPlatform> parseEglPlatform(const std::string& text);

}  // namespace cubeao::gl

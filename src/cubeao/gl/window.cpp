#include "cubeao/gl/window.h"

#include <GLFW/glfw3.h>

#include <mutex>
#include <utility>

#include "cubeao/gl/context.h"
#include "cubeao/gl/gl.h"

namespace cubeao::gl {
namespace {

// GLFW reports errors through a callback; keep the last one to explain a failed creation.
thread_local std::string lastGlfwError;

void onGlfwError(int code, const char* description) {
    lastGlfwError = "GLFW error " + std::to_string(code) + ": " + (description ? description : "");
}

// glfwInit once per process; glfwTerminate would destroy other windows, so it is left to exit.
bool initGlfw(std::string* whyNot) {
    static std::once_flag once;
    static bool ok = false;
    std::call_once(once, [] {
        glfwSetErrorCallback(onGlfwError);
        ok = glfwInit() == GLFW_TRUE;
    });
    if (!ok && whyNot) *whyNot = "glfwInit failed (no display?): " + lastGlfwError;
    return ok;
}

}  // namespace

std::optional<WindowContext> WindowContext::tryCreate(int width, int height, const std::string& title,
                                                      std::string* whyNot) {
    if (!initGlfw(whyNot)) return std::nullopt;
    glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, GLFW_TRUE);
    GLFWwindow* w = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!w) {
        if (whyNot) *whyNot = "glfwCreateWindow(4.5 core) failed: " + lastGlfwError;
        return std::nullopt;
    }
    glfwMakeContextCurrent(w);
    glfwSwapInterval(1);
    GLint flags = 0;
    glGetIntegerv(GL_CONTEXT_FLAGS, &flags);
    installDebugOutput((flags & GL_CONTEXT_FLAG_DEBUG_BIT) != 0);
    WindowContext ctx;
    ctx.window_ = w;
    return ctx;
}

WindowContext::~WindowContext() {
    if (window_) glfwDestroyWindow(window_);
}

WindowContext::WindowContext(WindowContext&& other) noexcept : window_(std::exchange(other.window_, nullptr)) {}

WindowContext& WindowContext::operator=(WindowContext&& other) noexcept {
    if (this != &other) {
        if (window_) glfwDestroyWindow(window_);
        window_ = std::exchange(other.window_, nullptr);
    }
    return *this;
}

bool WindowContext::shouldClose() const { return glfwWindowShouldClose(window_) == GLFW_TRUE; }
void WindowContext::swapBuffers() const { glfwSwapBuffers(window_); }
void WindowContext::pollEvents() { glfwPollEvents(); }
void WindowContext::framebufferSize(int& width, int& height) const { glfwGetFramebufferSize(window_, &width, &height); }

}  // namespace cubeao::gl

// A GLFW window with a 4.5 core context, for the interactive viewer (cubeao-view). Headless work
// (bake, tests, benchmarks) uses HeadlessContext instead: GLFW 3.3 has no headless platform.
#pragma once

#include <optional>
#include <string>

struct GLFWwindow;

namespace cubeao::gl {

class WindowContext {
public:
    // A visible window of the given size whose 4.5 core context is current, with GL debug output
    // routed to spdlog; nullopt with the reason (no display, no 4.5 core) in *whyNot.
    static std::optional<WindowContext> tryCreate(int width, int height, const std::string& title,
                                                  std::string* whyNot = nullptr);

    ~WindowContext();
    WindowContext(WindowContext&& other) noexcept;
    WindowContext& operator=(WindowContext&& other) noexcept;
    WindowContext(const WindowContext&) = delete;
    WindowContext& operator=(const WindowContext&) = delete;

    GLFWwindow* window() const { return window_; }
    bool shouldClose() const;
    void swapBuffers() const;
    static void pollEvents();
    void framebufferSize(int& width, int& height) const;

private:
    WindowContext() = default;
    GLFWwindow* window_ = nullptr;
};

}  // namespace cubeao::gl

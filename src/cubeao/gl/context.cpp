#include "cubeao/gl/context.h"

#include "cubeao/core/error.h"

#include <spdlog/spdlog.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace cubeao::gl {

namespace {

constexpr int kMajor = 4;
constexpr int kMinor = 5;

bool hasExtension(const char* list, const char* name) {
    if (list == nullptr) return false;
    const std::size_t n = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

std::string eglErrorText(EGLint code) {
    const char* name = "unknown EGL error";
    switch (code) {
        case EGL_NOT_INITIALIZED: name = "EGL_NOT_INITIALIZED"; break;
        case EGL_BAD_ACCESS: name = "EGL_BAD_ACCESS"; break;
        case EGL_BAD_ALLOC: name = "EGL_BAD_ALLOC"; break;
        case EGL_BAD_ATTRIBUTE: name = "EGL_BAD_ATTRIBUTE"; break;
        case EGL_BAD_CONFIG: name = "EGL_BAD_CONFIG"; break;
        case EGL_BAD_CONTEXT: name = "EGL_BAD_CONTEXT"; break;
        case EGL_BAD_DISPLAY: name = "EGL_BAD_DISPLAY"; break;
        case EGL_BAD_MATCH: name = "EGL_BAD_MATCH"; break;
        case EGL_BAD_PARAMETER: name = "EGL_BAD_PARAMETER"; break;
        default: break;
    }
    char hex[16];
    std::snprintf(hex, sizeof hex, "0x%04x", static_cast<unsigned>(code));
    return std::string(name) + " (" + hex + ")";
}

std::string eglFailure(const char* call) { return std::string(call) + " failed: " + eglErrorText(eglGetError()); }

// EGL displays are per process and eglTerminate is not reference counted (EGL_KHR_display_reference is
// rare), so two contexts on one display would pull it from under each other. Count users here instead.
class DisplayUsers {
public:
    static void add(EGLDisplay d) {
        std::lock_guard lock(mutex());
        ++counts()[d];
    }
    // Terminates the display once its last context is gone.
    static void remove(EGLDisplay d) {
        std::lock_guard lock(mutex());
        if (--counts()[d] <= 0) {
            counts().erase(d);
            eglTerminate(d);
        }
    }
    // For failed attempts: terminate only a display nobody else uses.
    static void terminateIfUnused(EGLDisplay d) {
        std::lock_guard lock(mutex());
        if (counts().count(d) == 0) eglTerminate(d);
    }

private:
    static std::mutex& mutex() {
        static std::mutex m;
        return m;
    }
    static std::map<EGLDisplay, int>& counts() {
        static std::map<EGLDisplay, int> c;
        return c;
    }
};

// ---- GL debug output --------------------------------------------------------------------------

const char* debugTypeName(GLenum type) {
    switch (type) {
        case GL_DEBUG_TYPE_ERROR: return "error";
        case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR: return "deprecated";
        case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR: return "undefined behaviour";
        case GL_DEBUG_TYPE_PORTABILITY: return "portability";
        case GL_DEBUG_TYPE_PERFORMANCE: return "performance";
        default: return "other";
    }
}

// Errors (and anything the driver calls high severity) are bugs: error level. Performance hints are
// frequent and driver specific: debug level. Notifications are filtered out before they get here.
// GL_DEBUG_TYPE_ERROR messages so far (debugErrorCount); the driver may call from its own thread.
std::atomic<std::size_t> debugErrors{0};
std::mutex firstDebugErrorMutex;
std::string firstDebugErrorText;

void APIENTRY onDebugMessage(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length,
                             const GLchar* message, const void* /*user*/) {
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
    std::string text = length >= 0 ? std::string(message, static_cast<std::size_t>(length)) : message;
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
    spdlog::level::level_enum level = spdlog::level::debug;
    if (type == GL_DEBUG_TYPE_ERROR || severity == GL_DEBUG_SEVERITY_HIGH)
        level = spdlog::level::err;
    else if (type == GL_DEBUG_TYPE_PERFORMANCE)
        level = spdlog::level::debug;
    else if (severity == GL_DEBUG_SEVERITY_MEDIUM || type == GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR ||
             type == GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR || type == GL_DEBUG_TYPE_PORTABILITY)
        level = spdlog::level::warn;
    spdlog::log(level, "GL {} #{}: {}", debugTypeName(type), id, text);
    if (type == GL_DEBUG_TYPE_ERROR && debugErrors.fetch_add(1) == 0) {
        const std::lock_guard<std::mutex> lock(firstDebugErrorMutex);
        firstDebugErrorText = "GL error #" + std::to_string(id) + ": " + text;
    }
}

// ---- one display ------------------------------------------------------------------------------

EGLConfig chooseConfig(EGLDisplay dpy, const char* exts, bool* ok) {
    const EGLint attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = EGL_NO_CONFIG_KHR;
    EGLint count = 0;
    *ok = (eglChooseConfig(dpy, attribs, &config, 1, &count) && count > 0) ||
          hasExtension(exts, "EGL_KHR_no_config_context");  // the surfaceless context needs no config
    return count > 0 ? config : EGL_NO_CONFIG_KHR;
}

EGLContext createCoreContext(EGLDisplay dpy, EGLConfig config, bool debug) {
    const EGLint flags = debug ? EGL_CONTEXT_OPENGL_DEBUG_BIT_KHR : 0;
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION_KHR, kMajor,
                              EGL_CONTEXT_MINOR_VERSION_KHR, kMinor,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK_KHR, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT_KHR,
                              EGL_CONTEXT_FLAGS_KHR, flags,
                              EGL_NONE};
    EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, attribs);
    // A driver without debug contexts may refuse the flag; a context without it still works.
    if (ctx == EGL_NO_CONTEXT && debug) return createCoreContext(dpy, config, false);
    return ctx;
}

// Checks what the driver actually gave: some return a lower version or a compatibility profile.
bool isCore45(std::string* why) {
    GLint major = 0, minor = 0, profile = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    if ((major > kMajor || (major == kMajor && minor >= kMinor)) && (profile & GL_CONTEXT_CORE_PROFILE_BIT))
        return true;
    *why = "got GL " + std::to_string(major) + "." + std::to_string(minor) +
           ((profile & GL_CONTEXT_CORE_PROFILE_BIT) ? " core" : " (not core)");
    return false;
}

// Initialises dpy and makes a current surfaceless 4.5 core context on it; EGL_NO_CONTEXT and *why
// on failure (the display is then terminated unless another HeadlessContext uses it).
EGLContext makeContext(EGLDisplay dpy, bool debug, std::string* why) {
    EGLint major = 0, minor = 0;
    if (!eglInitialize(dpy, &major, &minor)) {
        *why = eglFailure("eglInitialize");
        return EGL_NO_CONTEXT;
    }
    const char* exts = eglQueryString(dpy, EGL_EXTENSIONS);
    bool haveConfig = false;
    EGLConfig config = EGL_NO_CONFIG_KHR;
    EGLContext ctx = EGL_NO_CONTEXT;
    if (!hasExtension(exts, "EGL_KHR_surfaceless_context"))
        *why = "no EGL_KHR_surfaceless_context";
    else if (!hasExtension(exts, "EGL_KHR_create_context"))
        *why = "no EGL_KHR_create_context";
    else if (!eglBindAPI(EGL_OPENGL_API))
        *why = eglFailure("eglBindAPI(EGL_OPENGL_API)");
    else if (config = chooseConfig(dpy, exts, &haveConfig); !haveConfig)
        *why = "no EGL config with EGL_OPENGL_BIT";
    else if (ctx = createCoreContext(dpy, config, debug); ctx == EGL_NO_CONTEXT)
        *why = eglFailure("eglCreateContext(4.5 core)");
    else if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx))
        *why = eglFailure("eglMakeCurrent(no surface)");
    else if (isCore45(why))
        return ctx;

    if (ctx != EGL_NO_CONTEXT) {
        eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(dpy, ctx);
    }
    DisplayUsers::terminateIfUnused(dpy);
    return EGL_NO_CONTEXT;
}

struct Candidate {
    EglPlatform platform;
    std::string name;     // for platformName()
    std::string label;    // for the failure reason
    EGLDisplay display = EGL_NO_DISPLAY;
    std::string whyNot;   // set when no display could even be obtained
};

PFNEGLGETPLATFORMDISPLAYEXTPROC getPlatformDisplay() {
    return reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
}

std::string deviceDescription(EGLDeviceEXT device) {
    auto queryString =
        reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    if (queryString == nullptr) return "unknown";
    const char* exts = queryString(device, EGL_EXTENSIONS);
    if (hasExtension(exts, "EGL_EXT_device_drm")) {
        const char* file = queryString(device, EGL_DRM_DEVICE_FILE_EXT);
        if (file != nullptr) return file;
    }
    return hasExtension(exts, "EGL_MESA_device_software") ? "software" : "no DRM file";
}

void addDeviceCandidates(const char* clientExts, std::vector<Candidate>& out) {
    auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    auto getDisplay = getPlatformDisplay();
    if (!hasExtension(clientExts, "EGL_EXT_platform_device") || queryDevices == nullptr || getDisplay == nullptr) {
        out.push_back({EglPlatform::Device, "", "device", EGL_NO_DISPLAY, "EGL_EXT_platform_device not offered"});
        return;
    }
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (!queryDevices(16, devices, &count) || count == 0) {
        const std::string why = count == 0 ? "no EGL devices" : eglFailure("eglQueryDevicesEXT");
        out.push_back({EglPlatform::Device, "", "device", EGL_NO_DISPLAY, why});
        return;
    }
    for (EGLint i = 0; i < count; ++i) {
        const std::string label = "device " + std::to_string(i);
        Candidate c{EglPlatform::Device, "EGL " + label + " (" + deviceDescription(devices[i]) + ")", label,
                    EGL_NO_DISPLAY, ""};
        c.display = getDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        if (c.display == EGL_NO_DISPLAY) c.whyNot = eglFailure("eglGetPlatformDisplayEXT");
        out.push_back(std::move(c));
    }
}

void addSurfacelessCandidate(const char* clientExts, std::vector<Candidate>& out) {
    Candidate c{EglPlatform::Surfaceless, "EGL surfaceless (Mesa)", "surfaceless", EGL_NO_DISPLAY, ""};
    auto getDisplay = getPlatformDisplay();
    if (!hasExtension(clientExts, "EGL_MESA_platform_surfaceless") || getDisplay == nullptr)
        c.whyNot = "EGL_MESA_platform_surfaceless not offered";
    else if (c.display = getDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
             c.display == EGL_NO_DISPLAY)
        c.whyNot = eglFailure("eglGetPlatformDisplayEXT");
    out.push_back(std::move(c));
}

// The platform to use, or an error text for a CUBEAO_EGL_PLATFORM value we do not know.
std::optional<EglPlatform> requestedPlatform(const ContextSettings& settings, std::string* error) {
    if (settings.platform) return settings.platform;
    const char* env = std::getenv("CUBEAO_EGL_PLATFORM");
    if (env == nullptr || *env == '\0') return std::nullopt;
    if (auto p = parseEglPlatform(env)) return p;
    *error = std::string("CUBEAO_EGL_PLATFORM='") + env + "' is not 'device' or 'surfaceless'";
    return std::nullopt;
}

}  // namespace

std::size_t debugErrorCount() { return debugErrors.load(); }

std::string firstDebugError() {
    const std::lock_guard<std::mutex> lock(firstDebugErrorMutex);
    return firstDebugErrorText;
}

void installDebugOutput(bool debugContext) {
    glEnable(GL_DEBUG_OUTPUT);
    // Synchronous delivery logs a message before the offending call returns, so the log lines up with
    // the code; only worth it where the driver validates anyway (a debug context).
    if (debugContext) glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(onDebugMessage, nullptr);
    // Notifications (buffer placement, push/pop group echoes) would drown everything else.
    glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DEBUG_SEVERITY_NOTIFICATION, 0, nullptr, GL_FALSE);
    // Compile errors are thrown by the shader loader with source-string ids mapped to file names;
    // the driver's copy would repeat them with bare ids.
    glDebugMessageControl(GL_DEBUG_SOURCE_SHADER_COMPILER, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_FALSE);
}

// Fills a HeadlessContext from a display that just gave a current context.
struct ContextBuilder {
    static HeadlessContext build(const Candidate& c, EGLContext ctx, bool debug) {
        HeadlessContext out;
        out.display_ = c.display;
        out.context_ = ctx;
        DisplayUsers::add(c.display);
        out.platform_ = c.platform;
        out.platformName_ = c.name;
        out.renderer_ = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
        out.version_ = reinterpret_cast<const char*>(glGetString(GL_VERSION));
        glGetIntegerv(GL_MAJOR_VERSION, &out.major_);
        glGetIntegerv(GL_MINOR_VERSION, &out.minor_);
        if (debug) {
            GLint flags = 0;
            glGetIntegerv(GL_CONTEXT_FLAGS, &flags);
            installDebugOutput((flags & GL_CONTEXT_FLAG_DEBUG_BIT) != 0);
            out.debugOutput_ = true;
        }
        spdlog::debug("GL context: {} on {}, GL {}", out.renderer_, out.platformName_, out.version_);
        return out;
    }
};

std::optional<EglPlatform> parseEglPlatform(const std::string& text) {
    if (text == "device") return EglPlatform::Device;
    if (text == "surfaceless") return EglPlatform::Surfaceless;
    return std::nullopt;
}

std::optional<HeadlessContext> HeadlessContext::tryCreate(std::string* whyNot, const ContextSettings& settings) {
    std::string envError;
    const std::optional<EglPlatform> only = requestedPlatform(settings, &envError);
    if (!envError.empty()) {
        if (whyNot) *whyNot = envError;
        return std::nullopt;
    }
    const char* clientExts = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    std::vector<Candidate> candidates;
    if (!only || *only == EglPlatform::Device) addDeviceCandidates(clientExts, candidates);
    if (!only || *only == EglPlatform::Surfaceless) addSurfacelessCandidate(clientExts, candidates);

    const bool debug = !settings.noDebugContext;
    // Failed attempts unbind whatever was current; a caller's existing context gets it back.
    const EGLDisplay previousDisplay = eglGetCurrentDisplay();
    const EGLContext previousContext = eglGetCurrentContext();
    std::string reasons;
    for (Candidate& c : candidates) {
        if (c.whyNot.empty()) {
            const EGLContext ctx = makeContext(c.display, debug, &c.whyNot);
            if (ctx != EGL_NO_CONTEXT) return ContextBuilder::build(c, ctx, debug);
        }
        reasons += (reasons.empty() ? "" : "; ") + c.label + ": " + c.whyNot;
    }
    if (previousContext != EGL_NO_CONTEXT)
        eglMakeCurrent(previousDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, previousContext);
    if (whyNot) *whyNot = "no EGL display offered a 4.5 core context: " + reasons;
    return std::nullopt;
}

HeadlessContext HeadlessContext::create(const ContextSettings& settings) {
    std::string why;
    if (auto ctx = tryCreate(&why, settings)) return std::move(*ctx);
    throw Error("no OpenGL 4.5 context (" + why + ")");
}

HeadlessContext::~HeadlessContext() { destroy(); }

HeadlessContext::HeadlessContext(HeadlessContext&& other) noexcept { *this = std::move(other); }

HeadlessContext& HeadlessContext::operator=(HeadlessContext&& other) noexcept {
    if (this == &other) return *this;
    destroy();
    display_ = std::exchange(other.display_, EGL_NO_DISPLAY);
    context_ = std::exchange(other.context_, EGL_NO_CONTEXT);
    platform_ = other.platform_;
    platformName_ = std::move(other.platformName_);
    renderer_ = std::move(other.renderer_);
    version_ = std::move(other.version_);
    major_ = other.major_;
    minor_ = other.minor_;
    debugOutput_ = other.debugOutput_;
    return *this;
}

void HeadlessContext::makeCurrent() const {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
        throw Error("HeadlessContext::makeCurrent: " + eglFailure("eglMakeCurrent"));
}

void HeadlessContext::destroy() noexcept {
    if (context_ == EGL_NO_CONTEXT) return;
    // A context current on this thread is only destroyed once released.
    if (eglGetCurrentContext() == context_) eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
    DisplayUsers::remove(display_);
    display_ = EGL_NO_DISPLAY;
    context_ = EGL_NO_CONTEXT;
}

}  // namespace cubeao::gl

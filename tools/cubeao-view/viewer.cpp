#include "cubeao-view/viewer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/vec2.hpp>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "cubeao-view/panel.h"
#include "cubeao-view/script.h"
#include "cubeao-view/view_modes.h"
#include "cubeao-view/viewer_state.h"
#include "cubeao/bake/bake_settings.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/cli_util.h"
#include "cubeao/core/durable_file.h"
#include "cubeao/core/error.h"
#include "cubeao/gl/handles.h"
#include "cubeao/gl/window.h"
#include "cubeao/metrics/image_io.h"
#include "cubeao/placement/live_placement.h"
#include "cubeao/placement/placement.h"
#include "cubeao/runtime/frame_pipeline.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/camera_path.h"
#include "cubeao/scene/import.h"
#include "cubeao/ssao/ao_methods.h"

namespace cubeao::viewer {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

gl::Texture texture2D(GLenum format, int width, int height) {
    gl::Texture t = gl::Texture::create(GL_TEXTURE_2D);
    glTextureStorage2D(t.id(), 1, format, width, height);
    return t;
}

// Reads a texture back (tools and screenshots only: this waits for the GPU).
Image readR32f(GLuint texture, int width, int height) {
    Image image(width, height);
    glGetTextureImage(texture, 0, GL_RED, GL_FLOAT, GLsizei(image.pixels.size() * sizeof(float)), image.pixels.data());
    return image;  // texture row 0 is the image top (camera_view.h): already in Image order
}

// RGB floats in 0..1 of the bound read framebuffer's rectangle, top row first.
std::vector<float> readRgb(int width, int height) {
    std::vector<std::uint8_t> bytes(std::size_t(width) * std::size_t(height) * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, bytes.data());
    std::vector<float> rgb(std::size_t(width) * std::size_t(height) * 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c)
                rgb[(std::size_t(y) * width + x) * 3 + c] =
                    float(bytes[(std::size_t(height - 1 - y) * width + x) * 4 + c]) / 255.0f;
    return rgb;
}

void writeScreenshotPng(const fs::path& file, int width, int height, const std::vector<float>& rgb) {
    if (file.has_parent_path()) fs::create_directories(file.parent_path());
    writePngRgb(file, width, height, rgb);
    spdlog::info("cubeao-view: wrote {}", file.string());
}

class Viewer {
public:
    explicit Viewer(const ViewerOptions& o);
    ~Viewer();
    int run();

private:
    void loadInputs();
    void buildPipelines();
    FramePipeline& baselinePipeline(const std::string& name);
    FramePipeline& activePipeline();
    ProbeProjectionPass* probes() const;
    BakeSettings liveBake(Estimator estimator) const;

    // What a script command leaves the frame loop to do: run the next command at once, render a frame
    // first, or quit.
    enum class ScriptStep { Next, Render, Quit };
    bool stepScript();    // false when the script has ended (quit)
    bool continueSpan();  // a wait, walk or play spanning frames takes this frame
    ScriptStep runCommand(const ScriptCommand& c);
    void handleInput(double dtSeconds);
    void renderFrame();
    void drawView(int x, int y, int width, int height);
    void panel();  // draws the panel and carries out what was pressed on it
    void handleKeys();
    bool pressed(int key);  // went down since the last frame
    void viewScreenshot(const fs::path& file);
    void windowScreenshot(const fs::path& file);
    void save(const fs::path& file);
    fs::path defaultSavePath() const;
    void startLive();
    void setLive(bool on);    // the key L, the panel's checkbox and the script's `live`
    void togglePlaying();     // the key P and the panel's button
    void toggleRecording();   // the key R and the panel's button (to walk.json)
    void startRecording(const fs::path& file);
    void stopRecording();
    void setPathFrame(std::size_t f);
    const Image* referenceFor(std::size_t frame);
    void renderSize(int& w, int& h) const;
    nlohmann::json summary() const;
    // Damaged probes left out: those the pass found, and those live placement found adopting the cache.
    std::size_t damagedProbes() const;

    ViewerOptions o_;
    ViewerState s_;
    Scene scene_;
    std::optional<CameraPath> path_;
    std::unique_ptr<CacheReader> cache_;
    SsaoSettings ssao_;
    CompositeSettings composite_;
    std::optional<gl::WindowContext> window_;  // set in the constructor; optional only for its deferred creation

    std::unique_ptr<FramePipeline> main_;  // probes (cache or live), or gtao without probes
    std::map<std::string, std::unique_ptr<FramePipeline>> baselines_;
    std::unique_ptr<ViewModes> modes_;

    // Live placement: the placement scene is built on first use (Embree, free space: seconds).
    std::unique_ptr<placement::PlacementScene> placementScene_;
    const char* lastStalled_ = nullptr;  // live placement's last logged reason for not placing
    std::unique_ptr<placement::LivePlacement> live_;
    // Probes of the opened cache that live placement found damaged when adopting them, and left out
    // (the pass counts the ones it finds itself: ResidencyStats::damaged).
    std::size_t liveDamaged_ = 0;
    bool liveAoAsBc5_ = false;  // the pass holds the cache's AO as BC5, for live placement (buildPipelines)
    placement::LiveSettings::Objective liveObjective_ = placement::LiveSettings::Objective::Error;  // --live-objective

    std::uint32_t serial_ = 0;     // frames rendered
    int idleFrames_ = 0;           // frames without input
    glm::dvec2 cursor_{0.0};       // the mouse at the last frame
    bool dragging_ = false;        // a look button was down at the last frame
    int forcedIdle_ = 0;           // script `idle N`
    bool fixedSize_ = false;
    int fixedW_ = 0, fixedH_ = 0;

    // Script state.
    std::vector<ScriptCommand> script_;
    std::size_t scriptPos_ = 0;
    int waitFrames_ = 0;
    int settleLeft_ = 0, rebakeLeft_ = 0;
    glm::vec4 walkStep_{0.0f};  // (right, up, forward) per frame, w = frames left
    std::size_t playEnd_ = 0;
    bool quit_ = false;

    // Reference frames for the difference mode.
    std::map<std::size_t, std::optional<Image>> references_;
    gl::Texture referenceTex_;
    std::optional<std::size_t> referenceTexFrame_;

    // Figures for the panel and the --stats summary.
    double frameMs_ = 0.0, frameMsMean_ = 0.0;
    std::optional<PipelineTimings> timings_;
    ProbeProjectionPass::PixelShares shares_;
    std::deque<double> frameTimes_;
    std::map<int, bool> keyWasDown_;
    // Per rendered frame, for --stats: wall ms, the live bake's ms, the script line being run.
    struct FrameRecord {
        double ms = 0.0, bakeMs = 0.0;
        int scriptLine = 0;
    };
    std::vector<FrameRecord> frameLog_;
    int screenshots_ = 0;
};

Viewer::Viewer(const ViewerOptions& o) : o_(o) {
    s_.scale = o.scale;
    if (!(o.scale > 0.05f && o.scale <= 4.0f)) throw UsageError("--scale must lie in (0.05, 4]");
    if (o.width < 64 || o.height < 64 || o.width > 16384 || o.height > 16384)
        throw UsageError("--width/--height must lie in [64, 16384]");
    if (!(o.bakeMsPerFrame > 0.0 && o.bakeMsPerFrame <= 1000.0)) throw UsageError("--bake-ms must lie in (0, 1000]");
    if (o.liveRes < 4 || o.liveRes > 2048 || o.liveRes % 4) throw UsageError("--live-res must be a multiple of 4 in [4, 2048]");
    if (!(o.coverageTarget > 0.0 && o.coverageTarget <= 1.0)) throw UsageError("--coverage-target must lie in (0, 1]");
    if (o.liveObjective != "error" && o.liveObjective != "coverage")
        throw UsageError("--live-objective \"" + o.liveObjective + "\": expected error or coverage");
    liveObjective_ = o.liveObjective == "coverage" ? placement::LiveSettings::Objective::Coverage
                                                   : placement::LiveSettings::Objective::Error;
    cli::checkResidencyOptions(o.gpuBudgetMb, o.uploadMb);  // a negative MiB count would wrap to a huge budget
    const auto mode = parseViewMode(o.mode);
    if (!mode) throw UsageError("--mode \"" + o.mode + "\": not a view mode");
    s_.mode = *mode;
    if (!o.script.empty()) script_ = readScript(o.script);
    loadInputs();
    std::string whyNot;
    auto window = gl::WindowContext::tryCreate(o.width, o.height, "cubeao-view — " + scene_.source, &whyNot);
    if (!window) throw Error("cubeao-view needs a display with OpenGL 4.5 core: " + whyNot);
    window_.emplace(std::move(*window));
    glfwSwapInterval(o.vsync && o.script.empty() ? 1 : 0);  // scripts run as fast as they render

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini beside whatever directory we run in
    ImGui::StyleColorsDark();
    ImGui::GetStyle().WindowRounding = 4.0f;
    ImGui_ImplGlfw_InitForOpenGL(window_->window(), true);
    ImGui_ImplOpenGL3_Init("#version 450 core");

    modes_ = std::make_unique<ViewModes>();
    liveAoAsBc5_ = o.live;
    buildPipelines();
    if (o.live) startLive();
}

Viewer::~Viewer() {
    if (s_.recordFile) stopRecording();
    live_.reset();
    baselines_.clear();
    main_.reset();
    modes_.reset();
    referenceTex_ = {};
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
}

void Viewer::loadInputs() {
    scene_ = loadScene(o_.scene);
    const bool builtin = o_.scene.rfind("builtin:", 0) == 0;
    if (!o_.camera.empty() || builtin) path_ = resolveCameraPath(o_.camera, scene_);
    if (!o_.cache.empty()) {
        cache_ = std::make_unique<CacheReader>(o_.cache);
        cache_->expectScene(scene_.hash);
    }
    SsaoSettings s;
    s.method = SsaoMethod::Gtao;
    s.radius = cache_ ? cache_->params().radius : 0.0f;
    ssao_ = resolveSsaoSettings(s, scene_.defaultRadius());
    composite_ = previewComposite(scene_.up, 1.0f);

    s_.camera.up = glm::normalize(scene_.up);
    if (path_ && !path_->frames.empty()) {
        setPathFrame(0);
    } else {
        // No path: stand at the middle of the bounds, at a third of its height, looking along x.
        s_.camera.eye = scene_.bounds.center();
        s_.camera.forward = glm::normalize(glm::cross(s_.camera.up, glm::vec3(0.0f, 0.0f, 1.0f)) +
                                         glm::vec3(1e-3f, 0.0f, 0.0f));
        s_.camera.nearPlane = 1e-3f * scene_.bounds.diagonal();
    }
    s_.speed = 0.08f * scene_.bounds.diagonal();
}

void Viewer::buildPipelines() {
    ProbeProjectionSettings settings;
    settings.residency = ResidencySettings::fromMib(o_.gpuBudgetMb, o_.uploadMb);
    // Live placement adds probes that carry a confidence (its horizon bakes): with it the pass holds a
    // BC4 cache as BC5 (confidence 1); without it, as stored.
    if (liveAoAsBc5_) settings.aoFormat = AoFormat::Bc5;
    // The cache's probes over GTAO; live placement without a cache starts from no probes (GTAO covers
    // what no probe sees yet); neither: GTAO.
    std::unique_ptr<AoPass> method =
        !cache_ && o_.live ? makeEmptyProbePass(cacheParamsFor(liveBake(Estimator::HorizonSplit), scene_), ssao_,
                                                scene_.positions, scene_.indices, settings)
                           : makeAoPass(ssao_, cache_.get(), scene_.positions, scene_.indices, settings);
    // The probes' blur width follows the render size (renderFrame chooses it every frame).
    main_ = std::make_unique<FramePipeline>(scene_.positions, scene_.indices, std::move(method), BlurSettings{},
                                            composite_);
}

FramePipeline& Viewer::baselinePipeline(const std::string& name) {
    auto& p = baselines_[name];
    if (!p) {
        SsaoSettings s = ssao_;
        s.method = parseSsaoMethod(name);
        s = resolveSsaoSettings(s, scene_.defaultRadius());
        p = std::make_unique<FramePipeline>(scene_.positions, scene_.indices, makeAoPass(s, nullptr, scene_.positions, scene_.indices),
                                            BlurSettings{}, composite_);
    }
    return *p;
}

FramePipeline& Viewer::activePipeline() { return s_.mode == ViewMode::Baseline ? baselinePipeline(s_.baseline) : *main_; }

ProbeProjectionPass* Viewer::probes() const { return dynamic_cast<ProbeProjectionPass*>(&main_->method()); }

// Live probes match the opened cache (its resolutions, R, falloff), else --live-res at the scene's R.
BakeSettings Viewer::liveBake(Estimator estimator) const {
    BakeSettings b;
    b.estimator = estimator;
    b.res = o_.liveRes;
    b.ao.radius = ssao_.radius;
    if (cache_) {
        const CacheParams& p = cache_->params();
        b.res = int(p.res), b.depthRes = int(p.depthRes), b.depthFormat = p.depthFormat;
        b.levels = int(p.levels);  // the pass holds level 0 of either (ProbeSource::add)
        b.ao.falloff = Falloff(p.falloff);
        b.ao.seed = p.seed;
        // The opened cache's own estimator bakes as the cache did (rays, filter, horizon steps), so
        // its probes and the live bake's replace each other (LivePlacement::adopt needs them equal).
        if (Estimator(p.estimator) == estimator) {
            if (tracesRays(estimator)) b.ao.spp = int(p.spp);
            b.denoise = int(p.denoise);
            if (estimator != Estimator::Traced) b.directions = int(p.directions), b.steps = int(p.steps);
            if (estimator == Estimator::Hybrid) b.hybridThreshold = p.hybridThreshold;
        }
    }
    return resolveBakeSettings(b, scene_.defaultRadius());
}

void Viewer::startLive() {
    ProbeProjectionPass* pass = probes();
    if (!pass) {
        s_.status = "live placement needs probes: start with --live (or a --cache)";
        spdlog::warn("cubeao-view: {}", s_.status);
        return;
    }
    if (!live_ && pass->source().params().aoFormat != AoFormat::Bc5) {  // a BC4 cache: hold it as BC5 from now
        liveAoAsBc5_ = true;
        buildPipelines();
        pass = probes();
    }
    if (!live_) {
        const auto start = Clock::now();
        placement::PlaceSettings ps;
        ps.radius = ssao_.radius;
        // Probes go where a production bake (512²) would want them: the coverage criterion's texel
        // bound scales with the live resolution, so a coarse live bake does not multiply the probes.
        ps.res = liveBake(Estimator::HorizonSplit).res;
        ps.texelsPerRadius = placement::PlaceSettings{}.texelsPerRadius * float(ps.res) / 512.0f;
        ps.target = o_.coverageTarget;
        // Where the person stands is free, whichever way the model's faces point (issue 31).
        const glm::vec3 here = s_.camera.eye;
        placementScene_ = std::make_unique<placement::PlacementScene>(scene_, ps, path_ ? &*path_ : nullptr,
                                                                      std::span(&here, 1));
        placement::LiveSettings ls;
        ls.bakeMsPerFrame = o_.bakeMsPerFrame;
        ls.nearPlane = s_.camera.nearPlane;
        if (path_) ls.farPlane = path_->farPlane;
        ls.objective = liveObjective_;
        // The count's frames keep the view's aspect (64 pixels wide).
        int w = 0, h = 0;
        renderSize(w, h);
        ls.feedback.height = std::clamp(int(std::lround(64.0 * double(h) / double(w))), 8, 256);
        live_ = std::make_unique<placement::LivePlacement>(*placementScene_, liveBake(Estimator::HorizonSplit),
                                                           liveBake(Estimator::Traced), ls);
        if (cache_) {
            // The opened cache's probes are the pass's ids 0..n-1 (ProbeSource keeps the cache's order);
            // a damaged one is left out here as the pass leaves it out (or already has).
            std::vector<ProbeRecord> records;
            std::vector<ProbeId> ids;
            for (std::size_t i = 0; i < cache_->probeCount(); ++i) {
                const ProbeId id{std::uint32_t(i)};
                if (!pass->source().isLive(id)) continue;
                try {
                    records.push_back(cache_->copyProbe(i));
                } catch (const Error& e) {
                    spdlog::warn("cubeao-view: {}; left out", e.what());
                    pass->removeProbe(id);
                    ++liveDamaged_;
                    continue;
                }
                ids.push_back(id);
            }
            live_->adopt(std::move(records), ids, cache_->params());
        }
        if (liveObjective_ == placement::LiveSettings::Objective::Coverage)
            spdlog::info("cubeao-view: live placement ready in {:.1f} s (target coverage {:.0f} %)",
                         msSince(start) / 1000.0, 100.0 * o_.coverageTarget);
        else
            spdlog::info("cubeao-view: live placement ready in {:.1f} s (predicted AO error of the walk so far)",
                         msSince(start) / 1000.0);
    }
    s_.liveOn = true;
}

void Viewer::setLive(bool on) {
    if (on)
        startLive();
    else
        s_.liveOn = false;
}

void Viewer::togglePlaying() {
    if (!s_.pathFrame) setPathFrame(0);
    s_.playing = !s_.playing;
}

void Viewer::toggleRecording() {
    if (s_.recordFile)
        stopRecording();
    else
        startRecording("walk.json");
}

void Viewer::setPathFrame(std::size_t f) {
    if (!path_ || path_->frames.empty()) return;
    f = std::min(f, path_->frames.size() - 1);
    s_.camera.setFrame(*path_, f);
    s_.pathFrame = f;
}

void Viewer::renderSize(int& w, int& h) const {
    if (fixedSize_) {
        w = fixedW_, h = fixedH_;
        return;
    }
    int fw = 0, fh = 0;
    window_->framebufferSize(fw, fh);
    w = std::max(8, int(std::lround(float(fw) * s_.scale)));
    h = std::max(8, int(std::lround(float(fh) * s_.scale)));
}

const Image* Viewer::referenceFor(std::size_t frame) {
    if (o_.reference.empty()) return nullptr;
    auto it = references_.find(frame);
    if (it == references_.end()) {
        const fs::path file = fs::path(o_.reference) / cli::frameName("ao", frame, "exr");
        std::optional<Image> image;
        if (fs::exists(file)) {
            try {
                image = readImage(file);
            } catch (const Error& e) {
                spdlog::warn("cubeao-view: {}", e.what());
            }
        }
        it = references_.emplace(frame, std::move(image)).first;
    }
    return it->second ? &*it->second : nullptr;
}

// One script command per call, except waits, walks and plays, which span frames.
bool Viewer::stepScript() {
    if (continueSpan()) return true;
    while (scriptPos_ < script_.size()) {
        switch (runCommand(script_[scriptPos_++])) {
            case ScriptStep::Next: continue;
            case ScriptStep::Render: return true;
            case ScriptStep::Quit: return false;
        }
    }
    return false;  // the end of the script quits, as `quit` does
}

bool Viewer::continueSpan() {
    if (waitFrames_ > 0) {
        --waitFrames_;
        return true;
    }
    if (settleLeft_ > 0) {
        if (live_ && live_->stats().queued > 0) {
            --settleLeft_;
            return true;
        }
        settleLeft_ = 0;
    }
    if (rebakeLeft_ > 0) {
        if (live_ && live_->stats().toRebake > 0) {
            --rebakeLeft_;
            forcedIdle_ = 1;
            return true;
        }
        rebakeLeft_ = 0;
    }
    if (walkStep_.w > 0.0f) {
        s_.camera.move(glm::vec3(walkStep_));
        s_.pathFrame.reset();
        walkStep_.w -= 1.0f;
        return true;
    }
    if (s_.playing && s_.pathFrame && *s_.pathFrame + 1 < playEnd_) {
        setPathFrame(*s_.pathFrame + 1);
        return true;
    }
    s_.playing = false;
    return false;
}

// The command's arguments and names were checked when the script was read (script.h); what depends
// on the inputs (a camera path, its length) is checked here.
Viewer::ScriptStep Viewer::runCommand(const ScriptCommand& c) {
    using enum ScriptStep;
    const std::vector<double>& n = c.numbers;
    const auto needPath = [&] {
        const std::string where = o_.script + ":" + std::to_string(c.line);
        if (!path_) throw UsageError(where + ": \"" + verbName(c.verb) + "\" needs --camera PATH.json");
        if (std::size_t(n[0]) >= path_->frames.size())
            throw UsageError(where + ": frame " + std::to_string(std::size_t(n[0])) + " is past the path's " +
                             std::to_string(path_->frames.size()) + " frames");
    };
    const glm::vec3 v(n.size() >= 3 ? glm::vec3(n[0], n[1], n[2]) : glm::vec3(0.0f));
    switch (c.verb) {
        case Verb::Frames:
            if (n[0] < 1.0) return Next;
            waitFrames_ = int(n[0]) - 1;
            return Render;
        case Verb::Path:
            needPath();
            setPathFrame(std::size_t(n[0]));
            return Render;
        case Verb::Play:
            needPath();
            setPathFrame(std::size_t(n[0]));
            playEnd_ = std::min<std::size_t>(std::size_t(n[1]), path_->frames.size());
            s_.playing = true;
            return Render;
        case Verb::Eye: s_.camera.eye = scene_.toLocal(glm::dvec3(n[0], n[1], n[2])); break;  // file coordinates
        case Verb::Look: s_.camera.lookAt(scene_.toLocal(glm::dvec3(n[0], n[1], n[2]))); break;
        case Verb::Move: s_.camera.move(v); break;
        case Verb::Turn: s_.camera.turn(float(n[0]), float(n[1])); break;
        case Verb::Walk:
            walkStep_ = glm::vec4(v / float(n[3]), float(n[3]) - 1.0f);
            s_.camera.move(glm::vec3(walkStep_));
            s_.pathFrame.reset();
            return Render;
        case Verb::Size: fixedSize_ = true, fixedW_ = int(n[0]), fixedH_ = int(n[1]); return Next;
        case Verb::Mode: s_.mode = *parseViewMode(c.text); return Next;
        case Verb::Baseline: s_.baseline = c.text; return Next;
        case Verb::Live: setLive(c.text == "on"); return Next;
        case Verb::Idle:
            forcedIdle_ = int(n[0]);
            waitFrames_ = int(n[0]) - 1;
            return Render;
        case Verb::Settle: settleLeft_ = int(n[0]); return Render;
        case Verb::Rebake:
            rebakeLeft_ = int(n[0]);
            forcedIdle_ = 1;
            return Render;
        case Verb::Screenshot: viewScreenshot(c.text); return Next;
        case Verb::ScreenshotWindow: windowScreenshot(c.text); return Next;
        case Verb::Save: save(c.text); return Next;
        case Verb::Record:
            if (c.text == "stop")
                stopRecording();
            else
                startRecording(c.text);
            return Next;
        case Verb::Quit: return Quit;
    }
    s_.pathFrame.reset();  // eye, look, move, turn: the camera left the path
    return Next;
}

void Viewer::handleInput(double dt) {
    GLFWwindow* w = window_->window();
    const ImGuiIO& io = ImGui::GetIO();
    const auto down = [&](int key) { return glfwGetKey(w, key) == GLFW_PRESS; };
    bool moved = false;
    if (!io.WantCaptureKeyboard) {
        glm::vec3 d(0.0f);
        if (down(GLFW_KEY_W)) d.z += 1.0f;
        if (down(GLFW_KEY_S)) d.z -= 1.0f;
        if (down(GLFW_KEY_D)) d.x += 1.0f;
        if (down(GLFW_KEY_A)) d.x -= 1.0f;
        if (down(GLFW_KEY_E)) d.y += 1.0f;
        if (down(GLFW_KEY_Q)) d.y -= 1.0f;
        if (glm::length(d) > 0.0f) {
            const float fast = down(GLFW_KEY_LEFT_SHIFT) ? 4.0f : 1.0f;
            s_.camera.move(glm::normalize(d) * s_.speed * fast * float(dt));
            moved = true;
        }
    }
    double x = 0.0, y = 0.0;
    glfwGetCursorPos(w, &x, &y);
    const bool look = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS ||
                      (glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS && !io.WantCaptureMouse);
    if (look && dragging_ && (x != cursor_.x || y != cursor_.y)) {
        s_.camera.turn(float(cursor_.x - x) * 0.15f, float(cursor_.y - y) * 0.15f);  // 0.15° a pixel
        moved = true;
    }
    dragging_ = look;
    cursor_ = glm::dvec2(x, y);
    if (moved) {
        s_.pathFrame.reset();
        s_.playing = false;
    }
    idleFrames_ = moved ? 0 : idleFrames_ + 1;
}

void Viewer::renderFrame() {
    int w = 0, h = 0;
    renderSize(w, h);
    // The difference mode compares pixel by pixel: render at the reference's own size.
    if (s_.mode == ViewMode::ReferenceDiff && s_.pathFrame)
        if (const Image* ref = referenceFor(*s_.pathFrame)) w = ref->width, h = ref->height;
    const PinholeCamera pinhole = s_.camera.pinhole(w, h);
    const CameraView view = CameraView::fromPinhole(pinhole, s_.camera.nearPlane);
    const std::uint32_t frame = s_.pathFrame ? std::uint32_t(*s_.pathFrame) : serial_;

    ProbeProjectionPass* pass = probes();
    if (pass) {  // the probes' blur for this size: a resized window can cross the texel-size threshold
        const BlurSettings blur = probeBlurSettings(int(pass->source().params().res), h, pinhole.tanHalfFovY);
        if (blur.radius != main_->blur().settings().radius) main_->blur().setSettings(blur);
    }
    if (pass && s_.liveOn && live_) {
        const bool idle = forcedIdle_ > 0 || (script_.empty() && idleFrames_ > 60 && !s_.playing);
        live_->frame(pinhole, idle, *pass);
        // Say once, when it changes, why live placement cannot place (issue 31: never silently GTAO).
        const char* stalled = live_->stats().stalled;
        if (stalled && stalled != lastStalled_) spdlog::warn("cubeao-view: live placement cannot place: {}", stalled);
        lastStalled_ = stalled;
    }
    if (forcedIdle_ > 0) --forcedIdle_;
    const bool needsDiagnostics = s_.mode == ViewMode::ProbeId || s_.mode == ViewMode::Footprint ||
                                  s_.mode == ViewMode::Confidence || s_.mode == ViewMode::Path;
    if (pass) pass->setDiagnostics(needsDiagnostics);
    FramePipeline& pipeline = activePipeline();
    pipeline.render(view, frame);
    if (s_.mode == ViewMode::Baseline) main_->render(view, frame);  // keeps streaming and live placement fed
    if (auto t = main_->latestTimings()) timings_ = t;
    // The pass's pixel shares of a frame or two back, polled (never waited for).
    if (pass)
        if (auto shares = pass->latestPixelShares()) shares_ = *shares;
    if (s_.recordFile) s_.recorded.push_back({s_.camera.eye, s_.camera.eye + s_.camera.forward});
    ++serial_;
}

void Viewer::drawView(int x, int y, int width, int height) {
    FramePipeline& pipeline = activePipeline();
    ViewInputs in;
    in.shaded = pipeline.shadedTexture();
    in.ao = pipeline.aoTexture();
    if (ProbeProjectionPass* pass = probes(); pass && s_.mode != ViewMode::Baseline) {
        in.diagnostics = pass->diagnosticsTexture();
    }
    if (s_.mode == ViewMode::Baseline) in.baselineAo = pipeline.aoTexture();
    in.footprintScale = ssao_.radius / 16.0f;
    if (s_.mode == ViewMode::ReferenceDiff && s_.pathFrame) {
        if (const Image* ref = referenceFor(*s_.pathFrame); ref && ref->width == pipeline.width() &&
                                                           ref->height == pipeline.height()) {
            if (referenceTexFrame_ != *s_.pathFrame) {
                referenceTex_ = texture2D(GL_R32F, ref->width, ref->height);
                glTextureSubImage2D(referenceTex_.id(), 0, 0, 0, ref->width, ref->height, GL_RED, GL_FLOAT,
                                    ref->pixels.data());
                referenceTexFrame_ = *s_.pathFrame;
            }
            in.reference = referenceTex_.id();
        }
    }
    // Letterbox: keep the render's aspect ratio inside the given rectangle.
    const float aspect = float(pipeline.width()) / float(pipeline.height());
    int vw = width, vh = int(std::lround(float(width) / aspect));
    if (vh > height) vh = height, vw = int(std::lround(float(height) * aspect));
    modes_->draw(s_.mode, in, x + (width - vw) / 2, y + (height - vh) / 2, vw, vh);
}

void Viewer::viewScreenshot(const fs::path& file) {
    FramePipeline& pipeline = activePipeline();
    const int w = pipeline.width(), h = pipeline.height();
    if (file.extension() == ".exr") {
        if (file.has_parent_path()) fs::create_directories(file.parent_path());
        writeExr(file, readR32f(pipeline.aoTexture(), w, h));
        spdlog::info("cubeao-view: wrote {}", file.string());
        return;
    }
    gl::Texture colour = texture2D(GL_RGBA8, w, h);
    gl::Framebuffer fbo = gl::Framebuffer::create();
    glNamedFramebufferTexture(fbo.id(), GL_COLOR_ATTACHMENT0, colour.id(), 0);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
    drawView(0, 0, w, h);
    const std::vector<float> rgb = readRgb(w, h);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    writeScreenshotPng(file, w, h, rgb);
}

void Viewer::windowScreenshot(const fs::path& file) {
    int w = 0, h = 0;
    window_->framebufferSize(w, h);
    // Called after the panel is drawn and before the swap: the back buffer holds the whole window.
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    writeScreenshotPng(file, w, h, readRgb(w, h));
}

void Viewer::save(const fs::path& file) {
    if (live_) {
        const std::size_t n = live_->save(file);
        s_.status = "saved " + std::to_string(n) + " probes to " + file.string();
    } else if (cache_) {
        fs::copy_file(o_.cache, file, fs::copy_options::overwrite_existing);
        s_.status = "copied the opened cache to " + file.string();
    } else {
        s_.status = "nothing to save: no probes (turn live placement on)";
    }
    spdlog::info("cubeao-view: {}", s_.status);
}

void Viewer::startRecording(const fs::path& file) {
    s_.recordFile = file;
    s_.recorded.clear();
    s_.status = "recording to " + file.string();
}

void Viewer::stopRecording() {
    if (!s_.recordFile) return;
    CameraPath p;
    p.scene = scene_.source;
    p.origin = scene_.origin;  // the frames are local: written back in file coordinates
    p.up = s_.camera.up, p.fovYDeg = s_.camera.fovYDeg, p.nearPlane = s_.camera.nearPlane;
    if (path_) p.width = path_->width, p.height = path_->height, p.farPlane = path_->farPlane;
    p.frames = s_.recorded;
    if (s_.recordFile->has_parent_path()) fs::create_directories(s_.recordFile->parent_path());
    writeCameraPath(*s_.recordFile, p);
    s_.status = "recorded " + std::to_string(s_.recorded.size()) + " frames to " + s_.recordFile->string();
    spdlog::info("cubeao-view: {}", s_.status);
    s_.recordFile.reset();
}

std::size_t Viewer::damagedProbes() const {
    const ProbeProjectionPass* pass = probes();
    return pass ? pass->residency().stats().damaged + liveDamaged_ : 0;
}

nlohmann::json Viewer::summary() const {
    nlohmann::json j = {{"scene", scene_.source},
                        {"frames", serial_},
                        {"frame_ms_mean", frameMsMean_},
                        {"mode", viewModeName(s_.mode)}};
    if (ProbeProjectionPass* pass = probes()) {
        j["probes"] = pass->source().probes().liveCount();
        j["resident"] = pass->residency().stats().resident;
        j["damaged"] = damagedProbes();
        j["gpu_bytes"] = pass->gpuBytes();
        j["pixels"] = {{"uncovered", shares_.uncovered}, {"fallback_probe", shares_.fallbackProbe}};
    }
    if (live_) {
        const placement::LivePlacement::Stats s = live_->stats();
        j["live"] = {{"placed", s.placed},       {"baked", s.baked},         {"rebaked", s.rebaked},
                     {"queued", s.queued},       {"coverage", s.coverage},   {"bake_ms_mean", s.bakeMsMean},
                     {"bake_ms_budget", o_.bakeMsPerFrame}, {"objective", o_.liveObjective},
                     {"predicted_mae", s.predictedMae}, {"frames_counted", s.framesCounted}};
        if (path_) {
            // The walk's coverage with every probe placed so far (coverage.h's definition, Embree): per
            // path frame at FeedbackSettings' default 64×36 (the live count may use another height).
            const placement::FeedbackSettings fs;
            double sum = 0.0, lowest = 1.0;
            for (std::size_t f = 0; f < path_->frames.size(); ++f) {
                const double c = live_->feedback().frameCoverage(
                    placement::tracePixels(placementScene_->embree(), PinholeCamera(*path_, f, fs.width, fs.height)));
                sum += c, lowest = std::min(lowest, c);
            }
            j["live"]["walk_coverage_mean"] = sum / double(std::max<std::size_t>(path_->frames.size(), 1));
            j["live"]["walk_coverage_min"] = lowest;
        }
    }
    nlohmann::json log = nlohmann::json::array();
    for (const FrameRecord& f : frameLog_) log.push_back({f.ms, f.bakeMs, f.scriptLine});
    j["frame_log"] = {{"columns", {"ms", "bake_ms", "script_line"}}, {"frames", log}};
    return j;
}

bool Viewer::pressed(int key) {
    const bool down = glfwGetKey(window_->window(), key) == GLFW_PRESS;
    const bool was = std::exchange(keyWasDown_[key], down);
    return down && !was;
}

fs::path Viewer::defaultSavePath() const {
    if (!o_.saveTo.empty()) return o_.saveTo;
    return cache_ ? fs::path(o_.cache).replace_extension(".live.cubeao") : fs::path("live.cubeao");
}

// Keys: 1–8 view modes, Tab panel, P play/pause the path, [ ] path frames, R record, F12 screenshot,
// Ctrl+S save, L live placement, Esc quit. Not while ImGui has the keyboard (a text field).
void Viewer::handleKeys() {
    if (ImGui::GetIO().WantCaptureKeyboard) return;
    const std::span<const ViewMode> all = allViewModes();
    for (std::size_t i = 0; i < all.size() && i < 9; ++i)
        if (pressed(GLFW_KEY_1 + int(i))) s_.mode = all[i];
    if (pressed(GLFW_KEY_TAB)) s_.showPanel = !s_.showPanel;
    if (pressed(GLFW_KEY_ESCAPE)) quit_ = true;
    if (pressed(GLFW_KEY_P) && path_) togglePlaying();
    if (pressed(GLFW_KEY_RIGHT_BRACKET) && path_) setPathFrame(s_.pathFrame ? *s_.pathFrame + 1 : 0);
    if (pressed(GLFW_KEY_LEFT_BRACKET) && path_) setPathFrame(s_.pathFrame && *s_.pathFrame > 0 ? *s_.pathFrame - 1 : 0);
    if (pressed(GLFW_KEY_R)) toggleRecording();
    if (pressed(GLFW_KEY_F12)) {
        char name[64];
        std::snprintf(name, sizeof name, "cubeao-view-%03d.png", screenshots_++);
        viewScreenshot(name);
        s_.status = std::string("screenshot ") + name;
    }
    const bool ctrl = glfwGetKey(window_->window(), GLFW_KEY_LEFT_CONTROL) == GLFW_PRESS ||
                      glfwGetKey(window_->window(), GLFW_KEY_RIGHT_CONTROL) == GLFW_PRESS;
    if (pressed(GLFW_KEY_S) && ctrl) save(defaultSavePath());
    if (pressed(GLFW_KEY_L)) setLive(!s_.liveOn);
    const float scroll = ImGui::GetIO().MouseWheel;
    if (scroll != 0.0f && !ImGui::GetIO().WantCaptureMouse) s_.speed *= std::pow(1.25f, scroll);
}

void Viewer::panel() {
    PanelFigures f;
    f.sceneName = scene_.source;
    f.triangles = scene_.triangleCount();
    const FramePipeline& pipeline = activePipeline();
    f.width = pipeline.width(), f.height = pipeline.height();
    f.fixedSize = fixedSize_;
    f.frameMs = frameMs_;
    f.recentFrameMs = &frameTimes_;
    if (timings_) f.gpu = timings_->passes;
    f.gpuTimesAreExecution = main_->timesAreExecution();
    f.probes = probes();
    f.shares = shares_;
    f.damaged = damagedProbes();
    f.live = live_.get();
    f.coverageObjective = liveObjective_ == placement::LiveSettings::Objective::Coverage;
    f.coverageTarget = o_.coverageTarget, f.bakeMsBudget = o_.bakeMsPerFrame;
    f.pathFrames = path_ ? path_->frames.size() : 0;
    const PanelRequests r = drawPanel(s_, f);
    if (r.live) setLive(*r.live);
    if (r.pathFrame) setPathFrame(*r.pathFrame);
    if (r.togglePlaying) togglePlaying();
    if (r.toggleRecording) toggleRecording();
    if (r.save) save(defaultSavePath());
}

int Viewer::run() {
    auto last = Clock::now();
    bool scripted = !script_.empty();
    while (!window_->shouldClose() && !quit_) {
        gl::WindowContext::pollEvents();
        const auto now = Clock::now();
        const double dt = std::chrono::duration<double>(now - last).count();
        last = now;
        const auto frameStart = Clock::now();

        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        handleKeys();
        handleInput(std::min(dt, 0.25));
        if (s_.playing && !scripted && path_ && s_.pathFrame) {
            if (*s_.pathFrame + 1 < path_->frames.size())
                setPathFrame(*s_.pathFrame + 1);
            else
                s_.playing = false;
        }
        renderFrame();

        int fw = 0, fh = 0;
        window_->framebufferSize(fw, fh);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glViewport(0, 0, fw, fh);
        glClearColor(0.08f, 0.09f, 0.11f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        drawView(0, 0, fw, fh);
        if (s_.showPanel) panel();
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        // Script commands run after the frame is drawn, so screenshots show what was just rendered;
        // their own time (screenshots, saves) is not the frame's.
        const int line = scriptPos_ > 0 ? script_[scriptPos_ - 1].line : 0;
        const auto scriptStart = Clock::now();
        if (scripted && !stepScript()) quit_ = true;
        const double scriptMs = msSince(scriptStart);

        window_->swapBuffers();

        frameMs_ = msSince(frameStart) - scriptMs;
        if (frameLog_.size() < 1000000)
            frameLog_.push_back({frameMs_, live_ ? live_->stats().bakeMsLastFrame : 0.0, line});
        frameMsMean_ += (frameMs_ - frameMsMean_) / double(serial_);
        frameTimes_.push_back(frameMs_);
        if (frameTimes_.size() > 120) frameTimes_.pop_front();
    }
    if (live_) spdlog::info("cubeao-view: live placement: {} probes placed, {} baked, {} re-baked",
                            live_->stats().placed, live_->stats().baked, live_->stats().rebaked);
    if (!o_.statsJson.empty()) writeFileDurably(o_.statsJson, summary().dump(2) + "\n", "statistics");
    return 0;
}

}  // namespace

int runViewer(const ViewerOptions& options) {
    Viewer viewer(options);
    return viewer.run();
}

}  // namespace cubeao::viewer

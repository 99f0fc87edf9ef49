// What a person sees of cubeao-view and changes by keys, mouse, panel or script: the camera, the view
// mode, the path frame and playback, live placement on or off, recording. The Viewer (viewer.cpp) owns
// one and acts on it; the panel (panel.h) draws it and edits it.
#pragma once

#include <cmath>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "cubeao-view/view_mode.h"
#include "cubeao/core/camera.h"

namespace cubeao::viewer {

// A free camera: eye, unit forward, the scene's up. Turning keeps forward off the up axis.
struct FlyCamera {
    glm::vec3 eye{0.0f}, forward{0.0f, 0.0f, -1.0f}, up{0.0f, 1.0f, 0.0f};
    float fovYDeg = 60.0f, nearPlane = 0.05f;

    glm::vec3 right() const { return glm::normalize(glm::cross(forward, up)); }
    void turn(float yawDeg, float pitchDeg) {
        glm::vec3 f = glm::angleAxis(glm::radians(yawDeg), up) * forward;
        const glm::vec3 r = glm::normalize(glm::cross(f, up));
        const glm::vec3 pitched = glm::angleAxis(glm::radians(pitchDeg), r) * f;
        if (std::abs(glm::dot(glm::normalize(pitched), up)) < 0.995f) f = pitched;
        forward = glm::normalize(f);
    }
    void lookAt(const glm::vec3& target) {
        const glm::vec3 d = target - eye;
        if (glm::length(d) > 0.0f && std::abs(glm::dot(glm::normalize(d), up)) < 0.9999f) forward = glm::normalize(d);
    }
    void move(const glm::vec3& rightUpForward) {
        eye += right() * rightUpForward.x + up * rightUpForward.y + forward * rightUpForward.z;
    }
    // A one-frame camera path, so PinholeCamera builds the basis exactly as for a path frame.
    CameraPath asPath() const {
        CameraPath p;
        p.up = up, p.fovYDeg = fovYDeg, p.nearPlane = nearPlane;
        p.frames.push_back({eye, eye + forward});
        return p;
    }
    PinholeCamera pinhole(int width, int height) const { return PinholeCamera(asPath(), 0, width, height); }
    void setFrame(const CameraPath& path, std::size_t f) {
        up = glm::normalize(path.up), fovYDeg = path.fovYDeg, nearPlane = path.nearPlane;
        eye = path.frames[f].eye;
        forward = glm::normalize(path.frames[f].target - eye);
    }
};

struct ViewerState {
    ViewMode mode = ViewMode::Shaded;
    std::string baseline = "gtao";            // the baseline mode's method (viewerBaselines())
    FlyCamera camera;
    float speed = 1.0f;                       // world units per second
    std::optional<std::size_t> pathFrame;     // the camera sits on this frame of the camera path
    bool playing = false;                     // following the path, a frame per rendered frame
    bool liveOn = false;                      // live placement places and bakes
    bool showPanel = true;
    float scale = 0.5f;                       // render resolution relative to the window
    std::string status;                       // the last action's message, for the panel
    std::optional<std::filesystem::path> recordFile;  // recording the camera to this file
    std::vector<CameraFrame> recorded;        // the frames recorded so far
};

}  // namespace cubeao::viewer

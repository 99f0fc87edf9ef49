#include "cubeao/reference/embree_scene.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <spdlog/spdlog.h>

#include "cubeao/core/error.h"

namespace cubeao {

struct EmbreeScene::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
};

namespace {
void onEmbreeError(void*, RTCError code, const char* str) {
    spdlog::error("Embree error {}: {}", int(code), str ? str : "");
}
}  // namespace

EmbreeScene::EmbreeScene(const Scene& s) : impl_(std::make_unique<Impl>()) {
    impl_->device = rtcNewDevice(nullptr);
    if (!impl_->device) throw Error("Embree: cannot create a device (error " + std::to_string(rtcGetDeviceError(nullptr)) + ")");
    rtcSetDeviceErrorFunction(impl_->device, onEmbreeError, nullptr);
    impl_->scene = rtcNewScene(impl_->device);
    rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
    rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);

    RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree reads vertex buffers with 16-byte loads: one float of padding after the last vertex.
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), s.positions.size() + 1));
    std::memcpy(v, s.positions.data(), s.positions.size() * sizeof(glm::vec3));
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), s.triangleCount()));
    std::memcpy(idx, s.indices.data(), s.indices.size() * sizeof(std::uint32_t));
    rtcCommitGeometry(geom);
    rtcAttachGeometry(impl_->scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(impl_->scene);

    epsilon_ = surfaceEpsilonFor(s);
}

float surfaceEpsilonFor(const Scene& s) {
    // ~170 float ulps at the scene's largest coordinate (0.7 mm for a 68 m cathedral): enough to clear
    // the rounding of a hit point reconstructed 100 m from the camera, far below any AO radius.
    const glm::vec3 far = glm::max(glm::abs(s.bounds.min), glm::abs(s.bounds.max));
    const float extent = std::max({far.x, far.y, far.z});
    return std::max(1e-6f, extent * 1e-5f);
}

EmbreeScene::~EmbreeScene() {
    if (impl_->scene) rtcReleaseScene(impl_->scene);
    if (impl_->device) rtcReleaseDevice(impl_->device);
}

RayHit EmbreeScene::intersect(const glm::vec3& org, const glm::vec3& dir, float tnear, float tfar) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh{};
    rh.ray.org_x = org.x, rh.ray.org_y = org.y, rh.ray.org_z = org.z;
    rh.ray.dir_x = dir.x, rh.ray.dir_y = dir.y, rh.ray.dir_z = dir.z;
    rh.ray.tnear = tnear;
    rh.ray.tfar = tfar;
    rh.ray.mask = ~0u;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl_->scene, &ctx, &rh);
    RayHit out;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return out;
    out.hit = true;
    out.t = rh.ray.tfar;
    out.primitive = rh.hit.primID;
    out.normal = glm::normalize(glm::vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
    return out;
}

bool EmbreeScene::occluded(const glm::vec3& org, const glm::vec3& dir, float tnear, float tfar) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay ray{};
    ray.org_x = org.x, ray.org_y = org.y, ray.org_z = org.z;
    ray.dir_x = dir.x, ray.dir_y = dir.y, ray.dir_z = dir.z;
    ray.tnear = tnear;
    ray.tfar = tfar;
    ray.mask = ~0u;
    rtcOccluded1(impl_->scene, &ctx, &ray);
    return ray.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
}

}  // namespace cubeao

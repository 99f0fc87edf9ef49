// Embree reference AO against answers known in closed form (DESIGN.md §6).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "cubeao/core/error.h"
#include "cubeao/reference/ao_reference.h"
#include "cubeao/core/sampling.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scenes/builtin_scenes.h"

namespace cubeao {
namespace {

const glm::vec3 kUp(0.0f, 1.0f, 0.0f);

// A built-in scene and its Embree BVH, built once per test program and shared by the tests below.
struct Loaded {
    Scene scene;
    EmbreeScene rt;
    explicit Loaded(const std::string& spec) : scene(makeBuiltinScene(spec)), rt(scene) {}
};
const EmbreeScene& spherePlane() {
    static const Loaded loaded("builtin:sphere-plane");
    return loaded.rt;
}
const EmbreeScene& boxRoom() {
    static const Loaded loaded("builtin:box-room");
    return loaded.rt;
}

TEST(SpherePlane, UnderTheCentreMatchesOneMinusRatioSquared) {
    // Unbounded AO under a sphere of radius r at height h is 1 − (r/h)²; every ray towards the sphere
    // hits within sqrt(h² − r²) < 2, so R = 10 is "unbounded" here.
    const float r = scenes::kSphereRadius, h = scenes::kSphereHeight;
    const AoSettings settings{10.0f, 16384, Falloff::None, 0};
    const AoEstimate e = ambientOcclusion(spherePlane(), glm::vec3(0.0f), kUp, settings, 1234u);
    EXPECT_NEAR(e.ao, 1.0f - (r / h) * (r / h), 0.01f);
    // The iid standard error of a Bernoulli mean with p = 1/4.
    EXPECT_NEAR(e.stdError, std::sqrt(0.75 * 0.25 / 16384.0), 2e-4);
}

TEST(SpherePlane, RadiusShorterThanTheSphereSeesNothing) {
    // The sphere's lowest point is h − r = 1 above the origin: with R = 0.9 nothing is in reach.
    const AoSettings settings{0.9f, 256, Falloff::None, 0};
    EXPECT_EQ(ambientOcclusion(spherePlane(), glm::vec3(0.0f), kUp, settings, 7u).ao, 1.0f);
}

TEST(SpherePlane, OpenPlaneIsFullyOpen) {
    const AoSettings settings{2.0f, 256, Falloff::None, 0};
    const AoEstimate e = ambientOcclusion(spherePlane(), glm::vec3(30.0f, 0.0f, 30.0f), kUp, settings, 99u);
    EXPECT_EQ(e.ao, 1.0f);
    EXPECT_EQ(e.stdError, 0.0f);
}

TEST(SpherePlane, SmoothFalloffNeverDarkensMoreThanNone) {
    const AoSettings none{3.0f, 1024, Falloff::None, 0}, smooth{3.0f, 1024, Falloff::Smooth, 0};
    const float aoNone = ambientOcclusion(spherePlane(), glm::vec3(0.0f), kUp, none, 5u).ao;
    const float aoSmooth = ambientOcclusion(spherePlane(), glm::vec3(0.0f), kUp, smooth, 5u).ao;
    EXPECT_GT(aoSmooth, aoNone + 0.05f);  // hits lie 1–1.7 from the origin: weights well below 1
    EXPECT_LT(aoSmooth, 1.0f);
}

TEST(Falloff, WeightsAndNames) {
    EXPECT_EQ(occlusionWeight(Falloff::None, 2.9f, 3.0f), 1.0f);
    EXPECT_EQ(occlusionWeight(Falloff::Smooth, 0.0f, 3.0f), 1.0f);
    EXPECT_NEAR(occlusionWeight(Falloff::Smooth, 3.0f, 3.0f), 0.0f, 1e-6f);
    EXPECT_NEAR(occlusionWeight(Falloff::Smooth, 1.5f, 3.0f), 0.5625f, 1e-6f);
    EXPECT_EQ(parseFalloff("smooth"), Falloff::Smooth);
    EXPECT_THROW(parseFalloff("linear"), UsageError);
}

TEST(BoxRoom, ClosedBoxIsFullyOccludedWhenRadiusExceedsIt) {
    const float radius = 1.5f * glm::length(glm::vec3(scenes::kRoomX, scenes::kRoomY, scenes::kRoomZ));
    const AoSettings settings{radius, 1024, Falloff::None, 0};
    const AoEstimate e = ambientOcclusion(boxRoom(), glm::vec3(3.0f, 0.0f, 2.0f), kUp, settings, 3u);
    EXPECT_EQ(e.ao, 0.0f);
}

TEST(BoxRoom, AoFallsMonotonicallyTowardsTheInnerCorner) {
    // Floor points on the diagonal towards the free corner at the origin, all with the same rays (same
    // key): each ray's distance to the two walls shrinks as the point nears the corner, so the occluded
    // set only grows. Nothing else is within R of these points.
    const float radius = 1.5f;
    const AoSettings settings{radius, 1024, Falloff::None, 0};
    float previous = 2.0f, first = 0.0f, last = 0.0f;
    for (int i = 0; i <= 20; ++i) {
        const float d = 2.0f - 0.0975f * float(i);  // 2.0 m … 0.05 m from each wall
        const float ao = ambientOcclusion(boxRoom(), glm::vec3(d, 0.0f, d), kUp, settings, 42u).ao;
        EXPECT_LE(ao, previous) << "at " << d << " m from the walls";
        if (i == 0) first = ao;
        last = ao;
        previous = ao;
    }
    EXPECT_GT(first, 0.95f);        // 2 m from walls, R = 1.5: almost open
    EXPECT_LT(last, first - 0.3f);  // 5 cm from the corner: two walls block a large part
}

TEST(BoxRoom, EveryDirectionFromInsideHitsAWall) {
    // "Closed room": no ray escapes (the closed-box test above relies on it).
    const glm::vec3 p(4.0f, 1.5f, 3.0f);
    for (std::uint32_t i = 0; i < 512; ++i) {
        const glm::vec2 u = sampling::rotatedHammersley(i, 512, 0);
        const float z = 1.0f - 2.0f * u.x, s = std::sqrt(std::max(0.0f, 1.0f - z * z));
        const glm::vec3 dir(s * std::cos(6.2831853f * u.y), z, s * std::sin(6.2831853f * u.y));
        EXPECT_TRUE(boxRoom().intersect(p, dir, 0.0f, 100.0f).hit) << "direction " << i;
    }
}

TEST(BoxRoom, FrameIsDeterministicAndZeroWhenRadiusExceedsTheRoom) {
    const CameraPath path = builtinCameraPath("builtin:box-room");
    const PinholeCamera cam(path, 3, 32, 18);
    const AoSettings settings{20.0f, 16, Falloff::None, 0};
    const ReferenceFrame a = renderReferenceFrame(boxRoom(), cam, settings, 3, nullptr);
    const ReferenceFrame b = renderReferenceFrame(boxRoom(), cam, settings, 3, nullptr);
    ASSERT_EQ(a.ao.pixels.size(), 32u * 18u);
    EXPECT_EQ(a.ao.pixels, b.ao.pixels);
    EXPECT_EQ(a.backgroundFraction, 0.0);
    for (float v : a.ao.pixels) EXPECT_EQ(v, 0.0f);
    EXPECT_EQ(a.aoRays, 32u * 18u * 16u);
}

TEST(BoxRoom, FrameMatchesPointQueriesAtThePrimaryHits) {
    const CameraPath path = builtinCameraPath("builtin:box-room");
    const PinholeCamera cam(path, 0, 24, 16);
    const AoSettings settings{1.0f, 32, Falloff::None, 9};
    const ReferenceFrame f = renderReferenceFrame(boxRoom(), cam, settings, 0, nullptr);
    double mean = 0.0;
    for (int y = 0; y < cam.height; y += 5)
        for (int x = 0; x < cam.width; x += 5) {
            const glm::vec3 dir = cam.rayDirection(x, y);
            const RayHit hit = boxRoom().intersect(cam.eye, dir, 0.0f, 1e9f);
            ASSERT_TRUE(hit.hit);
            const glm::vec3 n = glm::dot(hit.normal, dir) > 0.0f ? -hit.normal : hit.normal;
            const float ao = ambientOcclusion(boxRoom(), cam.eye + hit.t * dir, n, settings,
                                              sampling::hashKey(std::uint32_t(x), std::uint32_t(y), 0u ^ 9u)).ao;
            EXPECT_EQ(f.ao.at(x, y), ao) << x << "," << y;
        }
    for (float v : f.ao.pixels) mean += v;
    mean /= double(f.ao.pixels.size());
    EXPECT_GT(mean, 0.5);  // a 1 m radius in an 8 m room: mostly open, with darker corners
    EXPECT_LT(mean, 0.999);
}

TEST(ReferenceFrame, BackFacesAreEvaluatedOnTheSideTheCameraSees) {
    // Under the sphere-plane's plane looking up: the plane's back face, whose hemisphere (downwards) is
    // empty. Without flipping the normal the rays would go up into the sphere and darken the centre.
    const Scene scene = makeBuiltinScene("builtin:sphere-plane");
    const EmbreeScene rt(scene);
    CameraPath path;
    path.frames.push_back({{0.5f, -1.0f, 0.0f}, {0.0f, 0.0f, 0.0f}});
    const PinholeCamera cam(path, 0, 16, 16);
    const AoSettings settings{5.0f, 64, Falloff::None, 0};
    const ReferenceFrame f = renderReferenceFrame(rt, cam, settings, 0, nullptr);
    EXPECT_EQ(f.backgroundFraction, 0.0);
    for (float v : f.ao.pixels) EXPECT_EQ(v, 1.0f);
}

TEST(ReferenceFrame, RejectsBadSettings) {
    const Scene scene = makeBuiltinScene("builtin:box-room");
    const EmbreeScene rt(scene);
    const PinholeCamera cam(builtinCameraPath("builtin:box-room"), 0, 8, 8);
    EXPECT_THROW(renderReferenceFrame(rt, cam, AoSettings{1.0f, 0, Falloff::None, 0}, 0, nullptr), UsageError);
    EXPECT_THROW(renderReferenceFrame(rt, cam, AoSettings{}, 0, nullptr), UsageError);
    const AoSettings ok{1.0f, 6, Falloff::None, 0};
    EXPECT_THROW(renderReferenceFrame(rt, cam, ok, 0, nullptr, 4), UsageError);  // 4 does not divide 6
    EXPECT_THROW(renderReferenceFrame(rt, cam, ok, 0, nullptr, 0), UsageError);
    EXPECT_NO_THROW(renderReferenceFrame(rt, cam, ok, 0, nullptr, 3));
    // --aa N: each of the N² primary rays traces spp/N² AO rays, in the replicas' sets.
    EXPECT_THROW(renderReferenceFrame(rt, cam, ok, 0, nullptr, 1, 2), UsageError);           // 4 does not divide 6
    EXPECT_THROW(renderReferenceFrame(rt, cam, AoSettings{1.0f, 4, Falloff::None, 0}, 0, nullptr, 2, 2), UsageError);
    EXPECT_THROW(renderReferenceFrame(rt, cam, ok, 0, nullptr, 1, 0), UsageError);
    EXPECT_NO_THROW(renderReferenceFrame(rt, cam, AoSettings{1.0f, 8, Falloff::None, 0}, 0, nullptr, 2, 2));
}

// Root mean square of the difference over all pixels.
double rmsDifference(const Image& a, const Image& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) sum += double(a.pixels[i] - b.pixels[i]) * (a.pixels[i] - b.pixels[i]);
    return std::sqrt(sum / double(a.pixels.size()));
}

TEST(ReferenceFrame, ReplicasMeasureTheErrorThatTwoSeedsShow) {
    // Two frames with different seeds have independent errors, so the RMS of their difference is
    // √2 × each one's RMS error: the truth that the replica estimate must match. The cloister's
    // arcades give every pixel a partly occluded hemisphere at R = 0.7 m.
    const Loaded cloister("builtin:cloister");
    const PinholeCamera cam(builtinCameraPath("builtin:cloister"), 10, 64, 36);
    AoSettings settings{cloister.scene.defaultRadius(), 64, Falloff::None, 1};
    const ReferenceFrame a = renderReferenceFrame(cloister.rt, cam, settings, 10, nullptr, 2);
    settings.seed = 2;
    const ReferenceFrame b = renderReferenceFrame(cloister.rt, cam, settings, 10, nullptr, 2);
    // Sky pixels are 1 in both images; the noise runs over the pixels that show geometry.
    ASSERT_LT(a.backgroundFraction, 0.5);
    const double observed = rmsDifference(a.ao, b.ao) / std::sqrt(2.0 * (1.0 - a.backgroundFraction));
    const double estimated = 0.5 * (a.noise + b.noise);
    // 2,304 pixels with one degree of freedom each: the estimate's own spread is a few per cent, and
    // the observed RMS from one pair about the same (measured: ratio 1.013; a variance not divided by
    // the replica count would read 1.41).
    EXPECT_GT(observed, 0.0);
    EXPECT_NEAR(estimated / observed, 1.0, 0.2) << "estimated " << estimated << ", observed " << observed;
    // The independent-ray bound (one replica) overstates the error of the rotated Hammersley set
    // (measured: 1.8× the 2 × 32-ray error, itself larger than the 64-ray set's).
    const ReferenceFrame bound = renderReferenceFrame(cloister.rt, cam, settings, 10, nullptr, 1);
    EXPECT_GT(bound.noise, 1.3 * observed) << "bound " << bound.noise;
}

TEST(Sampling, CosineDirectionsStayInTheHemisphereAndAverageToTheNormal) {
    const glm::vec3 n = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f));
    glm::vec3 sum(0.0f);
    const std::uint32_t count = 4096;
    for (std::uint32_t i = 0; i < count; ++i) {
        const glm::vec3 d = sampling::cosineHemisphere(sampling::rotatedHammersley(i, count, 17u), n);
        EXPECT_NEAR(glm::length(d), 1.0f, 1e-5f);
        EXPECT_GE(glm::dot(d, n), 0.0f);
        sum += d;
    }
    // E[cos θ] under a cosine-weighted pdf is 2/3, and the mean points along n.
    const glm::vec3 mean = sum / float(count);
    EXPECT_NEAR(glm::dot(mean, n), 2.0f / 3.0f, 2e-3f);
    EXPECT_NEAR(glm::length(mean - glm::dot(mean, n) * n), 0.0f, 2e-3f);
}

}  // namespace
}  // namespace cubeao

namespace cubeao {
namespace {

// Mean of each factor × factor block: the box filter of an image rendered at `factor` times the size.
Image boxDownsample(const Image& big, int factor) {
    Image small;
    small.width = big.width / factor;
    small.height = big.height / factor;
    small.pixels.assign(std::size_t(small.width) * std::size_t(small.height), 0.0f);
    for (int y = 0; y < small.height; ++y)
        for (int x = 0; x < small.width; ++x) {
            double sum = 0.0;
            for (int dy = 0; dy < factor; ++dy)
                for (int dx = 0; dx < factor; ++dx) sum += big.at(x * factor + dx, y * factor + dy);
            small.pixels[std::size_t(y) * std::size_t(small.width) + std::size_t(x)] = float(sum / (factor * factor));
        }
    return small;
}

// `reference --aa N` (issue 17): N×N primary rays per pixel, box-filtered, is the image an offline
// renderer makes, i.e. the same view rendered N times larger with pixel-centre rays and box-filtered
// down. The cloister at 32×18 has arcades against the sky in most frames, so pixel-centre sampling
// misses it by much more than noise at the silhouettes.
TEST(ReferenceFrame, AntiAliasingMatchesABoxFilteredLargerImage) {
    const Loaded cloister("builtin:cloister");
    const CameraPath path = builtinCameraPath("builtin:cloister");
    const AoSettings settings{cloister.scene.defaultRadius(), 256, Falloff::None, 0};
    const int w = 32, h = 18, n = 4;
    const ReferenceFrame aa = renderReferenceFrame(cloister.rt, PinholeCamera(path, 10, w, h), settings, 10, nullptr, 2, n);
    const ReferenceFrame centre = renderReferenceFrame(cloister.rt, PinholeCamera(path, 10, w, h), settings, 10, nullptr, 2);
    AoSettings fine = settings;
    fine.spp = settings.spp / (n * n);  // the same AO rays per pixel of the small image
    fine.seed = 7;
    const ReferenceFrame big = renderReferenceFrame(cloister.rt, PinholeCamera(path, 10, w * n, h * n), fine, 10, nullptr, 2);
    const Image truth = boxDownsample(big.ao, n);
    ASSERT_GT(aa.backgroundFraction, 0.02);  // some sky: silhouettes to filter
    EXPECT_NEAR(aa.backgroundFraction, big.backgroundFraction, 0.02);
    // Every sub-sample that sees geometry traces spp/n² AO rays.
    const double hitSamples = (1.0 - aa.backgroundFraction) * double(w * h * n * n);
    EXPECT_NEAR(double(aa.aoRays), hitSamples * double(settings.spp / (n * n)), 0.5);
    const double dAa = rmsDifference(aa.ao, truth), dCentre = rmsDifference(centre.ao, truth);
    // The big image's noise per small pixel is its per-pixel noise over n (n² independent pixels averaged).
    const double noise = std::sqrt(aa.noise * aa.noise + big.noise * big.noise / double(n * n));
    std::printf("[ info ] rms vs box-filtered 4x image: aa %.4f, pixel centres %.4f; noise %.4f\n", dAa, dCentre, noise);
    // Beyond the AO noise, the jittered sub-samples and the big image's cell centres cover a silhouette
    // differently (16 samples estimate its area share); measured 1.5× the AO noise at 256 rays.
    EXPECT_LT(dAa, 2.0 * noise);
    EXPECT_GT(dCentre, 2.5 * dAa);
}

}  // namespace
}  // namespace cubeao

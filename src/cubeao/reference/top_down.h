// A plan of a scene: an orthographic view from above, cut horizontally a little above the highest
// viewer (the walk's eyes, else the probes) so that roofs and vaults do not hide the floors the probes
// stand over. Rays go straight down from the cut (Embree); the shade is height (higher = lighter) times
// a Lambert term lit the same from either side of a face, outlines mark height jumps (the feet of walls),
// and a faint warm tint keeps it from reading as one more AO image. `cubeao report` draws the probes and
// the walk over it (toPixel).
#pragma once

#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "cubeao/scene/scene.h"

namespace cubeao {

struct TopDownView {
    int width = 0, height = 0;            // 0: nothing to draw (no scene and no points)
    std::vector<float> rgb;               // width × height × 3 in 0..1, row 0 first
    glm::vec3 e1{1, 0, 0}, e2{0, 0, 1}, up{0, 1, 0};  // pixel x along e1, y along e2, the view down −up
    float min1 = 0, min2 = 0, pixel = 1;  // the image's corner along e1 and e2, world units per pixel
    float cut = 0;                        // the section's height along `up`
    bool cutBelowTop = false;             // the cut removes part of the scene (a roof)
    glm::vec2 toPixel(const glm::vec3& p) const;  // a world point's pixel position (fractional)
};

// The view framing `probes` and `walk` with a margin (3 AO radii, at least 30 % of their extent) inside
// the scene's bounds, or the whole scene without points; at most `maxSide` pixels a side. The cut sits
// half an AO radius (`radius`; NaN: unknown, no offset) above the highest viewer. Without a scene (null)
// the image is blank around the points. Points in the scene's local coordinates.
TopDownView renderTopDown(const Scene* scene, std::span<const glm::vec3> probes, std::span<const glm::vec3> walk,
                          float radius, int maxSide);

}  // namespace cubeao

#include "cubeao/scenes/builtin_scenes.h"
#include "cubeao/scenes/mesh_builder.h"

namespace cubeao::scenes {

Scene makeTwoRooms() {
    MeshBuilder b;
    b.addBox({0.0f, 0.0f, 0.0f}, {kTwoRoomsX, kTwoRoomsY, kTwoRoomsZ}, /*inward=*/true);  // room A
    b.addBox({kTwoRoomsX + kTwoRoomsWall, 0.0f, 0.0f}, {2.0f * kTwoRoomsX + kTwoRoomsWall, kTwoRoomsY, kTwoRoomsZ},
             /*inward=*/true);                                                                // room B
    b.addBox({0.3f, 0.0f, 0.4f}, {1.1f, 1.2f, 1.6f}, false, false);  // a cabinet in room A: it hides some of A
    b.addBox({6.8f, 0.0f, 2.6f}, {7.8f, 0.75f, 3.6f}, false, false);  // a table in room B, away from the wall
    return b.take();
}

CameraPath twoRoomsPath() {
    CameraPath p;
    p.scene = "builtin:two-rooms";
    p.width = 320;
    p.height = 180;
    // Through room B, looking back at the thin wall and along it.
    const float wall = kTwoRoomsX + kTwoRoomsWall;
    for (int i = 0; i < 24; ++i) {
        const float t = float(i) / 23.0f;
        p.frames.push_back({{wall + 3.2f - 1.6f * t, 1.6f, 0.8f + 2.4f * t}, {wall, 0.9f - 0.4f * t, 3.2f - 2.4f * t}});
    }
    return p;
}

}  // namespace cubeao::scenes

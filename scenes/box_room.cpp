#include "cubeao/scenes/builtin_scenes.h"
#include "cubeao/scenes/mesh_builder.h"

namespace cubeao::scenes {

Scene makeBoxRoom() {
    MeshBuilder b;
    b.addBox({0.0f, 0.0f, 0.0f}, {kRoomX, kRoomY, kRoomZ}, /*inward=*/true);
    b.addBox({4.5f, 0.0f, 3.5f}, {6.0f, 0.8f, 4.5f}, false, false);  // table (a block)
    b.addBox({7.4f, 0.0f, 0.5f}, {8.0f, 2.0f, 2.0f}, false, false);  // cabinet against the +x wall
    b.addBox({1.0f, 0.0f, 4.5f}, {1.6f, 0.6f, 5.5f}, false, false);  // crate
    return b.take();
}

CameraPath boxRoomPath() {
    CameraPath p;
    p.scene = "builtin:box-room";
    p.width = 320;
    p.height = 180;
    for (int i = 0; i < 24; ++i) {
        const float t = float(i) / 23.0f;
        p.frames.push_back({{6.5f - 4.0f * t, 1.6f, 5.0f - 1.0f * t}, {1.0f - 0.5f * t, 0.6f, 0.5f + 1.5f * t}});
    }
    return p;
}

}  // namespace cubeao::scenes

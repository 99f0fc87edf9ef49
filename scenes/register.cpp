#include <mutex>

#include "cubeao/scene/builtin.h"
#include "cubeao/scenes/builtin_scenes.h"

namespace cubeao::scenes {

void registerBuiltinScenes() {
    static std::once_flag once;
    std::call_once(once, [] {
        registerBuiltinScene("sphere-plane", {makeSpherePlane, spherePlanePath});
        registerBuiltinScene("box-room", {makeBoxRoom, boxRoomPath});
        registerBuiltinScene("two-rooms", {makeTwoRooms, twoRoomsPath});
        registerBuiltinScene("cloister", {makeCloister, cloisterPath});
        registerBuiltinScene("town", {makeTown, townPath});
    });
}

}  // namespace cubeao::scenes

// Where the tests find the build's programs, the source tree and ../shared. The paths are compile
// definitions of test_paths.cpp alone (tests/CMakeLists.txt): every other test unit then compiles to
// the same object in any checkout, so a compiler cache filled in one clone hits in another (CI builds
// a fresh clone; CMakeLists.txt, "A compiler cache").
#pragma once

namespace cubeao::test {

const char* cubeaoBinary();    // the `cubeao` CLI of this build
const char* gpubenchBinary();  // `cubeao-gpubench` of this build
const char* viewerBinary();    // `cubeao-view` of this build (when the viewer is built)
const char* sourceDir();       // the repository root
const char* sharedDir();       // ../shared beside the repository (scenes, walks)

}  // namespace cubeao::test

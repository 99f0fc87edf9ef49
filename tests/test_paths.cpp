#include "test_paths.h"

namespace cubeao::test {

const char* cubeaoBinary() { return CUBEAO_BINARY; }
const char* gpubenchBinary() { return CUBEAO_GPUBENCH_BINARY; }
const char* viewerBinary() { return CUBEAO_VIEW_BINARY; }
const char* sourceDir() { return CUBEAO_SOURCE_DIR; }
const char* sharedDir() { return CUBEAO_SHARED_DIR; }

}  // namespace cubeao::test

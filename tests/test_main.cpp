// The test binary's main (GoogleTest's, plus two things every test needs first; shared by the
// helpers of issue 11: keep both when editing):
// - the builtin: scenes registered (scenes/include/cubeao/scenes/builtin_scenes.h), as the CLI's main does;
// - shader warnings made fatal (gl/shader.h) for every GL test and, through the environment, for
//   every `cubeao` run a test starts (cli_run.h): a GLSL warning is usually a real bug, and one that
//   is only logged scrolls by unread;
// - progress reports off (core/progress.h) unless the environment asks for them: a long child's
//   progress lines on stderr would otherwise interleave with the output a test reads; the progress
//   tests turn them on for their own children.
#include <gtest/gtest.h>

#include <cstdlib>

#include "cubeao/gl/shader.h"
#include "cubeao/scenes/builtin_scenes.h"

int main(int argc, char** argv) {
    cubeao::scenes::registerBuiltinScenes();
    ::setenv("CUBEAO_SHADER_WARNINGS", "error", 1);
    ::setenv("CUBEAO_PROGRESS", "off", 0);
    cubeao::gl::setShaderWarningsFatal(true);
    ::testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}

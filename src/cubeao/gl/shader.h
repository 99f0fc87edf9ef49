// Shader loading: a small preprocessor (pure, no GL) and program builders on top of it.
//
// GLSL has no #include, and we want shared headers in shaders/common/ plus #define variants instead
// of copy-pasted shaders (STYLE.md). The preprocessor resolves `#include "file"` against one include
// directory, once per file, and emits `#line LINE ID` directives so that the driver's messages
// ("3:12(5): error ...") can be mapped back to file names: ID is a source-string number, 0 for the
// main source and 1, 2, ... for headers in order of first inclusion (GLSL #line takes no file names).
//
// Limits, on purpose: only whole-line `#include "name"` (not inside #if blocks or /* */ comments:
// those are expanded regardless), no search path beyond the one include directory.
#pragma once

#include "cubeao/gl/handles.h"

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace cubeao::gl {

using ShaderDefines = std::vector<std::pair<std::string, std::string>>;  // {NAME, VALUE} -> #define NAME VALUE

struct PreprocessedShader {
    std::string text;                      // what glShaderSource gets
    std::vector<std::string> sourceNames;  // source-string id -> file name (0 = the main source)

    // Rewrites the source-string ids at the start of info-log lines ("0:12(5):" Mesa, "0(12) :" NVIDIA,
    // "ERROR: 0:12:" AMD) into file names: "shaders/foo.comp:12(5):".
    std::string mapLog(const std::string& infoLog) const;
};

// Keeps the #version line first, puts one `#define NAME VALUE` per define right after it, expands
// includes (once each; a cycle is an error) and numbers lines per file with #line. Throws
// cubeao::Error naming file and line for a missing #version, a missing include, a cycle or a
// malformed define. sourceName is used for messages only.
PreprocessedShader preprocessShaderSource(const std::string& source, const std::filesystem::path& includeDir,
                                          const ShaderDefines& defines, const std::string& sourceName);

// The same, text only.
std::string preprocessShader(const std::string& source, const std::filesystem::path& includeDir,
                             const ShaderDefines& defines, const std::string& sourceName);

// Where shader files live: $CUBEAO_SHADER_DIR, else the source tree's shaders/ if it exists, else the installed copy.
std::filesystem::path shaderDir();

// One stage of a program. name appears in error messages (a file path for files).
struct ShaderStage {
    GLenum stage;  // GL_COMPUTE_SHADER, GL_VERTEX_SHADER, GL_FRAGMENT_SHADER, ...
    std::string source;
    std::string name;
};

// Reads a stage from a file; a relative path is taken relative to shaderDir(). Throws cubeao::Error
// when the file cannot be read.
ShaderStage loadShaderStage(GLenum stage, const std::filesystem::path& file);

// Compiler and linker warnings: logged (spdlog::warn) by default, fatal when asked. A GLSL warning is
// usually a real bug (a variable read before it is written, a lost precision), so the tests make them
// fatal (tests/test_main.cpp), for their own programs and, through the environment, for the cubeao
// binary they run. Fatal when $CUBEAO_SHADER_WARNINGS is "error" (read at the first build) or after
// setShaderWarningsFatal(true), which overrides the variable.
void setShaderWarningsFatal(bool fatal);
bool shaderWarningsFatal();

// Preprocesses, compiles and links the stages (needs a current context). includeDir empty =
// shaderDir()/"common". Throws cubeao::Error with the info log, source ids mapped to file names, on
// an error, and on a warning when shaderWarningsFatal().
Program buildProgram(const std::vector<ShaderStage>& stages, const ShaderDefines& defines = {},
                     const std::filesystem::path& includeDir = {});

// File conveniences (paths relative to shaderDir()).
Program compileComputeProgram(const std::filesystem::path& computeFile, const ShaderDefines& defines = {});
Program compileRenderProgram(const std::filesystem::path& vertexFile, const std::filesystem::path& fragmentFile,
                             const ShaderDefines& defines = {});

}  // namespace cubeao::gl

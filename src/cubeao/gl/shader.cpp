#include "cubeao/gl/shader.h"

#include "cubeao/core/error.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include <unistd.h>  // getpid

namespace cubeao::gl {

namespace fs = std::filesystem;

namespace {

std::vector<std::string> splitLines(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        if (!line.empty() && line.back() == '\r') line.pop_back();  // files saved on Windows
        lines.push_back(std::move(line));
    }
    return lines;
}

// "#  version", "#include" etc.: the directive word after '#' and optional blanks, or "".
std::string directive(const std::string& line) {
    static const std::regex re(R"(^\s*#\s*([A-Za-z_]+))");
    std::smatch m;
    return std::regex_search(line, m, re) ? m[1].str() : std::string();
}

bool isPragmaOnce(const std::string& line) {
    static const std::regex re(R"(^\s*#\s*pragma\s+once\s*(//.*)?$)");
    return std::regex_match(line, re);
}

std::string readFile(const fs::path& path) {
    errno = 0;
    std::ifstream in(path, std::ios::binary);
    // The cause too (missing, unreadable): shaders are read at run time from CUBEAO_SHADER_DIR or the
    // build's copy, so a bad install shows up here.
    if (!in) throw Error("cannot read shader file " + path.string() + ": " + (errno ? std::strerror(errno) : "open failed"));
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

void checkDefine(const std::pair<std::string, std::string>& define, const std::string& sourceName) {
    static const std::regex identifier(R"([A-Za-z_][A-Za-z0-9_]*)");
    if (!std::regex_match(define.first, identifier))
        throw Error(sourceName + ": define name '" + define.first + "' is not an identifier");
    if (define.second.find_first_of("\r\n") != std::string::npos)
        throw Error(sourceName + ": value of define " + define.first + " spans lines");
}

// Shared kernel headers (shaders/common/*.h, glsl_cpp.h) hold C++-only code in
// `#ifdef __cplusplus` / `#if defined(__cplusplus)` blocks and GLSL-only code in `#ifndef __cplusplus`
// ones. GLSL never defines __cplusplus, so the loader drops the C++ side itself (with its
// `#include <...>` lines, which it could not resolve) and keeps the other, directives removed.
// Other conditionals pass through to the GLSL compiler untouched; only their nesting is tracked.
class CppBlocks {
public:
    explicit CppBlocks(std::string file) : file_(std::move(file)) {}

    // Whether `line` (1-based number `number`) goes to the GLSL compiler.
    bool keep(const std::string& line, std::size_t number) {
        const std::string word = directive(line);
        if (word == "if" || word == "ifdef" || word == "ifndef") {
            const int test = cppTest(line, word);
            blocks_.push_back({test, test == 0 ? true : test < 0, number});
            return test == 0 && live();
        }
        if (blocks_.empty()) return true;
        Block& b = blocks_.back();
        if (word == "else" || word == "elif") {
            if (b.test == 0) return live();
            if (word == "elif") throw Error(file_ + ":" + std::to_string(number) + ": #elif after a __cplusplus test");
            b.keeping = !b.keeping;
            return false;
        }
        if (word == "endif") {
            const bool pass = b.test == 0;
            blocks_.pop_back();
            return pass && live();
        }
        return live();
    }

    void finish(std::size_t lines) const {
        if (!blocks_.empty())
            throw Error(file_ + ":" + std::to_string(blocks_.back().line) + ": #if without #endif (file has " +
                        std::to_string(lines) + " lines)");
    }

private:
    struct Block {
        int test;      // +1: C++ only, −1: GLSL only (#ifndef __cplusplus), 0: any other condition
        bool keeping;  // whether the current branch of a __cplusplus block is GLSL's
        std::size_t line;
    };

    // +1 for `#ifdef __cplusplus` / `#if defined(__cplusplus)`, −1 for `#ifndef __cplusplus` /
    // `#if !defined(__cplusplus)`, 0 otherwise.
    static int cppTest(const std::string& line, const std::string& word) {
        static const std::regex name(R"(^\s*#\s*if(n?)def\s+__cplusplus\s*(//.*)?$)");
        static const std::regex defined(R"(^\s*#\s*if\s+(!?)\s*defined\s*\(?\s*__cplusplus\s*\)?\s*(//.*)?$)");
        std::smatch m;
        if (word != "if" && std::regex_match(line, m, name)) return m[1].length() ? -1 : 1;
        if (word == "if" && std::regex_match(line, m, defined)) return m[1].length() ? -1 : 1;
        return 0;
    }

    bool live() const {
        for (const Block& b : blocks_)
            if (!b.keeping) return false;
        return true;
    }

    std::string file_;
    std::vector<Block> blocks_;
};

// Expands one main source; one instance per preprocessShaderSource call.
class Preprocessor {
public:
    explicit Preprocessor(fs::path includeDir) : includeDir_(std::move(includeDir)) {}

    PreprocessedShader run(const std::string& source, const ShaderDefines& defines, const std::string& sourceName) {
        const std::vector<std::string> lines = splitLines(source);
        std::size_t version = 0;
        while (version < lines.size() && directive(lines[version]) != "version") ++version;
        if (version == lines.size()) throw Error(sourceName + ": no #version line (GLSL needs it first)");

        names_.push_back(sourceName);
        // Lines before #version can only be comments or blank; keeping them keeps line numbers true.
        for (std::size_t i = 0; i <= version; ++i) out_ += lines[i] + "\n";
        for (const auto& define : defines) {
            checkDefine(define, sourceName);
            out_ += "#define " + define.first + " " + define.second + "\n";
        }
        out_ += "#line " + std::to_string(version + 2) + " 0\n";  // the line after #version, 1-based
        expand(lines, version + 1, 0);
        return {std::move(out_), std::move(names_)};
    }

private:
    // Appends the lines of source `id` from index `first` on, includes expanded and C++-only blocks
    // dropped (each dropped line becomes an empty one, so line numbers stay true).
    void expand(const std::vector<std::string>& lines, std::size_t first, int id) {
        CppBlocks cpp(names_[id]);
        for (std::size_t i = first; i < lines.size(); ++i) {
            if (!cpp.keep(lines[i], i + 1)) {
                out_ += "\n";
                continue;
            }
            const std::string word = directive(lines[i]);
            if (word == "include") {
                include(lines[i], names_[id] + ":" + std::to_string(i + 1));
                out_ += "#line " + std::to_string(i + 2) + " " + std::to_string(id) + "\n";
            } else if (word == "version" && id != 0) {
                throw Error(names_[id] + ":" + std::to_string(i + 1) +
                            ": #version in an included file (only the main source has one)");
            } else {
                // #pragma once is for C++ includers of shared headers; including once is the default here.
                out_ += (isPragmaOnce(lines[i]) ? std::string() : lines[i]) + "\n";
            }
        }
        cpp.finish(lines.size());
    }

    // `where` is "file:line" of the #include, for messages.
    void include(const std::string& line, const std::string& where) {
        static const std::regex re(R"re(^\s*#\s*include\s*"([^"]+)"\s*(//.*)?$)re");
        std::smatch m;
        if (!std::regex_match(line, m, re)) throw Error(where + ": malformed #include (expected #include \"file\")");
        const std::string name = m[1].str();
        const fs::path path = (includeDir_ / name).lexically_normal();
        checkCycle(path, name, where);
        if (done_.count(path)) return;  // once per program: headers need no guards
        std::error_code ec;
        if (!fs::is_regular_file(path, ec))
            throw Error(where + ": cannot find #include \"" + name + "\" in " + includeDir_.string());
        const int id = static_cast<int>(names_.size());
        names_.push_back(path.string());
        out_ += "#line 1 " + std::to_string(id) + "\n";
        stack_.push_back(path);
        expand(splitLines(readFile(path)), 0, id);
        stack_.pop_back();
        done_.insert(path);
    }

    void checkCycle(const fs::path& path, const std::string& name, const std::string& where) const {
        const auto it = std::find(stack_.begin(), stack_.end(), path);
        if (it == stack_.end()) return;
        std::string chain;
        for (auto j = it; j != stack_.end(); ++j) chain += j->filename().string() + " -> ";
        throw Error(where + ": #include \"" + name + "\" is an include cycle: " + chain + path.filename().string());
    }

    fs::path includeDir_;
    std::string out_;
    std::vector<std::string> names_;  // source-string id -> name
    std::vector<fs::path> stack_;     // files being expanded, outermost first: a repeat is a cycle
    std::set<fs::path> done_;         // files already expanded
};

std::string infoLog(GLuint object, bool isProgram) {
    GLint length = 0;
    isProgram ? glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length) : glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    isProgram ? glGetProgramInfoLog(object, length, nullptr, log.data())
              : glGetShaderInfoLog(object, length, nullptr, log.data());
    log.resize(std::strlen(log.c_str()));
    return log;
}

// Lists the source-string ids, for logs whose format mapLog does not know.
std::string sourceTable(const std::vector<std::string>& names) {
    if (names.size() < 2) return {};
    std::string table = "\n(source strings:";
    for (std::size_t id = 0; id < names.size(); ++id) {
        // Appended piece by piece: gcc 12 flags `" " + std::to_string(id)` with a false -Wrestrict.
        table += ' ';
        table += std::to_string(id);
        table += " = ";
        table += names[id];
        table += ',';
    }
    table.back() = ')';
    return table;
}

// -1: not decided yet (read $CUBEAO_SHADER_WARNINGS at the first use), 0: log, 1: throw.
std::atomic<int> warningsFatal{-1};

// A non-empty info log from a successful compile or link: what `what` (e.g. "compiling x.comp") said.
void warning(const std::string& what, const std::string& log) {
    if (shaderWarningsFatal())
        throw Error(what + ": warnings are errors here (CUBEAO_SHADER_WARNINGS=error or setShaderWarningsFatal):\n" + log);
    spdlog::warn("{}:\n{}", what, log);
}

Shader compileStage(const ShaderStage& stage, const ShaderDefines& defines, const fs::path& includeDir) {
    const PreprocessedShader pre = preprocessShaderSource(stage.source, includeDir, defines, stage.name);
    Shader shader = Shader::create(stage.stage);
    if (!shader) {
        char hex[16];
        std::snprintf(hex, sizeof hex, "0x%04x", stage.stage);
        throw Error(stage.name + ": glCreateShader failed (stage " + hex + " unknown)");
    }
    // Mesa skips compiling a source its shader cache has seen before, and then has no log to give:
    // a warning shows once per cache, and never again (issue 11: the demo's "`q' used uninitialized"
    // came and went with the cache). When warnings matter, a comment that differs on every compile
    // makes the front end run each time; the back end's cache is keyed on the compiled IR, so it
    // still hits (measured on llvmpipe, a one-probe `bake --device gpu` with warm caches: 1.15 s with
    // the comment, 1.23 s without; with no cache at all, 8 s).
    std::string source = pre.text;
    if (shaderWarningsFatal()) {
        static std::atomic<std::uint64_t> compiles{0};
        source += "\n// compile " + std::to_string(::getpid()) + "." + std::to_string(compiles++) + "." +
                  std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()) + "\n";
    }
    const char* text = source.c_str();
    glShaderSource(shader.id(), 1, &text, nullptr);
    glCompileShader(shader.id());
    glObjectLabel(GL_SHADER, shader.id(), -1, stage.name.c_str());  // names it in debuggers and GL messages
    GLint ok = GL_FALSE;
    glGetShaderiv(shader.id(), GL_COMPILE_STATUS, &ok);
    std::string log = pre.mapLog(infoLog(shader.id(), false));
    while (!log.empty() && log.back() == '\n') log.pop_back();
    if (!ok) throw Error("compiling " + stage.name + " failed:\n" + log + sourceTable(pre.sourceNames));
    if (!log.empty()) warning("compiling " + stage.name, log + sourceTable(pre.sourceNames));
    return shader;
}

}  // namespace

void setShaderWarningsFatal(bool fatal) { warningsFatal = fatal ? 1 : 0; }

bool shaderWarningsFatal() {
    int state = warningsFatal.load();
    if (state < 0) {
        const char* env = std::getenv("CUBEAO_SHADER_WARNINGS");
        int fromEnv = env != nullptr && std::strcmp(env, "error") == 0 ? 1 : 0;
        // The first caller decides, unless setShaderWarningsFatal got there first.
        state = warningsFatal.compare_exchange_strong(state, fromEnv) ? fromEnv : warningsFatal.load();
    }
    return state == 1;
}

std::string PreprocessedShader::mapLog(const std::string& infoLog) const {
    // The source id is the first number on a line, followed by ':' or '(' and the line number.
    static const std::regex re(R"(^(\s*(?:ERROR:\s*|WARNING:\s*)?)(\d+)([:(]\d+))");
    std::string out;
    for (const std::string& line : splitLines(infoLog)) {
        std::smatch m;
        std::size_t id = 0;
        if (std::regex_search(line, m, re) && (id = std::stoul(m[2].str())) < sourceNames.size())
            out += m[1].str() + sourceNames[id] + m[3].str() + m.suffix().str() + "\n";
        else
            out += line + "\n";
    }
    return out;
}

PreprocessedShader preprocessShaderSource(const std::string& source, const fs::path& includeDir,
                                          const ShaderDefines& defines, const std::string& sourceName) {
    return Preprocessor(includeDir).run(source, defines, sourceName);
}

std::string preprocessShader(const std::string& source, const fs::path& includeDir, const ShaderDefines& defines,
                             const std::string& sourceName) {
    return preprocessShaderSource(source, includeDir, defines, sourceName).text;
}

fs::path shaderDir() {
    if (const char* env = std::getenv("CUBEAO_SHADER_DIR"); env != nullptr && *env != '\0') return env;
    // A library built in the source tree reads that tree's shaders/ while it exists, so edits show
    // without an install; an installed library whose source tree is gone reads the installed copy
    // (CMakeLists.txt, docs/INTEGRATION.md "Shaders").
#ifdef CUBEAO_SHADER_DIR
    std::error_code ec;
    if (fs::is_directory(CUBEAO_SHADER_DIR, ec)) return CUBEAO_SHADER_DIR;
#endif
#if defined(CUBEAO_INSTALLED_SHADER_DIR)
    return CUBEAO_INSTALLED_SHADER_DIR;
#elif defined(CUBEAO_SHADER_DIR)
    return CUBEAO_SHADER_DIR;  // its error names the missing directory
#else
    return "shaders";
#endif
}

ShaderStage loadShaderStage(GLenum stage, const fs::path& file) {
    const fs::path path = file.is_absolute() ? file : shaderDir() / file;
    return {stage, readFile(path), path.string()};
}

Program buildProgram(const std::vector<ShaderStage>& stages, const ShaderDefines& defines, const fs::path& includeDir) {
    const fs::path dir = includeDir.empty() ? shaderDir() / "common" : includeDir;
    std::vector<Shader> shaders;
    std::string names;
    for (const ShaderStage& stage : stages) {
        shaders.push_back(compileStage(stage, defines, dir));
        names += (names.empty() ? "" : " + ") + stage.name;
    }
    Program program = Program::create();
    for (const Shader& shader : shaders) glAttachShader(program.id(), shader.id());
    glLinkProgram(program.id());
    // Detached shaders are freed with their handles now instead of living as long as the program.
    for (const Shader& shader : shaders) glDetachShader(program.id(), shader.id());
    GLint ok = GL_FALSE;
    glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
    if (!ok) {
        std::string log = infoLog(program.id(), true);
        while (!log.empty() && log.back() == '\n') log.pop_back();
        throw Error("linking " + names + " failed:\n" + log);
    }
    std::string log = infoLog(program.id(), true);
    while (!log.empty() && log.back() == '\n') log.pop_back();
    if (!log.empty()) warning("linking " + names, log);
    glObjectLabel(GL_PROGRAM, program.id(), -1, names.c_str());
    return program;
}

Program compileComputeProgram(const fs::path& computeFile, const ShaderDefines& defines) {
    return buildProgram({loadShaderStage(GL_COMPUTE_SHADER, computeFile)}, defines);
}

Program compileRenderProgram(const fs::path& vertexFile, const fs::path& fragmentFile, const ShaderDefines& defines) {
    return buildProgram({loadShaderStage(GL_VERTEX_SHADER, vertexFile), loadShaderStage(GL_FRAGMENT_SHADER, fragmentFile)},
                        defines);
}

}  // namespace cubeao::gl

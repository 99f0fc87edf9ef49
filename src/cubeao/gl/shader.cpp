#include "cubeao/gl/shader.h"

#include "cubeao/core/error.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

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
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error("cannot read shader file " + path.string());
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
    // Appends the lines of source `id` from index `first` on, includes expanded.
    void expand(const std::vector<std::string>& lines, std::size_t first, int id) {
        for (std::size_t i = first; i < lines.size(); ++i) {
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
    for (std::size_t id = 0; id < names.size(); ++id) table += " " + std::to_string(id) + " = " + names[id] + ",";
    table.back() = ')';
    return table;
}

Shader compileStage(const ShaderStage& stage, const ShaderDefines& defines, const fs::path& includeDir) {
    const PreprocessedShader pre = preprocessShaderSource(stage.source, includeDir, defines, stage.name);
    Shader shader = Shader::create(stage.stage);
    if (!shader) {
        char hex[16];
        std::snprintf(hex, sizeof hex, "0x%04x", stage.stage);
        throw Error(stage.name + ": glCreateShader failed (stage " + hex + " unknown)");
    }
    const char* text = pre.text.c_str();
    glShaderSource(shader.id(), 1, &text, nullptr);
    glCompileShader(shader.id());
    glObjectLabel(GL_SHADER, shader.id(), -1, stage.name.c_str());  // names it in debuggers and GL messages
    GLint ok = GL_FALSE;
    glGetShaderiv(shader.id(), GL_COMPILE_STATUS, &ok);
    std::string log = pre.mapLog(infoLog(shader.id(), false));
    while (!log.empty() && log.back() == '\n') log.pop_back();
    if (!ok) throw Error("compiling " + stage.name + " failed:\n" + log + sourceTable(pre.sourceNames));
    if (!log.empty()) spdlog::warn("compiling {}:\n{}", stage.name, log);  // warnings are usually real bugs
    return shader;
}

}  // namespace

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
#ifdef CUBEAO_SHADER_DIR
    return CUBEAO_SHADER_DIR;
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

// Running the cubeao binary from a test: exit code and stdout, and the JSON object every command
// prints as its last line with --json (DESIGN.md §5).
#pragma once

#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>

#include <nlohmann/json.hpp>

namespace cubeao::test {

struct CliRun {
    int code = -1;
    std::string out;
};

// Runs a shell command line; `out` is what it writes to stdout.
inline CliRun runCommand(const std::string& cmd) {
    CliRun r;
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return r;
    std::array<char, 4096> buf{};
    while (std::size_t n = std::fread(buf.data(), 1, buf.size(), p)) r.out.append(buf.data(), n);
    const int status = pclose(p);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

// Runs the binary; `out` is its stdout, followed by its stderr when withStderr.
inline CliRun runCli(const std::string& args, bool withStderr = false) {
    return runCommand(std::string(CUBEAO_BINARY) + " " + args + (withStderr ? " 2>&1" : " 2>/dev/null"));
}

inline nlohmann::json lastLine(const std::string& out) {
    std::string s = out;
    while (!s.empty() && s.back() == '\n') s.pop_back();
    return nlohmann::json::parse(s.substr(s.rfind('\n') + 1));
}

}  // namespace cubeao::test

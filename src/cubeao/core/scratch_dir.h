// A scratch directory for a process's temporary files: PREFIX-PID under the system's temporary
// directory, created at once and removed with what it holds when the object goes (also when the work
// in it fails). The benchmarks write their throw-away caches there.
#pragma once

#include <filesystem>
#include <string>

namespace cubeao {

struct ScratchDir {
    std::filesystem::path path;
    explicit ScratchDir(const std::string& prefix);
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    ~ScratchDir();
};

}  // namespace cubeao

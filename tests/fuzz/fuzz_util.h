// Shared by the libFuzzer targets (issue 15): a per-process scratch file for parsers that read paths.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include <unistd.h>

namespace cubeao::fuzz {

// `data` written to a file named NAME in a per-process directory (overwritten on every input).
inline std::filesystem::path scratchFile(const std::string& name, const std::uint8_t* data, std::size_t size) {
    static const std::filesystem::path dir = [] {
        auto d = std::filesystem::temp_directory_path() / ("cubeao-fuzz-" + std::to_string(::getpid()));
        std::filesystem::create_directories(d);
        return d;
    }();
    const std::filesystem::path path = dir / name;
    FILE* f = std::fopen(path.c_str(), "wb");
    if (f) {
        if (size) std::fwrite(data, 1, size, f);
        std::fclose(f);
    }
    return path;
}

}  // namespace cubeao::fuzz

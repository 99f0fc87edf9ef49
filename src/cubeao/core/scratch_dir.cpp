#include "cubeao/core/scratch_dir.h"

#include <system_error>

#include <unistd.h>

namespace cubeao {

ScratchDir::ScratchDir(const std::string& prefix)
    : path(std::filesystem::temp_directory_path() / (prefix + "-" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path);
}

ScratchDir::~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
}

}  // namespace cubeao

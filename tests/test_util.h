// Helpers shared by the test files: one copy here instead of a private copy in each test_*.cpp.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <ostream>
#include <random>
#include <string>
#include <system_error>

#include <glm/vec3.hpp>

#include "cubeao/core/error.h"

namespace glm {
// Readable failure messages for EXPECT_EQ on vectors. It must live in namespace glm so that
// GoogleTest finds it by argument-dependent lookup.
inline void PrintTo(const vec3& v, std::ostream* os) { *os << "(" << v.x << ", " << v.y << ", " << v.z << ")"; }
}  // namespace glm

namespace cubeao::test {

// Sets an environment variable for one scope and restores the previous value.
class ScopedEnv {
public:
    ScopedEnv(const char* name, const std::string& value) : name_(name) {
        if (const char* old = std::getenv(name)) old_ = old;
        ::setenv(name, value.c_str(), 1);
    }
    ~ScopedEnv() { old_ ? ::setenv(name_, old_->c_str(), 1) : ::unsetenv(name_); }
    ScopedEnv(const ScopedEnv&) = delete;
    ScopedEnv& operator=(const ScopedEnv&) = delete;

private:
    const char* name_;
    std::optional<std::string> old_;
};

// The message of the cubeao::Error `f` throws, or "" and a test failure when it throws nothing, so
// an assertion on the message can never pass by accident. Other exceptions propagate (and fail
// the test).
template <class F>
std::string errorMessage(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected cubeao::Error, nothing was thrown";
    return "";
}

// Whether this build runs under AddressSanitizer (CUBEAO_SANITIZE): GCC and clang define
// __SANITIZE_ADDRESS__ with -fsanitize=address. Address-space limits cannot apply under it.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kAddressSanitizer = true;
#else
inline constexpr bool kAddressSanitizer = false;
#endif

inline bool contains(const std::string& haystack, const std::string& needle) {
    return haystack.find(needle) != std::string::npos;
}

// A fresh directory temp_directory_path()/cubeao-test[-TAG]-<pid>-<n>-<random>, removed with
// everything in it at scope exit. The pid, a process-wide counter and a random number keep
// concurrent test processes and several directories in one test apart; the tag only helps a
// human tell them apart. Non-copyable: a copy would delete the directory twice.
class TempDir {
public:
    explicit TempDir(const std::string& tag = "") {
        static std::atomic<unsigned> counter{0};
        std::random_device rd;
        const std::string prefix = tag.empty() ? "cubeao-test-" : "cubeao-test-" + tag + "-";
        do {
            path_ = std::filesystem::temp_directory_path() /
                    (prefix + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "-" +
                     std::to_string(rd()));
        } while (!std::filesystem::create_directories(path_));  // false: it already existed
    }
    ~TempDir() {
        std::error_code ignored;  // never throw from a destructor
        std::filesystem::remove_all(path_, ignored);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    const std::filesystem::path& path() const { return path_; }
    // Shorthand for path() / name.
    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

    // Writes `text` to the file `name` (which may contain subdirectories, created as needed) and
    // returns its path as a string.
    std::string write(const std::string& name, const std::string& text) const {
        const std::filesystem::path p = path_ / name;
        std::filesystem::create_directories(p.parent_path());
        std::ofstream out(p, std::ios::binary);
        out << text;
        return p.string();
    }
    // The path of `name` in the directory, normalised the way the shader preprocessor reports
    // include files.
    std::string file(const std::string& name) const { return (path_ / name).lexically_normal().string(); }

private:
    std::filesystem::path path_;
};

}  // namespace cubeao::test

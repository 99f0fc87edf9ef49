// Error types shared by every stage. Messages name the file or item and what was expected
// (STYLE.md "Errors"); the CLI maps Error to exit code 1 and UsageError to exit code 2.
#pragma once

#include <stdexcept>
#include <string>

namespace cubeao {

// A failure the user can act on: bad input file, missing scene, mismatched images.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The command line itself is wrong (unknown value, malformed --frames); exit code 2.
class UsageError : public Error {
public:
    using Error::Error;
};

}  // namespace cubeao

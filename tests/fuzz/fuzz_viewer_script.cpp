// The viewer's script language (tools/cubeao-view/script.h): cubeao::UsageError or commands, never a
// crash.
#include <string>

#include "cubeao-view/script.h"
#include "cubeao/core/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        (void)cubeao::viewer::parseScript(std::string(reinterpret_cast<const char*>(data), size), "fuzz");
    } catch (const cubeao::Error&) {
    }
    return 0;
}

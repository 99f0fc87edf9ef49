// The boundary between cubeao_metrics and OpenImageIO. OIIO is not linked into cubeao's programs:
// it brings some 260 shared libraries (OpenCV, DCMTK, GDCM, libheif, ...), whose loading and
// relocation cost every process 0.4 s before main() (`cubeao --help`: 0.43 s, now 0.03 s). Tests
// start the CLI hundreds of times: the plain suite took 9 min 40 s with OIIO linked, 3 min 52 s
// without (2 cores).
// Instead OIIO lives in a plugin, libcubeao_oiio.so (oiio_module.cpp), that image_io.cpp loads with
// dlopen the first time a program reads, writes or compares an image.
//
// The plugin is built with the same compiler and standard library as the programs (it is part of
// this build, installed beside the static libraries), so the table passes C++ types. Each entry
// returns "" on success, else the reason in OpenImageIO's words.
// Private to cubeao_metrics: not installed (cmake/Install.cmake).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace cubeao::oiio {

inline constexpr int kApiVersion = 1;

enum class Pixel { U8, F32 };

struct WriteSpec {
    int width = 0, height = 0, channels = 0;
    Pixel type = Pixel::U8;
    bool exrLuminance = false;  // one channel named "Y", ZIP compression (image_io.h)
};

struct Api {
    int version = kApiVersion;
    // Writes `pixels` (interleaved, `spec.type`) to `file` with the writer that `formatFrom`'s
    // extension names (the file itself is a temporary name).
    std::string (*write)(const char* formatFrom, const char* file, const WriteSpec& spec, const void* pixels);
    // The first channel of the first subimage, as float.
    std::string (*readFirstChannel)(const char* file, int* width, int* height, std::vector<float>* pixels);
    // An 8-bit PNG in memory.
    std::string (*encodePng)(int width, int height, int channels, const std::uint8_t* bytes,
                             std::vector<unsigned char>* png);
    // Mean absolute and root-mean-square difference of two single-channel float images
    // (ImageBufAlgo::compare).
    std::string (*compare)(const float* a, const float* b, int width, int height, double* mean, double* rms);
};

// The plugin's table, loaded on first use (image_io.cpp): $CUBEAO_OIIO_MODULE when set, else this
// build's libcubeao_oiio.so while it exists, else the installed one. Throws cubeao::Error naming
// every path it tried when none loads.
const Api& api();

}  // namespace cubeao::oiio

// The plugin's one exported symbol.
extern "C" const cubeao::oiio::Api* cubeao_oiio_api();

// libcubeao_oiio.so: the OpenImageIO calls of cubeao_metrics, loaded at run time (oiio_module.h
// says why). Nothing here throws across the boundary: every failure comes back as text.
#include "cubeao/metrics/oiio_module.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <exception>

namespace {

using cubeao::oiio::Pixel;
using cubeao::oiio::WriteSpec;

OIIO::TypeDesc typeOf(Pixel p) { return p == Pixel::F32 ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8; }

// OIIO's own error text, never empty (an empty string means success to the caller).
std::string failure(std::string why) { return why.empty() ? std::string("OpenImageIO gave no reason") : why; }

std::string write(const char* formatFrom, const char* file, const WriteSpec& s, const void* pixels) try {
    auto out = OIIO::ImageOutput::create(formatFrom);
    if (!out)
        return failure(OIIO::geterror());
    OIIO::ImageSpec spec(s.width, s.height, s.channels, typeOf(s.type));
    if (s.exrLuminance) {
        spec.channelnames = {"Y"};
        spec.attribute("compression", "zip");
    }
    if (out->open(file, spec) && out->write_image(typeOf(s.type), pixels) && out->close())
        return {};
    return failure(out->geterror());
} catch (const std::exception& e) {
    return failure(e.what());
}

std::string readFirstChannel(const char* file, int* width, int* height, std::vector<float>* pixels) try {
    auto in = OIIO::ImageInput::open(file);
    if (!in)
        return failure(OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.deep || spec.width <= 0 || spec.height <= 0 || spec.nchannels < 1 || spec.depth > 1)
        return "not a flat 2D image with at least one channel";
    *width = spec.width, *height = spec.height;
    pixels->assign(std::size_t(spec.width) * std::size_t(spec.height), 0.0f);
    // Channel 0 only: an RGB(A) file written by another tool still yields its first channel.
    if (!in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, pixels->data()))
        return failure(in->geterror());
    return {};
} catch (const std::exception& e) {
    return failure(e.what());
}

std::string encodePng(int width, int height, int channels, const std::uint8_t* bytes,
                      std::vector<unsigned char>* png) try {
    OIIO::Filesystem::IOVecOutput proxy(*png);
    auto out = OIIO::ImageOutput::create("png");
    if (!out)
        return failure(OIIO::geterror());
    out->set_ioproxy(&proxy);
    if (out->open("memory.png", OIIO::ImageSpec(width, height, channels, OIIO::TypeDesc::UINT8)) &&
        out->write_image(OIIO::TypeDesc::UINT8, bytes) && out->close())
        return {};
    return failure(out->geterror());
} catch (const std::exception& e) {
    return failure(e.what());
}

std::string compare(const float* a, const float* b, int width, int height, double* mean, double* rms) try {
    // Wrapped without copying (read-only use).
    const OIIO::ImageSpec spec(width, height, 1, OIIO::TypeDesc::FLOAT);
    const OIIO::ImageBuf bufA(spec, const_cast<float*>(a)), bufB(spec, const_cast<float*>(b));
    // Thresholds only count warnings/failures, which we do not use.
    const auto r = OIIO::ImageBufAlgo::compare(bufA, bufB, 1.0f, 1.0f);
    if (r.error)
        return failure(OIIO::geterror());
    *mean = r.meanerror, *rms = r.rms_error;
    return {};
} catch (const std::exception& e) {
    return failure(e.what());
}

const cubeao::oiio::Api kApi{cubeao::oiio::kApiVersion, write, readFirstChannel, encodePng, compare};

}  // namespace

extern "C" __attribute__((visibility("default"))) const cubeao::oiio::Api* cubeao_oiio_api() { return &kApi; }

// Image and sequence metrics for `cubeao compare` (DESIGN.md §5, §6): how far an AO image
// sequence (probes, screen-space baselines) is from another (usually the Embree reference).
//
// All figures treat AO as a signal with peak 1 (1 = open, 0 = occluded) and are computed in double.
//  - MAE, RMSE: mean absolute / root-mean-square difference per pixel (OIIO ImageBufAlgo::compare).
//  - PSNR = 20 log10(1 / RMSE) dB. Identical images have RMSE 0 and PSNR = +infinity: the C++
//    value is std::numeric_limits<double>::infinity() (no made-up cap that could pollute averages),
//    and toJson() writes it as JSON null, since JSON has no infinity.
//  - SSIM: Wang, Bovik, Sheikh, Simoncelli 2004, "Image quality assessment: from error visibility
//    to structural similarity", eq. 13 with their settings: 11x11 Gaussian window (sigma 1.5,
//    normalised), K1 = 0.01, K2 = 0.03, L = 1; mean over all windows that lie fully inside the image
//    (MATLAB filter2 'valid'), no downsampling. Needs images of at least 11x11 pixels.
//  - Flicker: mean over pixels and consecutive frame pairs of |(a_t - a_{t-1}) - (b_t - b_{t-1})|:
//    the frame-to-frame change of A that B does not have (or vice versa). A constant per-pixel
//    offset between A and B does not flicker, so this separates temporal instability from bias
//    (which MAE already measures). A single frame has no pair: flicker 0.
// Size mismatches throw cubeao::Error with both sizes (and both files where files are known).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cubeao/core/image.h"

namespace cubeao {

struct ImageDiff {
    double mae = 0.0;
    double rmse = 0.0;
    double psnr = 0.0;  // dB, +infinity for identical images
};

double psnrFromRmse(double rmse);  // 20 log10(1 / rmse); +infinity for rmse == 0

ImageDiff imageDiff(const Image& a, const Image& b);
double ssim(const Image& a, const Image& b);

// Flicker of one consecutive pair of frames, and of whole sequences (equal lengths and sizes).
double flickerPair(const Image& aPrev, const Image& a, const Image& bPrev, const Image& b);
double temporalFlicker(const std::vector<Image>& a, const std::vector<Image>& b);

struct FrameMetrics {
    std::string name;  // file name, e.g. "ao_0005.exr"
    int frame = 0;     // camera path frame index from the name
    double mae = 0.0, rmse = 0.0, psnr = 0.0, ssim = 0.0;
};

struct SequenceMetrics {
    std::vector<FrameMetrics> frames;  // sorted by frame index
    double mae = 0.0;      // over all pixels of all frames
    double rmse = 0.0;     // over all pixels of all frames
    double psnr = 0.0;     // from the overall rmse
    double ssim = 0.0;     // mean of the per-frame values
    double flicker = 0.0;  // over consecutive files in frame order (gaps in the indices are not skipped)
};

// Compares the frames `ao_NNNN.exr` of two directories, paired by file name; other files (PNG
// previews) are ignored. Throws cubeao::Error when a directory is missing or has no frames, when
// the two sets of frame names differ (listing what is missing on which side), when a file cannot
// be read or holds a non-finite value, or when paired or consecutive frames differ in size.
SequenceMetrics compareDirs(const std::filesystem::path& dirA, const std::filesystem::path& dirB);

// Field names are a contract (DESIGN.md §5): mae, rmse, psnr, ssim, flicker, frames (array of
// {name, frame, mae, rmse, psnr, ssim}). An infinite psnr is written as null.
nlohmann::json toJson(const FrameMetrics& frame);
nlohmann::json toJson(const SequenceMetrics& metrics);

}  // namespace cubeao

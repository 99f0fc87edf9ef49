// A baked probe as images, from its uncompressed data: for people looking at a bake (`bake --dump`)
// and for tools that want float faces (the cache, docs/FORMAT.md, stores them compressed). Float data
// goes to single-channel EXR (lossless: a write/read round trip is bit exact), previews to PNG
// (image_io.h conventions).
//
// Stacked images, writeProbeImages: `probe_NNNN_ao.exr`, `probe_NNNN_confidence.exr`,
// `probe_NNNN_distance.exr` (NNNN = probe index, 4+ digits), res wide and 6·res tall. Face f (cube.h
// order +X, −X, +Y, −Y, +Z, −Z) fills image rows [f·res, (f+1)·res), face 0 at the top. Inside a
// face, image pixel (x, y) (row y = 0 at the top) is texel (i, j) = (x, res − 1 − y): the face as its
// framebuffer looks on screen (texel row j = 0 is the framebuffer's bottom row, cube.h). Mind that
// the GL cube-map table points j (tc) *down* in the world on the four side faces, so in these images
// world-up lies at the bottom of ±X and ±Z; the cross PNG of dumpProbe shows the world upright.
// Distance is 0 where the probe sees nothing (AO and confidence are 1 there).
//
// Dump, dumpProbe: the same three quantities per face, `probe_NNNN_face{K}_{ao,confidence,distance}.exr`
// (res × res, the same orientation as a face of the stacked images), and two horizontal-cross PNGs,
// 4·res × 3·res, of the AO (`probe_NNNN_cross.png`, grey) and of the distance
// (`probe_NNNN_cross_distance.png`, grey = distance / largest distance of the probe); both tint texels
// that see nothing dark blue and fill the six cells outside the cross with dark magenta.
//
// Cross layout (cell = res × res pixels; column, row of cells from the top-left):
//          [+Y]
//     [−X] [+Z] [+X] [−Z]
//          [−Y]
// Every face is shown as seen from inside the cube in GL's (left-handed, RenderMan) cube-map frame,
// which is the right-handed world mirrored left–right (facing +Z, +X appears on the right); with
// this cell order no other orientation keeps the shared edges continuous. In the middle row world-up
// is at the top and the row runs continuously around the vertical axis; +Y's
// bottom edge meets +Z's top edge and −Y's top edge meets +Z's bottom edge, so the cross folds into a
// cube whose shared edges match (tests/bake/test_bake_cpu.cpp checks continuity across every cell border).
// In cube.h terms each face shows texel (i, j) at cell pixel (i, j): texel row 0 at the cell's top.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "cubeao/bake/bake.h"

namespace cubeao {

// "probe_0007"-style prefix of every file of probe `probeIndex`.
std::string probeFileStem(std::uint32_t probeIndex);

// Writes the three stacked EXRs into `dir` (which must exist). Error naming the file on failure.
void writeProbeImages(const std::filesystem::path& dir, std::uint32_t probeIndex, const BakedProbe& probe);

// What writeProbeImages stored, back in cube::texelIndex order.
struct ProbeImages {
    int res = 0;
    std::vector<float> ao, confidence, distance;
};
// Reads the three stacked EXRs of `probeIndex` from `dir`. Error naming the file when one is missing,
// is not res × 6·res, or disagrees with the others in size.
ProbeImages readProbeImages(const std::filesystem::path& dir, std::uint32_t probeIndex);

// Writes the per-face EXRs and the two cross PNGs into `dir` (which must exist).
void dumpProbe(const std::filesystem::path& dir, std::uint32_t probeIndex, const BakedProbe& probe);

// The texel (cube::texelIndex) shown at pixel (x, y) of a 4·res × 3·res cross; −1 outside the cross.
std::ptrdiff_t crossTexelIndex(int x, int y, int res);

}  // namespace cubeao

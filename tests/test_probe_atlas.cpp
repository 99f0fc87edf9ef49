// Where the projection puts each probe in its textures (probeAtlasLayout, runtime/probe_projection.h).
#include <gtest/gtest.h>

#include "cubeao/core/error.h"
#include "cubeao/runtime/probe_projection.h"
#include "test_util.h"

namespace {

using cubeao::ProbeAtlasLayout;
using cubeao::probeAtlasLayout;

void expectLayout(const ProbeAtlasLayout& l, int tilesX, int tilesY, int pages) {
    EXPECT_EQ(l.tilesX, tilesX);
    EXPECT_EQ(l.tilesY, tilesY);
    EXPECT_EQ(l.pages, pages);
}

TEST(ProbeAtlas, NearSquarePagesJustBigEnough) {
    expectLayout(probeAtlasLayout(1, 512, 16384, 2048), 1, 1, 1);
    expectLayout(probeAtlasLayout(3, 16, 16384, 2048), 2, 2, 1);
    expectLayout(probeAtlasLayout(10, 512, 16384, 2048), 4, 3, 1);
    expectLayout(probeAtlasLayout(10000, 16, 16384, 2048), 100, 100, 1);  // bench render's sweep: one page
}

TEST(ProbeAtlas, MorePagesWhenAPageIsFull) {
    // 16384 / 512 = 32 tiles a side: 1,024 probes a page.
    expectLayout(probeAtlasLayout(10000, 512, 16384, 2048), 32, 32, 10);
    expectLayout(probeAtlasLayout(1025, 512, 16384, 2048), 32, 32, 2);
    // Every probe has a tile, and no page is empty.
    for (const std::size_t n : {1u, 2u, 5u, 17u, 341u, 342u, 4097u}) {
        const ProbeAtlasLayout l = probeAtlasLayout(n, 64, 1024, 2048);
        const std::size_t perPage = std::size_t(l.tilesPerPage());
        EXPECT_GE(perPage * std::size_t(l.pages), n) << n;
        EXPECT_LT(perPage * std::size_t(l.pages - 1), n) << n;
        EXPECT_LE(l.tilesX * 64, 1024);
        EXPECT_LE(l.tilesY * 64, 1024);
    }
}

TEST(ProbeAtlas, TooManyProbesForTheLayersIsAnError) {
    const std::string m = cubeao::test::errorMessage([] { probeAtlasLayout(5000, 512, 2048, 12); });
    EXPECT_NE(m.find("5000 probes"), std::string::npos) << m;
    EXPECT_NE(m.find("12 layers"), std::string::npos) << m;
}

}  // namespace

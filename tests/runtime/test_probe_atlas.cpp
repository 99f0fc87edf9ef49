// Where the projection puts each probe in its textures (probeAtlasLayout, runtime/residency_planner.h).
#include <gtest/gtest.h>

#include <set>
#include <tuple>

#include "common/runtime_layout.h"
#include "cubeao/core/error.h"
#include "cubeao/runtime/residency_planner.h"
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

// The packed tile the projection reads (ProbeEntry::tile): slot i's tile in row-major order within its
// page, pages after one another, every slot in its own tile inside the textures.
TEST(ProbeAtlas, EverySlotsPackedTileIsItsOwnTileInRowMajorOrder) {
    for (const auto& [n, res, maxSize] : {std::tuple(10u, 512, 16384), std::tuple(10000u, 512, 16384),
                                          std::tuple(4097u, 64, 1024), std::tuple(10000u, 16, 16384)}) {
        const ProbeAtlasLayout l = probeAtlasLayout(n, res, maxSize, 2048);
        std::set<std::tuple<int, int, int>> seen;
        for (std::uint32_t slot = 0; slot < n; ++slot) {
            const std::uint32_t tile = l.tile(cubeao::SlotId{slot});
            ASSERT_NE(tile, cubeao::kernel::kNoSlot);
            const glm::ivec3 c = cubeao::kernel::atlasTileCorner(tile, res);
            const int inPage = int(slot) % l.tilesPerPage();
            EXPECT_EQ(c, glm::ivec3(inPage % l.tilesX * res, inPage / l.tilesX * res, 6 * (int(slot) / l.tilesPerPage())))
                << n << " probes, slot " << slot;
            EXPECT_LE(c.x + res, l.tilesX * res);
            EXPECT_LE(c.y + res, l.tilesY * res);
            EXPECT_LT(c.z / 6, l.pages);
            seen.insert({c.x, c.y, c.z});
        }
        EXPECT_EQ(seen.size(), n);
    }
    // The largest tile the packing holds: column and row 2047, page 1023.
    EXPECT_EQ(cubeao::kernel::atlasTileCorner(cubeao::kernel::packAtlasTile(2047, 2047, 1022), 4),
              glm::ivec3(2047 * 4, 2047 * 4, 6 * 1022));
    // At 4² a side of 16384 would hold 4096 tiles: the layout keeps to what the packing holds.
    EXPECT_LT(probeAtlasLayout(10000000, 4, 16384, 2048).tilesX, cubeao::kernel::kMaxAtlasTiles);
}

TEST(ProbeAtlas, TooManyProbesForTheLayersIsAnError) {
    const std::string m = cubeao::test::errorMessage([] { probeAtlasLayout(5000, 512, 2048, 12); });
    EXPECT_NE(m.find("5000 probes"), std::string::npos) << m;
    EXPECT_NE(m.find("12 layers"), std::string::npos) << m;
}

}  // namespace

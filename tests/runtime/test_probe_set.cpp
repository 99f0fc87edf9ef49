// The one record of which probes a run holds (runtime/probe_set.h).
#include <gtest/gtest.h>

#include <vector>

#include "cubeao/core/error.h"
#include "cubeao/runtime/probe_set.h"
#include "probe_id_print.h"

namespace {

using namespace cubeao;

TEST(ProbeSet, IdsInOrderOfArrivalAndARemovedIdIsNeverLiveOrReused) {
    const std::vector<glm::vec3> start = {{1, 0, 0}, {2, 0, 0}};
    ProbeSet set(start);
    EXPECT_EQ(set.size(), 2u);
    EXPECT_EQ(set.liveCount(), 2u);
    EXPECT_EQ(set.add({3, 0, 0}), ProbeId{2});
    EXPECT_EQ(set.position(ProbeId{2}), glm::vec3(3, 0, 0));
    set.remove(ProbeId{0});
    EXPECT_FALSE(set.isLive(ProbeId{0}));
    EXPECT_TRUE(set.isLive(ProbeId{1}));
    EXPECT_EQ(set.liveCount(), 2u);
    EXPECT_EQ(set.size(), 3u) << "a removed probe keeps its id";
    EXPECT_EQ(set.position(ProbeId{0}), glm::vec3(1, 0, 0));
    EXPECT_EQ(set.add({4, 0, 0}), ProbeId{3}) << "ids are not reused";
    EXPECT_THROW(set.remove(ProbeId{0}), Error) << "already removed";
    EXPECT_THROW(set.remove(ProbeId{9}), Error) << "never issued";
    EXPECT_FALSE(set.isLive(ProbeId::None));
    EXPECT_EQ(set.liveCount(), 3u);
}

}  // namespace

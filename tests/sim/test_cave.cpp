// Which voxels are the cave: channel voxels, protochannels when there are none, source inlets that
// touch a passage, never sinks.
#include <gtest/gtest.h>

#include "sim/cave.h"

namespace cavesim {
namespace {

Domain block() { return emptyDomain(Dims{9, 5, 5}, 1.0, 0.05f); }

void addSource(Domain& d, std::vector<std::size_t> voxels) {
    for (std::size_t v : voxels) d.flags[v] |= kSource;
    d.sourceVoxels.push_back(std::move(voxels));
    d.sourcePressure.push_back(1.0);
}

void addSink(Domain& d, std::vector<std::size_t> voxels) {
    for (std::size_t v : voxels) d.flags[v] |= kSink;
    d.sinkVoxels.push_back(std::move(voxels));
}

long count(const Grid3<std::uint8_t>& m) {
    long n = 0;
    for (std::uint8_t v : m.data) n += v;
    return n;
}

TEST(CaveMask, SourceInsideAPassageIsCaveSoNoSpeckOfRockRemains) {
    Domain d = block();
    for (int i = 0; i < 9; ++i) d.flags.at(i, 2, 2) |= kChannel;
    const std::size_t src = d.dims.index(4, 2, 2);
    d.flags[src] &= ~std::uint32_t(kChannel);  // sources are never eroded
    addSource(d, {src});
    const auto m = caveMask(d, CaveExtent::kChannels);
    EXPECT_EQ(m[src], 1);
    EXPECT_EQ(count(m), 9);
}

TEST(CaveMask, OnlySourceVoxelsTouchingAPassageAreInlets) {
    Domain d = block();
    for (int i = 3; i < 9; ++i) d.flags.at(i, 2, 2) |= kChannel;
    // A source row along x at the left end: (0..2, 2, 2); only (2, 2, 2) touches the passage.
    addSource(d, {d.dims.index(0, 2, 2), d.dims.index(1, 2, 2), d.dims.index(2, 2, 2)});
    // A second source far from any passage (diagonal contact counts, this one has none).
    addSource(d, {d.dims.index(0, 0, 4)});
    const auto m = caveMask(d, CaveExtent::kChannels);
    EXPECT_EQ(m.at(2, 2, 2), 1);
    EXPECT_EQ(m.at(1, 2, 2), 0) << "a source box does not grow through itself";
    EXPECT_EQ(m.at(0, 2, 2), 0);
    EXPECT_EQ(m.at(0, 0, 4), 0);
    EXPECT_EQ(count(m), 6 + 1);
}

TEST(CaveMask, DiagonalContactMakesAnInlet) {
    Domain d = block();
    d.flags.at(5, 3, 3) |= kChannel;
    addSource(d, {d.dims.index(4, 2, 2)});  // corner neighbour of the channel voxel
    EXPECT_EQ(caveMask(d, CaveExtent::kChannels).at(4, 2, 2), 1);
}

TEST(CaveMask, SinksAreNeverCave) {
    Domain d = block();
    for (int i = 0; i < 9; ++i) d.flags.at(i, 2, 2) |= kChannel;
    addSink(d, {d.dims.index(8, 2, 2)});
    const auto m = caveMask(d, CaveExtent::kChannels);
    EXPECT_EQ(m.at(8, 2, 2), 0);
    EXPECT_EQ(count(m), 8);
}

TEST(CaveMask, ProtochannelsStandInWhenThereIsNoChannel) {
    Domain d = block();
    for (int k = 1; k < 5; ++k) d.flags.at(4, 2, k) |= kProtochannel;
    addSource(d, {d.dims.index(4, 2, 0)});
    auto m = caveMask(d, CaveExtent::kChannels);
    EXPECT_EQ(count(m), 4 + 1);  // the protochannel and its source
    // Once one voxel is channel, the protochannels are no longer the cave.
    d.flags.at(0, 0, 0) |= kChannel;
    m = caveMask(d, CaveExtent::kChannels);
    EXPECT_EQ(count(m), 1);
    EXPECT_EQ(m.at(0, 0, 0), 1);
}

TEST(CaveMask, WithProtochannelsTheStage1TreesAreSidePassages) {
    Domain d = block();
    for (int i = 0; i < 9; ++i) d.flags.at(i, 2, 2) |= kChannel;
    for (int k = 3; k < 5; ++k) d.flags.at(4, 2, k) |= kProtochannel;  // a branch off the passage
    d.flags.at(0, 0, 0) |= kProtochannel;                              // an isolated tip
    addSink(d, {d.dims.index(8, 0, 0)});
    d.flags.at(8, 0, 0) |= kProtochannel;                              // a protochannel sink voxel
    EXPECT_EQ(count(caveMask(d, CaveExtent::kChannels)), 9);
    const auto m = caveMask(d, CaveExtent::kWithProtochannels);
    EXPECT_EQ(count(m), 9 + 2 + 1);
    EXPECT_EQ(m.at(4, 2, 4), 1);
    EXPECT_EQ(m.at(8, 0, 0), 0);
}

}  // namespace
}  // namespace cavesim

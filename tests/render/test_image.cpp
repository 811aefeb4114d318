// Image primitives: reduction by an integer factor (used for the frames of images/sequence.png).
#include <gtest/gtest.h>

#include "core/error.h"
#include "render/image.h"

namespace cavesim::render {
namespace {

TEST(Downsample, AveragesBlocksAndKeepsPartialEdgeBlocks) {
    Image src(5, 3, {0, 0, 0});
    // Left 2x2 block: two white, two black pixels -> mid grey; the rest stays black.
    src.set(0, 0, {255, 255, 255});
    src.set(1, 1, {255, 255, 255});
    // A red pixel alone in the partial block at the right edge (column 4, rows 0-1).
    src.set(4, 0, {200, 0, 0});
    const Image out = downsample(src, 2);
    ASSERT_EQ(out.width, 3);
    ASSERT_EQ(out.height, 2);
    EXPECT_EQ(out.get(0, 0).r, 128);
    EXPECT_EQ(out.get(1, 0).r, 0);
    EXPECT_EQ(out.get(2, 0).r, 100);  // (200 + 0) / 2: the partial block averages what it covers
    EXPECT_EQ(out.get(2, 0).g, 0);
    EXPECT_EQ(out.get(0, 1).r, 0);
}

TEST(Downsample, FactorOneCopiesAndBadFactorThrows) {
    Image src(3, 2, {10, 20, 30});
    const Image same = downsample(src, 1);
    EXPECT_EQ(same.pixels, src.pixels);
    EXPECT_THROW(downsample(src, 0), InternalError);
    const Image big = downsample(src, 10);
    ASSERT_EQ(big.width, 1);
    EXPECT_EQ(big.get(0, 0).g, 20);
}

}  // namespace
}  // namespace cavesim::render

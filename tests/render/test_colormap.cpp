// The colour maps against matplotlib's reference tables (matplotlib/_cm_listed.py, values × 255).
#include <gtest/gtest.h>

#include <cmath>

#include "render/colormap.h"

namespace cavesim::render {
namespace {

Rgb reference(double r, double g, double b) {
    auto c = [](double v) { return std::uint8_t(std::lround(255.0 * v)); };
    return {c(r), c(g), c(b)};
}

TEST(Colormap, ViridisMatchesMatplotlibEntries) {
    EXPECT_EQ(viridis(0.0), reference(0.267004, 0.004874, 0.329415));
    EXPECT_EQ(viridis(64 / 255.0), reference(0.229739, 0.322361, 0.545706));
    EXPECT_EQ(viridis(128 / 255.0), reference(0.127568, 0.566949, 0.550556));
    EXPECT_EQ(viridis(192 / 255.0), reference(0.369214, 0.788888, 0.382914));
    EXPECT_EQ(viridis(1.0), reference(0.993248, 0.906157, 0.143936));
}

TEST(Colormap, InfernoMatchesMatplotlibEntries) {
    EXPECT_EQ(inferno(0.0), reference(0.001462, 0.000466, 0.013866));
    EXPECT_EQ(inferno(64 / 255.0), reference(0.341500, 0.062325, 0.429425));
    EXPECT_EQ(inferno(128 / 255.0), reference(0.735683, 0.215906, 0.330245));
    EXPECT_EQ(inferno(192 / 255.0), reference(0.978422, 0.557937, 0.034931));
    EXPECT_EQ(inferno(1.0), reference(0.988362, 0.998364, 0.644924));
}

TEST(Colormap, ClampsOutsideTheUnitInterval) {
    EXPECT_EQ(viridis(-1.0), viridis(0.0));
    EXPECT_EQ(viridis(2.0), viridis(1.0));
    EXPECT_EQ(inferno(std::nan("")), inferno(0.0));
}

}  // namespace
}  // namespace cavesim::render

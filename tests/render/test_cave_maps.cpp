// Cave maps: the extended elevation's layout against hand-computed distances, and the files.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/check.h"
#include "render/cave_maps.h"
#include "render/png_io.h"

namespace cavesim::render {
namespace {

// A Y: passage 0 from the entrance (station 0) to the junction (1), then passage 1 down to
// station 2 and passage 2 on to station 3. Horizontal legs: 5 m, 6 m, 8 m.
CaveMapInput yCave() {
    CaveMapInput in;
    in.title = "Y";
    in.blockMax = {20, 20, 12};
    in.stations = {
        {{0, 0, 10}, 0.5, "p0.0"}, {{3, 4, 10}, 0.5, "p0.1"}, {{3, 10, 5}, 0.5, "p1.1"}, {{11, 4, 10}, 0.5, "p2.1"}};
    in.passages = {{0, 1}, {1, 2}, {3, 1}};  // passage 2 is listed from its far end
    in.sources = {{0.2, 0.1, 10}};
    in.sinks = {{3, 10, 5}};
    return in;
}

TEST(CaveMaps, ExtendedElevationLaysPassagesEndToEndFromTheEntrance) {
    double extent = 0;
    const auto xs = extendedElevationLayout(yCave(), &extent);
    ASSERT_EQ(xs.size(), 3u);
    EXPECT_DOUBLE_EQ(xs[0][0], 0.0);
    EXPECT_DOUBLE_EQ(xs[0][1], 5.0);
    // Passage 1 continues passage 0 from the junction.
    EXPECT_DOUBLE_EQ(xs[1][0], 5.0);
    EXPECT_DOUBLE_EQ(xs[1][1], 11.0);
    // Passage 2 leaves the junction too, but after passage 1: a gap of 3 % of the 19 m, and it is
    // drawn from the junction (its last station) to its far end (its first).
    const double gap = 0.03 * 19.0;
    EXPECT_DOUBLE_EQ(xs[2][1], 11.0 + gap);
    EXPECT_DOUBLE_EQ(xs[2][0], 19.0 + gap);
    EXPECT_DOUBLE_EQ(extent, 19.0 + gap);
}

TEST(CaveMaps, EntranceIsThePassageEndNearestTheFirstSource) {
    CaveMapInput in = yCave();
    in.sources = {{11, 4, 10}};  // at station 3: passage 2 first, reversed
    const auto xs = extendedElevationLayout(in);
    EXPECT_DOUBLE_EQ(xs[2][0], 0.0);
    EXPECT_DOUBLE_EQ(xs[2][1], 8.0);
    EXPECT_DOUBLE_EQ(xs[0][1], 8.0);  // passage 0 continues from the junction, backwards
    EXPECT_DOUBLE_EQ(xs[0][0], 13.0);
}

TEST(CaveMaps, RejectsBadPassages) {
    CaveMapInput in = yCave();
    in.passages.push_back({2});
    EXPECT_THROW(extendedElevationLayout(in), InternalError);
    in.passages.back() = {2, 9};
    EXPECT_THROW(extendedElevationLayout(in), InternalError);
}

TEST(CaveMaps, WritesPngAndSvgOfEachMap) {
    const auto dir = std::filesystem::temp_directory_path() / "cavesim_test_cave_maps";
    std::filesystem::remove_all(dir);
    const auto files = writeCaveMaps(yCave(), false, dir.string(), 400);
    EXPECT_EQ(files, (std::vector<std::string>{"map_plan.png", "map_plan.svg", "map_extended_elevation.png",
                                               "map_extended_elevation.svg"}));
    const Image plan = readPng((dir / "map_plan.png").string());
    EXPECT_EQ(plan.width, 400);
    EXPECT_GT(distinctColours(plan), 50u);  // passages in elevation colours, anti-aliased text
    std::ifstream svg(dir / "map_extended_elevation.svg");
    const std::string text((std::istreambuf_iterator<char>(svg)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("<svg"), std::string::npos);
    EXPECT_NE(text.find("width=\"400"), std::string::npos);
    const auto section = writeCaveMaps(yCave(), true, dir.string(), 400);
    EXPECT_EQ(section.front(), "map_section.png");
    // Same input, same bytes.
    EXPECT_EQ(drawCaveMap(yCave(), MapKind::kPlan, 400).svg, drawCaveMap(yCave(), MapKind::kPlan, 400).svg);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cavesim::render

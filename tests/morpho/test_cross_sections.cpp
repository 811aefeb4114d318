// Passage cross-sections: hand-built slices (circle, slot, keyhole, V, wide and low) measured and
// classified against hand-computed numbers; voxel caves through the skeleton: a cylinder is a
// tube, a tall slot a canyon, a circle over a slot a keyhole; a short stub between junctions is
// not classified.
#include <gtest/gtest.h>

#include <algorithm>

#include "morpho/cross_sections.h"
#include "morpho/skeleton.h"

namespace cavesim::morpho {
namespace {

/// A slice from rows of text: '#' in the section.
SectionSlice slice(const std::vector<std::string>& rows, double step = 0.5) {
    SectionSlice s;
    s.rows = int(rows.size());
    s.cols = int(rows.front().size());
    s.step = step;
    for (const std::string& r : rows)
        for (char c : r) s.cells.push_back(c == '#');
    return s;
}

/// The disc x² + y² ≤ 20 on integer points: rows 5, 7, 9, 9, 9, 9, 9, 7, 5 wide; 69 samples.
std::vector<std::string> disc() {
    std::vector<std::string> rows;
    for (int y = -4; y <= 4; ++y) {
        std::string r;
        for (int x = -4; x <= 4; ++x) r += x * x + y * y <= 20 ? '#' : '.';
        rows.push_back(r);
    }
    return rows;
}

TEST(CrossSections, DiscSliceIsATube) {
    const SectionShape s = measureSection(slice(disc()));
    EXPECT_EQ(s.cls, SectionClass::kTube);
    EXPECT_DOUBLE_EQ(s.width_m, 4.5);
    EXPECT_DOUBLE_EQ(s.height_m, 4.5);
    EXPECT_DOUBLE_EQ(s.area_m2, 69 * 0.25);
}

TEST(CrossSections, SlotSliceIsACanyon) {
    const SectionShape s = measureSection(slice(std::vector<std::string>(10, "..###..")));
    EXPECT_EQ(s.cls, SectionClass::kCanyon);
    EXPECT_DOUBLE_EQ(s.width_m, 1.5);
    EXPECT_DOUBLE_EQ(s.height_m, 5.0);
}

TEST(CrossSections, DiscOverSlotSliceIsAKeyhole) {
    std::vector<std::string> rows = disc();
    for (int i = 0; i < 6; ++i) rows.push_back("...###...");
    const SectionShape s = measureSection(slice(rows));
    EXPECT_EQ(s.cls, SectionClass::kKeyhole);
    EXPECT_DOUBLE_EQ(s.width_m, 4.5);
    EXPECT_DOUBLE_EQ(s.height_m, 7.5);
    EXPECT_DOUBLE_EQ(s.area_m2, (69 + 18) * 0.25);
}

TEST(CrossSections, VAndWideLowAreOther) {
    // A V, widest at the top (9, 8, …, 1): not a keyhole; W = H, fill 45/81 < 0.6.
    std::vector<std::string> v;
    for (int w = 9; w >= 1; --w) v.push_back(std::string(std::size_t(w), '#') + std::string(std::size_t(9 - w), '.'));
    EXPECT_EQ(measureSection(slice(v)).cls, SectionClass::kOther);
    EXPECT_EQ(measureSection(slice(std::vector<std::string>(3, "############"))).cls, SectionClass::kOther);
    EXPECT_EQ(measureSection(slice({"...", "..."})).cls, SectionClass::kOther);  // empty: other, zero size
    EXPECT_DOUBLE_EQ(measureSection(slice({"...", "..."})).width_m, 0.0);
}

/// A passage along x (i in [2, 38)) whose cross-section in (j, k) is `inside(j, k)`.
template <typename F>
Grid3<std::uint8_t> passage(int ny, int nz, F inside) {
    Grid3<std::uint8_t> mask(Dims{40, ny, nz}, 0);
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 2; i < 38; ++i)
                if (inside(j, k)) mask.at(i, j, k) = 1;
    return mask;
}

const PassageSection& longest(const CrossSections& c) {
    return *std::max_element(c.passages.begin(), c.passages.end(),
                             [](const PassageSection& a, const PassageSection& b) { return a.length_m < b.length_m; });
}

TEST(CrossSections, VoxelCylinderIsATube) {
    const auto mask = passage(13, 13, [](int j, int k) { return (j - 6) * (j - 6) + (k - 6) * (k - 6) <= 20; });
    const CrossSections c = measureCrossSections(mask, 1.0, skeletonize(mask, 1.0));
    ASSERT_EQ(c.passages.size(), 1u);
    const PassageSection& p = c.passages[0];
    EXPECT_EQ(p.cls, SectionClass::kTube);
    EXPECT_EQ(p.votes[0], c.stations);  // every station a tube
    // Widest row and height: 9 voxels (the disc above, one voxel per 2 samples).
    EXPECT_DOUBLE_EQ(p.width_m, 9.0);
    EXPECT_DOUBLE_EQ(p.height_m, 9.0);
    EXPECT_DOUBLE_EQ(p.z_m, 6.5);
    const nlohmann::json j = toJson(c);
    EXPECT_EQ(j["summary"][0]["class"], "tube");
    EXPECT_EQ(j["summary"][0]["passages"], 1);
    EXPECT_EQ(j["passages"][0]["class"], "tube");
}

TEST(CrossSections, VoxelSlotIsACanyon) {
    const auto mask = passage(9, 16, [](int j, int k) { return j >= 3 && j < 6 && k >= 2 && k < 14; });
    const CrossSections c = measureCrossSections(mask, 1.0, skeletonize(mask, 1.0));
    const PassageSection& p = longest(c);
    EXPECT_EQ(p.cls, SectionClass::kCanyon);
    EXPECT_DOUBLE_EQ(p.width_m, 3.0);
    EXPECT_DOUBLE_EQ(p.height_m, 12.0);
}

TEST(CrossSections, VoxelCircleOverSlotIsAKeyhole) {
    // Disc of radius² 20 centred at (j, k) = (8, 14) over a slot 3 wide from k = 2 up into it.
    const auto mask = passage(17, 21, [](int j, int k) {
        return (j - 8) * (j - 8) + (k - 14) * (k - 14) <= 20 || (j >= 7 && j < 10 && k >= 2 && k < 12);
    });
    const CrossSections c = measureCrossSections(mask, 1.0, skeletonize(mask, 1.0));
    const PassageSection& p = longest(c);
    EXPECT_EQ(p.cls, SectionClass::kKeyhole);
    EXPECT_DOUBLE_EQ(p.width_m, 9.0);
    EXPECT_DOUBLE_EQ(p.height_m, 17.0);  // k = 2 … 18
}

TEST(CrossSections, StubBetweenJunctionsIsShort) {
    // Two junctions 1 m apart: the 1-edge branch between them has no station clear of both.
    Skeleton s;
    const std::vector<Vec3d> pos{{5, 5, 5}, {6, 5, 5}, {5, 0, 5}, {5, 10, 5}, {6, 0, 5}, {6, 10, 5}};
    for (const auto& p : pos) s.nodes.push_back({p, 1.0, 0});
    s.edges = {{0, 1}, {0, 2}, {0, 3}, {1, 4}, {1, 5}};
    Grid3<std::uint8_t> mask(Dims{12, 12, 12}, 1);
    const CrossSections c = measureCrossSections(mask, 1.0, s);
    bool foundShort = false;
    for (const PassageSection& p : c.passages) foundShort |= p.cls == SectionClass::kShort;
    EXPECT_TRUE(foundShort);
    EXPECT_EQ(toJson(c)["summary"][4]["class"], "short");
}

}  // namespace
}  // namespace cavesim::morpho

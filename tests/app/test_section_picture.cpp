// images/sections.png: one column per class present, the slice of each example drawn in its
// class colour; nothing without a section.
#include <gtest/gtest.h>

#include "app/section_picture.h"
#include "morpho/skeleton.h"

namespace cavesim::app {
namespace {

TEST(SectionPicture, OneTubeColumnAndNothingWithoutSections) {
    Grid3<std::uint8_t> mask(Dims{40, 13, 13}, 0);
    for (int k = 0; k < 13; ++k)
        for (int j = 0; j < 13; ++j)
            for (int i = 2; i < 38; ++i)
                if ((j - 6) * (j - 6) + (k - 6) * (k - 6) <= 20) mask.at(i, j, k) = 1;
    const morpho::CrossSections c = morpho::measureCrossSections(mask, 1.0, morpho::skeletonize(mask, 1.0));
    ASSERT_EQ(c.passages.size(), 1u);
    const render::Image img = sectionsPicture(c, "test");
    // At least two panels wide; title, header, one panel and its caption high.
    EXPECT_EQ(img.width, 440);
    EXPECT_EQ(img.height, 30 + 24 + 220 + 40);
    // The panel's centre is cave, drawn in the tube colour.
    EXPECT_EQ(img.get(110, 30 + 24 + 10 + 100), (render::Rgb{40, 110, 200}));
    EXPECT_EQ(sectionsPicture(morpho::CrossSections{}, "none").width, 0);
}

}  // namespace
}  // namespace cavesim::app

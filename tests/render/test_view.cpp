// Cameras and frames: projection and rays agree, views frame the block exactly, figures line up.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/error.h"
#include "render/colormap.h"
#include "render/image.h"
#include "render/view.h"

namespace cavesim::render {
namespace {

TEST(Camera, OrthographicRaysProjectBackToTheirPixel) {
    const Frame f = makeFrame(View::kSideYZ, {40, 30, 20}, 0.5, 800);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> ux(f.vx, f.vx + f.vw), uy(f.vy, f.vy + f.vh);
    for (int n = 0; n < 100; ++n) {
        const double px = ux(rng), py = uy(rng);
        Vec3d o, d;
        f.camera.ray(px, py, o, d);
        EXPECT_DOUBLE_EQ(d[0], f.camera.forward[0]);
        for (double t : {0.0, 3.0, 17.5}) {
            const auto p = f.camera.project({o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]});
            EXPECT_NEAR(p.x, px, 1e-9);
            EXPECT_NEAR(p.y, py, 1e-9);
            EXPECT_NEAR(p.depth, t, 1e-9);
        }
    }
}

TEST(Camera, PerspectiveRaysProjectBackToTheirPixelAndDepthGrows) {
    const Frame f = makeFrame(View::kPerspective, {60, 60, 20}, 1.0, 1024);
    for (double px : {f.vx + 3.5, f.vx + f.vw / 2.0, f.vx + f.vw - 2.5})
        for (double py : {f.vy + 1.5, f.vy + f.vh * 0.7}) {
            Vec3d o, d;
            f.camera.ray(px, py, o, d);
            EXPECT_NEAR(std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), 1.0, 1e-12);
            double last = 0.0;
            for (double t : {10.0, 50.0, 120.0}) {
                const auto p = f.camera.project({o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]});
                EXPECT_NEAR(p.x, px, 1e-7);
                EXPECT_NEAR(p.y, py, 1e-7);
                EXPECT_GT(p.depth, last);
                last = p.depth;
            }
        }
}

TEST(Frame, PlanViewportIsExactlyTheBlock) {
    const Frame f = makeFrame(View::kPlan, {60, 30, 20}, 1.0, 1024);
    EXPECT_EQ(f.width, 1024);
    EXPECT_NEAR(double(f.vw) / f.vh, 2.0, 0.02);
    // Block corners land on the viewport corners; y points up.
    const auto lowLeft = f.camera.project({0, 0, 20});
    const auto topRight = f.camera.project({60, 30, 20});
    EXPECT_NEAR(lowLeft.x, f.vx, 1e-9);
    EXPECT_NEAR(lowLeft.y, f.vy + f.vh, 0.6);
    EXPECT_NEAR(topRight.x, f.vx + f.vw, 1e-9);
    EXPECT_NEAR(topRight.y, f.vy, 0.6);
    EXPECT_DOUBLE_EQ(lowLeft.depth, 0.0);  // depth measured from the top face down
    EXPECT_DOUBLE_EQ(f.camera.project({5, 5, 0}).depth, 20.0);
}

TEST(Frame, SideViewsLookAtTheRightFaces) {
    const Frame xz = makeFrame(View::kSideXZ, {60, 60, 20}, 1.0, 1024);
    EXPECT_NEAR(double(xz.vw) / xz.vh, 3.0, 0.03);
    EXPECT_LT(xz.camera.project({10, 0, 10}).x, xz.camera.project({20, 0, 10}).x);  // x right
    EXPECT_GT(xz.camera.project({10, 0, 5}).y, xz.camera.project({10, 0, 15}).y);   // z up
    const Frame yz = makeFrame(View::kSideYZ, {60, 60, 20}, 1.0, 1024);
    EXPECT_LT(yz.camera.project({0, 10, 10}).x, yz.camera.project({0, 20, 10}).x);  // y right
    EXPECT_DOUBLE_EQ(yz.camera.project({60, 5, 5}).depth, 0.0);                     // seen from x = max
}

TEST(Frame, SameViewAndWidthLineUpWhateverTheFooter) {
    const Frame a = makeFrame(View::kPlan, {60, 60, 20}, 1.0, 900, 1);
    const Frame b = makeFrame(View::kPlan, {60, 60, 20}, 1.0, 900, 5);
    EXPECT_EQ(a.vx, b.vx);
    EXPECT_EQ(a.vy, b.vy);
    EXPECT_EQ(a.vw, b.vw);
    EXPECT_EQ(a.vh, b.vh);
    EXPECT_GT(b.height, a.height);
}

TEST(Frame, TallBlocksAreCappedAndCentred) {
    const Frame f = makeFrame(View::kSideXZ, {5, 1, 400}, 1.0, 512);
    EXPECT_LE(f.vh, int(1.25 * 512) + 1);
    EXPECT_GT(f.vx, 40);
    EXPECT_EQ(f.width, 512);
}

TEST(Frame, RejectsBadInput) {
    EXPECT_THROW(makeFrame(View::kPlan, {10, 10, 10}, 1.0, 10), InternalError);
    EXPECT_THROW(makeFrame(View::kPlan, {10, 0, 10}, 1.0, 512), InternalError);
    EXPECT_THROW(makeFrame(View::kPlan, {10, 10, 10}, -1.0, 512), InternalError);
}

TEST(Cells, FillCellsPaintsEachCellWhereItProjects) {
    const Frame f = makeFrame(View::kSideXZ, {7, 3, 5}, 2.0, 400);
    Image img = makeCanvas(f);
    fillCells(img, f, [](int u, int v) { return Rgb{std::uint8_t(20 * u), std::uint8_t(30 * v), 7}; });
    for (int v = 0; v < 5; ++v)
        for (int u = 0; u < 7; ++u) {
            const auto p = f.camera.project(viewPlanePoint(f, u + 0.5, v + 0.5));
            EXPECT_EQ(img.get(int(p.x), int(p.y)), (Rgb{std::uint8_t(20 * u), std::uint8_t(30 * v), 7}))
                << u << "," << v;
        }
}

TEST(Cells, OutlineFollowsTheBoundary) {
    const Frame f = makeFrame(View::kPlan, {10, 10, 1}, 1.0, 400, 0);
    Image img(f.width, f.height, colours::kWhite);
    // One inside cell at (4, 6): its four sides are drawn, its centre is not.
    outlineCells(
        img, f, [](int u, int v) { return u == 4 && v == 6; }, colours::kBlack, 1);
    const auto centre = f.camera.project(viewPlanePoint(f, 4.5, 6.5));
    const auto left = f.camera.project(viewPlanePoint(f, 4.0, 6.5));
    const auto top = f.camera.project(viewPlanePoint(f, 4.5, 7.0));
    EXPECT_EQ(img.get(int(centre.x), int(centre.y)), colours::kWhite);
    EXPECT_EQ(img.get(int(std::lround(left.x)), int(left.y)), colours::kBlack);
    EXPECT_EQ(img.get(int(top.x), int(std::lround(top.y))), colours::kBlack);
}

TEST(Numbers, NiceNumbersAndFormats) {
    EXPECT_DOUBLE_EQ(niceNumber(12.0), 10.0);
    EXPECT_DOUBLE_EQ(niceNumber(4.0), 5.0);
    EXPECT_DOUBLE_EQ(niceNumber(0.026), 0.02);
    EXPECT_DOUBLE_EQ(niceNumber(-3.0), 1.0);
    EXPECT_EQ(formatMetres(20.0), "20");
    EXPECT_EQ(formatMetres(2.5), "2.5");
    EXPECT_EQ(formatMetres(0.25), "0.25");
    EXPECT_EQ(formatValue(0.0), "0");
    EXPECT_EQ(formatValue(1e-4), "0.0001");
}

TEST(Annotations, DrawingIsClippedAndLeavesMarks) {
    const Frame f = makeFrame(View::kPerspective, {20, 10, 5}, 1.0, 300, 2);
    Image img = makeCanvas(f);
    const double before = pixelVariance(img);
    drawBlockOutline(img, f);
    drawAxes(img, f);
    drawTitle(img, f, "a title", std::string(400, 'x'));  // far too long: shrunk and shortened
    drawStandardLegend(img, f);
    drawColourBar(
        img, f, 1,
        [](double t) {
            return Rgb{std::uint8_t(255 * t), 0, 0};
        },
        1e-3, 10.0, true, "log");
    EXPECT_GT(pixelVariance(img), before);
    EXPECT_EQ(img.width, 300);
}

}  // namespace
}  // namespace cavesim::render

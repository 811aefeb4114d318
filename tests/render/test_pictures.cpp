// The 2D figures of the voxel state: sizes, colours where the data says, layout, PNG round trip.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <random>

#include "core/error.h"
#include "render/colormap.h"
#include "render/pictures.h"
#include "render/png_io.h"
#include "render/view.h"
#include "sim/cave.h"

namespace cavesim::render {
namespace {

// A block with two zones (x < nx/2: source 0, else source 1), a protochannel along x at mid
// height, a channel (the cave) along the same line in the right half, pressure = x, flow
// decaying away from the channel.
Domain twoZones(Dims dims) {
    Domain d = emptyDomain(dims, 0.5, 0.05f);
    const int jm = dims.ny / 2, km = dims.nz / 2;
    for (int k = 0; k < dims.nz; ++k)
        for (int j = 0; j < dims.ny; ++j)
            for (int i = 0; i < dims.nx; ++i) {
                d.zone.at(i, j, k) = i < dims.nx / 2 ? 0 : 1;
                d.pressure.at(i, j, k) = float(i);
                d.flow.at(i, j, k) = float(std::pow(10.0, -std::abs(k - km) - std::abs(j - jm)));
                if (j == jm && k == km) {
                    d.flags.at(i, j, k) |= kProtochannel;
                    if (i >= dims.nx / 2) {
                        d.flags.at(i, j, k) |= kChannel;
                        d.porosity.at(i, j, k) = 1.f;
                    }
                }
            }
    d.sourceVoxels = {{dims.index(1, jm, km)}, {dims.index(dims.nx - 2, jm, km)}};
    d.sourcePressure = {1.0, 2.0};
    d.sinkVoxels = {{dims.index(dims.nx / 2, 0, 0)}};
    for (const auto& s : d.sourceVoxels) d.flags[s[0]] |= kSource;
    d.flags[d.sinkVoxels[0][0]] |= kSink;
    return d;
}

Rgb at(const Image& img, const Frame& f, double u, double v) {
    const auto p = f.camera.project(viewPlanePoint(f, u, v));
    return img.get(int(p.x), int(p.y));
}

void expectReadable(const Image& img, int width) {
    EXPECT_EQ(img.width, width);
    EXPECT_GT(img.height, 50);
    EXPECT_GT(pixelVariance(img), 100.0);
    EXPECT_GE(distinctColours(img), 6u);
}

TEST(ZonesPicture, PlanShowsEachZoneItsProtochannelsAndSources) {
    const Domain d = twoZones({30, 20, 6});
    const int width = 600;
    const Image img = zonesPicture(d, width);
    expectReadable(img, width);
    const Frame f = makeFrame(View::kPlan, d.dims, d.voxelSize, width, 2);  // same viewport
    EXPECT_EQ(at(img, f, 5.5, 3.5), mix(zoneColour(0), colours::kWhite, 0.45));
    EXPECT_EQ(at(img, f, 24.5, 16.5), mix(zoneColour(1), colours::kWhite, 0.45));
    EXPECT_EQ(at(img, f, 8.5, 10.5), mix(zoneColour(0), colours::kBlack, 0.55));  // protochannel, zone 0
    // Source S1 is marked in red at its voxel.
    const auto s = f.camera.project({1.5 * d.voxelSize, 10.5 * d.voxelSize, 3.5 * d.voxelSize});
    EXPECT_EQ(img.get(int(s.x), int(s.y)), colours::kSource);
}

TEST(ZonesPicture, SectionIsDrawnAsItself) {
    const Domain d = twoZones({40, 1, 16});
    const Image img = zonesPicture(d, 512);
    expectReadable(img, 512);
    const Frame f = makeFrame(View::kSideXZ, d.dims, d.voxelSize, 512, 2);
    EXPECT_EQ(at(img, f, 3.5, 2.5), mix(zoneColour(0), colours::kWhite, 0.45));
    EXPECT_EQ(at(img, f, 36.5, 2.5), mix(zoneColour(1), colours::kWhite, 0.45));
}

TEST(ZonesPicture, NoZonesStillGivesAPicture) {
    Domain d = twoZones({12, 12, 4});
    for (auto& z : d.zone.data) z = -1;
    d.sourceVoxels.clear();
    d.sourcePressure.clear();
    expectReadable(zonesPicture(d, 256), 256);
}

TEST(FieldPictures, SectionPressureHasTheColourOfItsValue) {
    const Domain d = twoZones({40, 1, 16});
    const int width = 640;
    const Image img = pressurePicture(d, caveMask(d, CaveExtent::kChannels), width);
    expectReadable(img, width);
    const Frame f = makeFrame(View::kSideXZ, d.dims, d.voxelSize, width, 2);
    // pressure = i on [0, 39]: linear colour bar from 0 to 39.
    for (int i : {2, 20, 33}) EXPECT_EQ(at(img, f, i + 0.5, 2.5), viridis(i / 39.0)) << i;
}

TEST(FieldPictures, BlockPicturesHaveTwoPanelsAndLogFlow) {
    const Domain d = twoZones({30, 20, 6});
    const int width = 500;
    const Image p = pressurePicture(d, caveMask(d, CaveExtent::kChannels), width),
                fl = flowPicture(d, caveMask(d, CaveExtent::kChannels), width);
    expectReadable(p, width);
    expectReadable(fl, width);
    const Frame plan = makeFrame(View::kPlan, d.dims, d.voxelSize, width, 2);
    const Frame side = makeFrame(View::kSideXZ, d.dims, d.voxelSize, width, 2);
    EXPECT_EQ(p.height, plan.height + side.height);
    // Flow: the largest value of each column; 1 on the channel line (the top of the log scale),
    // 1e-4 and below shown as rock.
    EXPECT_EQ(at(fl, plan, 3.5, 10.5), inferno(1.0));
    EXPECT_EQ(at(fl, plan, 3.5, 4.5), mix(colours::kRock, colours::kWhite, 0.55));
}

TEST(FieldPictures, WithoutStage2DataTheyStillDraw) {
    Domain d = twoZones({20, 1, 10});
    for (auto& v : d.pressure.data) v = 0.f;
    for (auto& v : d.flow.data) v = 0.f;
    expectReadable(pressurePicture(d, caveMask(d, CaveExtent::kChannels), 300), 300);
    expectReadable(flowPicture(d, caveMask(d, CaveExtent::kChannels), 300), 300);
    d.pressure = Grid3<float>();  // absent grids read as zeros
    expectReadable(pressurePicture(d, caveMask(d, CaveExtent::kChannels), 300), 300);
}

TEST(StateFrame, SectionStacksPorosityPressureAndFlow) {
    const Domain d = twoZones({40, 1, 16});
    const int width = 480;
    const Image img = stateFrame(d, caveMask(d, CaveExtent::kChannels), "iteration 7", width);
    const Frame f = makeFrame(View::kSideXZ, d.dims, d.voxelSize, width, 2);
    EXPECT_EQ(img.width, width);
    EXPECT_EQ(img.height, 3 * f.height);
    // Channel voxels (porosity 1) are dark in the top panel, rock light.
    EXPECT_LT(int(at(img, f, 30.5, 8.5).r), 60);
    EXPECT_GT(int(at(img, f, 30.5, 2.5).r), 200);
}

TEST(StateFrame, BlockIsOnePlanPanel) {
    const Domain d = twoZones({30, 20, 6});
    const Image img = stateFrame(d, caveMask(d, CaveExtent::kChannels), "iteration 1", 400);
    const Frame f = makeFrame(View::kPlan, d.dims, d.voxelSize, 400, 2);
    EXPECT_EQ(img.height, f.height);
    expectReadable(img, 400);
    // The cave (channel at k = 3 of nz = 6) coloured by the depth of its top.
    EXPECT_EQ(at(img, f, 20.5, 10.5), depthRamp(2.0 / 5.0));
}

TEST(ComposeStrip, FramesSideBySideOrInRows) {
    std::vector<Image> frames{Image(100, 50, Rgb{255, 0, 0}), Image(100, 50, Rgb{0, 255, 0}),
                              Image(80, 40, Rgb{0, 0, 255})};
    const Image strip = composeStrip(frames, 1);
    const int gap = 4;
    EXPECT_EQ(strip.width, 3 * 100 + 2 * gap);
    EXPECT_EQ(strip.height, 50);
    EXPECT_EQ(strip.get(10, 10), (Rgb{255, 0, 0}));
    EXPECT_EQ(strip.get(100 + gap + 10, 10), (Rgb{0, 255, 0}));
    EXPECT_EQ(strip.get(2 * (100 + gap) + 10, 10), (Rgb{0, 0, 255}));
    const Image grid = composeStrip(frames, 2);
    EXPECT_EQ(grid.width, 2 * 100 + gap);
    EXPECT_EQ(grid.height, 2 * 50 + gap);
    EXPECT_EQ(grid.get(10, 50 + gap + 10), (Rgb{0, 0, 255}));
    EXPECT_THROW(composeStrip({}, 1), InternalError);
    EXPECT_THROW(composeStrip(frames, 0), InternalError);
    EXPECT_THROW(composeStrip({Image()}, 1), InternalError);
}

TEST(FracturesPicture, LabelShowsWhatCannotBeEstimatedAsNotAvailable) {
    FractureFamilyStats st;
    st.meanDipDirection = 45;
    st.meanDip = 7;
    st.kappaEstimate = 0;  // what the measurement leaves for fewer than 2 discs
    st.count = 1;
    EXPECT_EQ(fractureFamilyLabel(0, st), "family 1: 1 discs, measured dip direction/dip 045/07, kappa n/a");
    st.count = 0;
    EXPECT_EQ(fractureFamilyLabel(1, st), "family 2: 0 discs, measured dip direction/dip n/a, kappa n/a");
    st.count = 12;
    st.kappaEstimate = 31.6;
    EXPECT_EQ(fractureFamilyLabel(2, st), "family 3: 12 discs, measured dip direction/dip 045/07, kappa 32");
}

// Discs are blended at 12 %, so a few dozen layers saturate the picture. A family far past that is
// drawn as an evenly spaced subset of about 64 layers and looks like one drawn whole, and a sparse
// family beside it keeps every disc. (300 000 discs covering the view drawn one by one took
// minutes; the subset takes a moment.)
TEST(FracturesPicture, ADenseFamilyIsDrawnAsASubsetAndASparseOneWhole) {
    const Dims dims{30, 30, 12};
    const Domain d = emptyDomain(dims, 1.0, 0.05f);
    const Grid3<std::uint8_t> noCave(dims, 0);
    FractureDisc wide;  // flat: in plan it covers the whole view
    wide.centre = {15, 15, 6};
    wide.normal = {0, 0, 1};
    wide.radius = 40;
    const std::vector<std::array<double, 2>> spots{{4, 4}, {4, 25}, {25, 4}};
    const auto network = [&](std::size_t dense, bool sparse) {
        FractureNetwork net;
        net.families.resize(2);
        net.families[0].count = long(dense);
        net.discs.assign(dense, wide);
        for (const auto& xy : spots) {
            if (!sparse) break;
            FractureDisc small = wide;
            small.family = 1;
            small.centre = {xy[0], xy[1], 6};
            small.radius = 1.5;
            net.discs.push_back(small);
            ++net.families[1].count;
        }
        return net;
    };
    const Frame f = makeFrame(View::kPlan, dims, 1.0, 256, 3);
    const auto pixel = [&](const Image& img, double x, double y) {
        return img.get(f.vx + int(x / 30.0 * f.vw), f.vy + f.vh - 1 - int(y / 30.0 * f.vh));
    };
    // 40 discs are drawn whole, 300 000 as a subset: the same colour at the centre, within rounding.
    const Image whole = fracturesPicture(d, noCave, network(40, false), 256);
    const Image subset = fracturesPicture(d, noCave, network(300000, true), 256);
    const Rgb a = pixel(whole, 15, 15), b = pixel(subset, 15, 15);
    EXPECT_NEAR(a.r, b.r, 2);
    EXPECT_NEAR(a.g, b.g, 2);
    EXPECT_NEAR(a.b, b.b, 2);
    EXPECT_NE(a, pixel(fracturesPicture(d, noCave, network(0, false), 256), 15, 15));  // the discs are drawn
    // Every disc of the sparse family shows over the dense one.
    const Image without = fracturesPicture(d, noCave, network(300000, false), 256);
    for (const auto& xy : spots) EXPECT_NE(pixel(subset, xy[0], xy[1]), pixel(without, xy[0], xy[1])) << xy[0] << ", " << xy[1];
}

TEST(Pictures, RejectBadWidths) {
    const Domain d = twoZones({8, 8, 4});
    EXPECT_THROW(zonesPicture(d, 10), InternalError);
    EXPECT_THROW(stateFrame(d, caveMask(d, CaveExtent::kChannels), "x", 100000), InternalError);
}

TEST(Png, RoundTripIsExactAndLeavesNoTemporaryFile) {
    const auto dir = std::filesystem::temp_directory_path() / "cavesim_test_render_png";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    Image img(37, 23);
    std::mt19937 rng(11);
    for (auto& p : img.pixels) p = std::uint8_t(rng() & 255);
    const std::string path = (dir / "a.png").string();
    writePng(path, img);
    const Image back = readPng(path);
    EXPECT_EQ(back.width, 37);
    EXPECT_EQ(back.height, 23);
    EXPECT_EQ(back.pixels, img.pixels);
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()), 1);
    EXPECT_THROW(writePng((dir / "missing" / "b.png").string(), img), RuntimeError);
    EXPECT_THROW(writePng(path, Image()), RuntimeError);
    EXPECT_THROW(readPng((dir / "nothing.png").string()), RuntimeError);
    std::filesystem::remove_all(dir);
}

TEST(Pictures, WrittenFilesHaveTheRequestedWidth) {
    const auto dir = std::filesystem::temp_directory_path() / "cavesim_test_render_files";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const Domain d = twoZones({16, 12, 4});
    writeZonesPicture(d, (dir / "zones.png").string(), 320);
    writeFieldPictures(d, caveMask(d, CaveExtent::kChannels), dir.string(), 320);
    for (const char* name : {"zones.png", "pressure.png", "flow.png"}) {
        const Image img = readPng((dir / name).string());
        EXPECT_EQ(img.width, 320) << name;
        EXPECT_GT(pixelVariance(img), 0.0) << name;
    }
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cavesim::render

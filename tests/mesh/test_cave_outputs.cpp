// cave.obj / cave.ply / cave_voxels.obj and the ray-traced pictures of a small cave domain.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "core/error.h"
#include "mesh/cave_mesh.h"
#include "mesh/cave_pictures.h"
#include "render/colormap.h"
#include "render/png_io.h"
#include "render/view.h"
#include "sim/cave.h"

namespace cavesim::mesh {
namespace {

namespace fs = std::filesystem;

// A 24×16×10 block (voxels of 0.5 m) with an L-shaped channel: along x at (j, k) = (8, 5), then
// up along z at i = 18; a source at its start, a sink at its top.
Domain lChannel(bool withCave = true) {
    Domain d = emptyDomain(Dims{24, 16, 10}, 0.5, 0.05f);
    if (withCave) {
        for (int i = 3; i <= 18; ++i)
            for (int dj = -1; dj <= 1; ++dj)
                for (int dk = -1; dk <= 1; ++dk) d.flags.at(i, 8 + dj, 5 + dk) |= kChannel;
        for (int k = 5; k < 10; ++k) d.flags.at(18, 8, k) |= kChannel;
    }
    d.sourceVoxels = {{d.dims.index(2, 8, 5)}};
    d.sourcePressure = {1.0};
    d.sinkVoxels = {{d.dims.index(18, 8, 9)}};
    d.flags[d.sourceVoxels[0][0]] |= kSource;
    d.flags[d.sinkVoxels[0][0]] |= kSink;
    return d;
}

long caveVoxels(const Domain& d) {
    long n = 0;
    for (std::uint8_t v : caveMask(d, CaveExtent::kChannels).data) n += v;
    return n;
}

fs::path freshDir(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("cavesim_test_mesh_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

long countFiles(const fs::path& dir) {
    return long(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

TEST(CaveMeshFiles, WritesObjAndPlyThatReadBackAsTheSameClosedMesh) {
    const fs::path dir = freshDir("files");
    const Domain d = lChannel();
    const MeshStats stats = writeCaveMesh(makeCave(d, CaveExtent::kChannels), dir.string());
    EXPECT_TRUE(stats.closed);
    EXPECT_TRUE(stats.manifold);
    EXPECT_EQ(stats.components, 1);
    EXPECT_EQ(stats.eulerCharacteristic, 2);
    EXPECT_GT(stats.volumeM3, 0.0);
    EXPECT_GT(stats.seconds, 0.0);
    // The smooth surface encloses about the voxels' volume: the 3×3 tube, the riser up to the sink
    // (3 voxels above the tube, the last one the sink, which is not cave) and the source inlet.
    const double voxels = double(caveVoxels(d));
    EXPECT_EQ(voxels, 16 * 9 + 3 - 1 + 1);
    EXPECT_NEAR(stats.volumeM3, voxels * 0.125, 0.15 * voxels * 0.125);
    EXPECT_EQ(countFiles(dir), 2);  // cave.obj, cave.ply, no temporary left behind
    for (const char* name : {"cave.obj", "cave.ply"}) {
        const TriangleMesh back = readMeshFile((dir / name).string());
        const MeshStats s = measureMesh(back);
        EXPECT_EQ(s.faces, stats.faces) << name;
        EXPECT_EQ(s.vertices, stats.vertices) << name;
        EXPECT_NEAR(s.volumeM3, stats.volumeM3, 1e-4 * stats.volumeM3) << name;
        EXPECT_TRUE(s.closed) << name;
        // World space, metres: inside the block give or take a voxel.
        for (const auto& p : back.vertices)
            for (int a = 0; a < 3; ++a) {
                const double extent = (a == 0 ? 24 : a == 1 ? 16 : 10) * 0.5;
                ASSERT_GT(p[a], -0.5);
                ASSERT_LT(p[a], extent + 0.5);
            }
    }
}

TEST(CaveMeshFiles, ObjNormalsPointOutOfTheCave) {
    const fs::path dir = freshDir("normals");
    Domain d = lChannel(false);
    // A ball of radius 3.5 voxels centred in the block.
    for (int k = 0; k < 10; ++k)
        for (int j = 0; j < 16; ++j)
            for (int i = 0; i < 24; ++i)
                if (std::pow(i + 0.5 - 12, 2) + std::pow(j + 0.5 - 8, 2) + std::pow(k + 0.5 - 5, 2) <= 3.5 * 3.5)
                    d.flags.at(i, j, k) |= kChannel;
    writeCaveMesh(makeCave(d, CaveExtent::kChannels), dir.string());
    std::ifstream in(dir / "cave.obj");
    std::string line;
    std::vector<std::array<double, 3>> v, vn;
    while (std::getline(in, line)) {
        std::istringstream ss(line);
        std::string tag;
        ss >> tag;
        std::array<double, 3> x{};
        if (tag == "v" && ss >> x[0] >> x[1] >> x[2]) v.push_back(x);
        if (tag == "vn" && ss >> x[0] >> x[1] >> x[2]) vn.push_back(x);
    }
    ASSERT_EQ(v.size(), vn.size());
    ASSERT_GT(v.size(), 100u);
    for (std::size_t n = 0; n < v.size(); ++n) {
        const double r[3] = {v[n][0] - 6.0, v[n][1] - 4.0, v[n][2] - 2.5};
        ASSERT_GT(r[0] * vn[n][0] + r[1] * vn[n][1] + r[2] * vn[n][2], 0.0);
    }
}

TEST(CaveMeshFiles, VoxelStyleAlsoWritesTheBlockyMesh) {
    const fs::path dir = freshDir("voxel");
    const Domain d = lChannel();
    MeshOptions o;
    o.style = MeshStyle::kVoxel;
    writeCaveMesh(makeCave(d, CaveExtent::kChannels), dir.string(), o);
    ASSERT_TRUE(fs::exists(dir / "cave_voxels.obj"));
    const MeshStats s = measureMesh(readMeshFile((dir / "cave_voxels.obj").string()));
    EXPECT_NEAR(s.volumeM3, double(caveVoxels(d)) * 0.125, 1e-9);  // exactly the cubes
    EXPECT_TRUE(s.closed);
}

TEST(CaveMeshFiles, EmptyCaveWritesNothing) {
    const fs::path dir = freshDir("empty");
    const MeshStats s = writeCaveMesh(makeCave(lChannel(false), CaveExtent::kChannels), dir.string());
    EXPECT_EQ(s.faces, 0);
    EXPECT_EQ(s.vertices, 0);
    EXPECT_DOUBLE_EQ(s.volumeM3, 0.0);
    EXPECT_EQ(countFiles(dir), 0);
}

TEST(CaveMeshFiles, RejectsBadInput) {
    const fs::path dir = freshDir("bad");
    MeshOptions o;
    o.adaptivity = 2.0;
    EXPECT_THROW(writeCaveMesh(makeCave(lChannel(), CaveExtent::kChannels), dir.string(), o), InternalError);
    EXPECT_THROW(writeCaveMesh(makeCave(lChannel(), CaveExtent::kChannels), (dir / "no" / "such" / "dir").string()),
                 RuntimeError);
    EXPECT_THROW(writeMeshFile(TriangleMesh{}, (dir / "x.stl").string()), InternalError);
    EXPECT_THROW(readMeshFile((dir / "none.obj").string()), RuntimeError);
}

TEST(VoxelMesh, CubesHaveExactAreaAndVolume) {
    Grid3<std::uint8_t> m({3, 2, 2}, 0);
    m.at(0, 0, 0) = m.at(1, 0, 0) = 1;  // a 2×1×1 bar
    const MeshStats s = measureMesh(buildVoxelMesh(m, 2.0));
    EXPECT_DOUBLE_EQ(s.volumeM3, 2 * 8.0);
    EXPECT_DOUBLE_EQ(s.areaM2, 10 * 4.0);
    EXPECT_TRUE(s.closed);
    EXPECT_EQ(s.eulerCharacteristic, 2);
}

TEST(MeasureMesh, DetectsOpenAndInconsistentMeshes) {
    // A tetrahedron, outward.
    TriangleMesh t{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};
    MeshStats s = measureMesh(t);
    EXPECT_TRUE(s.closed);
    EXPECT_EQ(s.eulerCharacteristic, 2);
    EXPECT_NEAR(s.volumeM3, 1.0 / 6.0, 1e-12);
    TriangleMesh flipped = t;
    std::swap(flipped.triangles[0][1], flipped.triangles[0][2]);
    s = measureMesh(flipped);
    EXPECT_FALSE(s.manifold);
    EXPECT_FALSE(s.closed);
    TriangleMesh open = t;
    open.triangles.pop_back();
    s = measureMesh(open);
    EXPECT_TRUE(s.manifold);
    EXPECT_FALSE(s.closed);
    TriangleMesh bad = t;
    bad.triangles[0][0] = 9;
    EXPECT_THROW(measureMesh(bad), InternalError);
}

// --- Pictures -----------------------------------------------------------------------------------

TEST(CavePictures, FourViewsOfTheRequestedWidthShowTheCave) {
    const Domain d = lChannel();
    const int width = 480;
    const auto views = renderCaveViews(makeCave(d, CaveExtent::kChannels), width);
    for (std::size_t v = 0; v < views.size(); ++v) {
        EXPECT_EQ(views[v].width, width) << render::viewStem(kCaveViews[v]);
        EXPECT_GT(pixelVariance(views[v]), 100.0);
        EXPECT_GT(distinctColours(views[v]), 50u);  // shaded, not flat
    }
    // Plan: the channel's top seen at (i, j) = (10, 8) is shaded cave, the rock at (10, 2) is the
    // block's rock tint.
    const render::Frame plan = render::makeFrame(render::View::kPlan, d.dims, d.voxelSize, width, 2);
    const render::Image& img = views[1];
    auto pixel = [&](double x, double y) {
        const auto p = plan.camera.project({x, y, 5.0});
        return img.get(int(p.x), int(p.y));
    };
    const render::Rgb rock = render::mix(render::colours::kRock, render::colours::kWhite, 0.55);
    EXPECT_NE(pixel(10.5 * 0.5, 8.5 * 0.5), rock);
    EXPECT_EQ(pixel(10.5 * 0.5, 2.5 * 0.5), rock);
    // The source is marked in red.
    EXPECT_EQ(pixel(2.5 * 0.5, 8.5 * 0.5), render::colours::kSource);
}

TEST(CavePictures, EmptyCaveStillShowsTheBlock) {
    const auto views = renderCaveViews(makeCave(lChannel(false), CaveExtent::kChannels), 300);
    for (const auto& v : views) {
        EXPECT_EQ(v.width, 300);
        EXPECT_GT(pixelVariance(v), 10.0);
    }
}

TEST(CavePictures, SameForAnyThreadCount) {
    const Domain d = lChannel();
    const auto many = renderCaveViews(makeCave(d, CaveExtent::kChannels), 320);
    std::array<render::Image, 4> one;
    {
        tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
        one = renderCaveViews(makeCave(d, CaveExtent::kChannels), 320);
    }
    for (std::size_t v = 0; v < 4; ++v) EXPECT_EQ(many[v].pixels, one[v].pixels);
}

TEST(CavePictures, WritesFourPngs) {
    const fs::path dir = freshDir("pictures");
    writeCavePictures(makeCave(lChannel(), CaveExtent::kChannels), (dir / "images").string(), 256);
    EXPECT_EQ(countFiles(dir / "images"), 4);
    for (const char* name : {"perspective.png", "plan.png", "side_xz.png", "side_yz.png"}) {
        const render::Image img = render::readPng((dir / "images" / name).string());
        EXPECT_EQ(img.width, 256) << name;
    }
    EXPECT_THROW(writeCavePictures(makeCave(lChannel(), CaveExtent::kChannels), (dir / "images").string(), 10),
                 InternalError);
}

std::string fileBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(CavePictures, SharedLevelSetWritesTheSameFiles) {
    const Domain d = lChannel();
    const fs::path a = freshDir("separate"), b = freshDir("shared");
    const MeshStats sa = writeCaveMesh(makeCave(d, CaveExtent::kChannels), a.string());
    writeCavePictures(makeCave(d, CaveExtent::kChannels), (a / "images").string(), 256);
    const MeshStats sb =
        writeCaveMeshAndPictures(makeCave(d, CaveExtent::kChannels), b.string(), (b / "images").string(), 256);
    EXPECT_EQ(sa.faces, sb.faces);
    EXPECT_DOUBLE_EQ(sa.volumeM3, sb.volumeM3);
    for (const char* name : {"cave.obj", "cave.ply", "images/plan.png", "images/perspective.png", "images/side_xz.png",
                             "images/side_yz.png"})
        EXPECT_EQ(fileBytes(a / name), fileBytes(b / name)) << name;
}

// A 30×1×12 section with a straight channel along x at k = 6, a source before it, a sink after it.
Domain lineSection() {
    Domain d = lChannel(false);
    d.dims = {30, 1, 12};
    d.flags = Grid3<std::uint8_t>(d.dims, 0);
    for (int i = 2; i < 28; ++i) d.flags.at(i, 0, 6) |= kChannel;
    d.sourceVoxels = {{d.dims.index(1, 0, 6)}};
    d.sinkVoxels = {{d.dims.index(29, 0, 6)}};
    return d;
}

TEST(CavePictures, SectionDomainsRender) {
    const Domain d = lineSection();
    const auto views = renderCaveViews(makeCave(d, CaveExtent::kChannels), 400);
    for (const auto& v : views) EXPECT_GT(pixelVariance(v), 100.0);
}

TEST(CavePictures, SectionsGetOnlyTheSectionView) {
    const Domain d = lineSection();
    const fs::path dir = freshDir("section_pictures");
    writeCavePictures(makeCave(d, CaveExtent::kChannels), (dir / "images").string(), 256);
    EXPECT_EQ(countFiles(dir / "images"), 1);
    EXPECT_TRUE(fs::exists(dir / "images" / "side_xz.png"));
}

}  // namespace
}  // namespace cavesim::mesh

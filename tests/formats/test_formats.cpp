// The export writers on the hand-made cave of sample.h: exact answers, tinygltf as the glTF
// reader, error paths. readers.sh/readers.py load the files with other programs' readers.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "formats/csv_formats.h"
#include "formats/exports.h"
#include "formats/gocad_formats.h"
#include "formats/mesh_formats.h"
#include "formats/passages.h"
#include "formats/survey_formats.h"
#include "formats/vtk_formats.h"
#include "mesh/cave_mesh.h"
#include "mesh/vdb_io.h"
#include "sample.h"
#include "sim/cave.h"

namespace cavesim::formats {
namespace {

namespace fs = std::filesystem;

class FormatsTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("cavesim_formats_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    static std::string slurp(const std::string& p) {
        std::ifstream f(p, std::ios::binary);
        return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    }
    fs::path dir_;
    test::Sample s_ = test::makeSample();
};

TEST(FormatSet, ParsesListsAllAndNone) {
    EXPECT_EQ(toString(parseFormatSet("all")), "glb,vtk,stl,svx,th,gocad,csv,vdb");
    EXPECT_EQ(toString(parseFormatSet(" vdb , glb")), "glb,vdb");
    EXPECT_EQ(toString(parseFormatSet("none")), "none");
    EXPECT_TRUE(parseFormatSet("none").empty());
    EXPECT_EQ(toString(parseFormatSet(kDefaultFormats)), "glb,vtk,svx,csv");
    const FormatSet all = parseFormatSet("all");
    EXPECT_EQ(parseFormatSet(toString(all)), all);
}

/// The InputError parseFormatSet(`list`) throws; a test failure when it accepts the list.
std::string formatSetError(const std::string& list) {
    try {
        parseFormatSet(list);
    } catch (const InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << list;
    return "";
}

TEST(FormatSet, NoneStandsAlone) {
    // "all,none" once gave every format and "glb,none" gave glb: none beside others means nothing.
    for (const char* list : {"all,none", "none,glb", "glb, none"}) {
        const std::string e = formatSetError(list);
        EXPECT_NE(e.find("\"none\" stands alone"), std::string::npos) << e;
    }
}

TEST(FormatSet, RefusesAFormatListedTwice) {
    // As the scenario's [output] formats, which must list distinct values.
    for (const char* list : {"glb,glb", "vtk, csv,vtk", "all,glb"}) {
        const std::string e = formatSetError(list);
        EXPECT_NE(e.find("is listed twice"), std::string::npos) << e;
    }
    EXPECT_EQ(formatSetError("glb,glb"),
              "formats \"glb,glb\": \"glb\" is listed twice (give each format once; \"all\" lists every one)");
}

TEST(FormatSet, RejectsUnknownAndEmptyEntries) {
    try {
        parseFormatSet("glb,obj");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("unknown format \"obj\""), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("glb, vtk, stl, svx, th, gocad, csv, vdb, all, none"), std::string::npos);
    }
    EXPECT_THROW(parseFormatSet("glb,,vtk"), InputError);
    EXPECT_THROW(parseFormatSet(""), InputError);
    EXPECT_THROW(parseFormatSet("GLB"), InputError);
}

TEST(Passages, WallDistancesAreExactInTheMask) {
    const Grid3<std::uint8_t> cave = caveMask(test::makeSample().domain, CaveExtent::kChannels);
    // From the main passage's axis (y = 2, z = 1.5) the walls are 0.5 m away across and up/down.
    EXPECT_DOUBLE_EQ(distanceToWall(cave, 0.5, {2.0, 2.0, 1.5}, {0, 1, 0}), 0.5);
    EXPECT_DOUBLE_EQ(distanceToWall(cave, 0.5, {2.0, 2.0, 1.5}, {0, 0, -1}), 0.5);
    EXPECT_DOUBLE_EQ(distanceToWall(cave, 0.5, {2.0, 2.0, 1.5}, {1, 0, 0}), 3.5);   // east end wall x = 5.5
    EXPECT_DOUBLE_EQ(distanceToWall(cave, 0.5, {3.0, 2.0, 1.5}, {0, 1, 0}), 2.0);   // up the side passage to y = 4
    EXPECT_DOUBLE_EQ(distanceToWall(cave, 0.5, {3.0, 0.25, 1.5}, {0, 1, 0}), 0.0);  // starts in rock
    EXPECT_DOUBLE_EQ(distanceToWall(cave, 0.5, {-1.0, 2.0, 1.5}, {1, 0, 0}), 0.0);  // starts outside
    const double r = std::sqrt(0.5);
    EXPECT_NEAR(distanceToWall(cave, 0.5, {2.0, 2.0, 1.5}, {0, r, r}), std::sqrt(0.5), 1e-12);  // edge of the box
    const Lrud l = measureLrud(cave, 0.5, {3.0, 2.0, 1.5}, {1, 0, 0.3});  // heading east: left is north
    EXPECT_DOUBLE_EQ(l.left, 2.0);
    EXPECT_DOUBLE_EQ(l.right, 0.5);
    EXPECT_DOUBLE_EQ(l.up, 0.5);
    EXPECT_DOUBLE_EQ(l.down, 0.5);
    const Lrud v = measureLrud(cave, 0.5, {3.0, 2.0, 1.5}, {0, 0, 1});  // vertical: taken as north, left −x
    EXPECT_DOUBLE_EQ(v.left, 2.5);
    EXPECT_DOUBLE_EQ(v.right, 2.5);
}

TEST(Passages, LegReadingsAndStationNames) {
    LegReading east = legReading({0, 0, 0}, {2, 0, 0});
    EXPECT_DOUBLE_EQ(east.tape, 2.0);
    EXPECT_DOUBLE_EQ(east.compass, 90.0);
    EXPECT_DOUBLE_EQ(east.clino, 0.0);
    LegReading sw = legReading({0, 0, 0}, {-1, -1, std::sqrt(2.0)});
    EXPECT_DOUBLE_EQ(sw.compass, 225.0);
    EXPECT_NEAR(sw.clino, 45.0, 1e-12);
    LegReading north = legReading({0, 0, 0}, {0, 1, 0});
    EXPECT_DOUBLE_EQ(north.compass, 0.0);
    LegReading up = legReading({1, 1, 1}, {1, 1, 3});
    EXPECT_TRUE(up.plumbed);
    EXPECT_DOUBLE_EQ(up.clino, 90.0);

    const test::Sample s = test::makeSample();
    const auto passages = findPassages(s.skeleton);
    ASSERT_EQ(passages.size(), 3u);
    const auto names = stationNames(s.skeleton, passages);
    EXPECT_EQ(names[0], "p0.0");
    EXPECT_EQ(names[2], "p0.2");  // the junction keeps its first passage's name
    EXPECT_EQ(names[4], "p1.2");
    EXPECT_EQ(names[6], "p2.2");
}

TEST_F(FormatsTest, GlbLoadsInTinygltfRotatedToYUp) {
    for (NormalSide side : {NormalSide::kOutward, NormalSide::kInward}) {
        GlbOptions o;
        o.normals = side;
        writeGlb(s_.box, path("cave.glb"), o);
        tinygltf::TinyGLTF loader;
        tinygltf::Model m;
        std::string err, warn;
        ASSERT_TRUE(loader.LoadBinaryFromFile(&m, &err, &warn, path("cave.glb"))) << err;
        EXPECT_TRUE(err.empty() && warn.empty()) << err << warn;
        EXPECT_EQ(m.asset.version, "2.0");
        ASSERT_EQ(m.meshes.size(), 1u);
        const tinygltf::Primitive& prim = m.meshes[0].primitives[0];
        const tinygltf::Accessor& pos = m.accessors[std::size_t(prim.attributes.at("POSITION"))];
        const tinygltf::Accessor& nor = m.accessors[std::size_t(prim.attributes.at("NORMAL"))];
        const tinygltf::Accessor& idx = m.accessors[std::size_t(prim.indices)];
        EXPECT_EQ(pos.count, 8u);
        EXPECT_EQ(idx.count, 36u);
        // Box [0,1] × [0,2] × [0,3] (z up) → x [0,1], y [0,3], z [−2,0] (y up).
        EXPECT_EQ(pos.minValues, (std::vector<double>{0, 0, -2}));
        EXPECT_EQ(pos.maxValues, (std::vector<double>{1, 3, 0}));
        auto data = [&m](const tinygltf::Accessor& a) {
            const tinygltf::BufferView& v = m.bufferViews[std::size_t(a.bufferView)];
            return m.buffers[std::size_t(v.buffer)].data.data() + v.byteOffset + a.byteOffset;
        };
        std::vector<float> p(24), n(24);
        std::vector<std::uint32_t> t(36);
        std::memcpy(p.data(), data(pos), 96);
        std::memcpy(n.data(), data(nor), 96);
        std::memcpy(t.data(), data(idx), 144);
        // Vertex 6 = (1, 2, 3) → (1, 3, −2); its outward normal (1, 1, 1)/√3 → (1, 1, −1)/√3.
        EXPECT_EQ(p[18], 1.f);
        EXPECT_EQ(p[19], 3.f);
        EXPECT_EQ(p[20], -2.f);
        const float sgn = side == NormalSide::kInward ? -1.f : 1.f;
        EXPECT_FLOAT_EQ(n[18], sgn / std::sqrt(3.f));
        EXPECT_FLOAT_EQ(n[20], -sgn / std::sqrt(3.f));
        // Every triangle's winding agrees with the normals' side: the face normal points away
        // from the box centre (0.5, 1.5, −1) when outward, towards it when inward.
        for (int f = 0; f < 12; ++f) {
            std::array<float, 3> v[3];
            for (int c = 0; c < 3; ++c) v[c] = {p[3 * t[3 * f + c]], p[3 * t[3 * f + c] + 1], p[3 * t[3 * f + c] + 2]};
            const auto fn = faceNormal(v[0], v[1], v[2]);
            const float out = fn[0] * (v[0][0] - 0.5f) + fn[1] * (v[0][1] - 1.5f) + fn[2] * (v[0][2] + 1.f);
            EXPECT_GT(sgn * out, 0.f) << "triangle " << f;
        }
    }
}

TEST_F(FormatsTest, StlIsBinaryWithFaceNormals) {
    writeStl(s_.box, path("cave.stl"));
    const std::string b = slurp(path("cave.stl"));
    ASSERT_EQ(b.size(), 84u + 50u * 12u);
    EXPECT_EQ(b.substr(0, 13), "cavesim cave:");
    std::uint32_t count = 0;
    std::memcpy(&count, b.data() + 80, 4);
    EXPECT_EQ(count, 12u);
    float first[12];
    std::memcpy(first, b.data() + 84, 48);
    EXPECT_EQ(first[0], 0.f);  // triangle (0, 2, 1) is the bottom: normal −z
    EXPECT_EQ(first[1], 0.f);
    EXPECT_EQ(first[2], -1.f);
    EXPECT_EQ(first[9], 1.f);  // its third vertex is vertex 1 = (1, 0, 0)
}

TEST_F(FormatsTest, GocadTSurfAndPLine) {
    writeGocadTSurf(s_.box, path("cave.ts"));
    const std::string ts = slurp(path("cave.ts"));
    EXPECT_EQ(ts.rfind("GOCAD TSurf 1\nHEADER {\nname: cave\n}\n", 0), 0u);
    EXPECT_NE(ts.find("TFACE\nVRTX 1 0 0 0\nVRTX 2 1 0 0\n"), std::string::npos);
    EXPECT_NE(ts.find("TRGL 1 3 2\n"), std::string::npos);
    EXPECT_EQ(ts.substr(ts.size() - 4), "END\n");
    writeGocadPLine(s_.skeleton, path("skeleton.pl"), &s_.domain);
    const std::string pl = slurp(path("skeleton.pl"));
    EXPECT_NE(pl.find("PROPERTIES radius passage_id flow pressure\n"), std::string::npos);
    EXPECT_NE(pl.find("ILINE\nPVRTX 1 1 2 1.5 0.5 0 2 0.25\n"), std::string::npos);
    EXPECT_NE(pl.find("SEG 6 7\nEND\n"), std::string::npos);
}

TEST_F(FormatsTest, SurvexAndTherionText) {
    const Grid3<std::uint8_t> cave = caveMask(s_.domain, CaveExtent::kChannels);
    writeSurvex(s_.skeleton, cave, 0.5, path("cave.svx"));
    const std::string svx = slurp(path("cave.svx"));
    for (const char* line : {"*begin cave\n", "*units tape metres\n", "*fix p0.0 1.0000 2.0000 1.5000\n",
                             "*data normal from to tape compass clino\np0.0 p0.1 1.0000 90.000 0.000\n",
                             "*data passage station left right up down\np0.0 0.500 0.500 0.500 0.500\n",
                             "p0.2 p2.1 1.0000 0.000 0.000\n", "p0.2 2.500 2.500 0.500 0.500\n", "*end cave\n"})
        EXPECT_NE(svx.find(line), std::string::npos) << line;
    writeTherion(s_.skeleton, cave, 0.5, path("cave.th"));
    const std::string th = slurp(path("cave.th"));
    for (const char* line :
         {"encoding utf-8\n", "survey cave -title \"cavesim cave\"\n", "    fix p0_0 1.0000 2.0000 1.5000\n",
          "    data normal from to length compass clino\n    p0_0 p0_1 1.0000 90.000 0.000\n",
          "    data dimensions station left right up down\n", "  endcentreline\nendsurvey\n"})
        EXPECT_NE(th.find(line), std::string::npos) << line;
    // A vertical leg: compass omitted, clino "up".
    morpho::Skeleton shaft;
    shaft.nodes.resize(2);
    shaft.nodes[0].position = {1, 2, 1.25};
    shaft.nodes[1].position = {1, 2, 1.75};
    shaft.edges = {{0, 1}};
    writeSurvex(shaft, cave, 0.5, path("shaft.svx"));
    EXPECT_NE(slurp(path("shaft.svx")).find("p0.0 p0.1 0.5000 - up\n"), std::string::npos);
    SurveyOptions bad;
    bad.name = "my cave";
    EXPECT_THROW(writeSurvex(s_.skeleton, cave, 0.5, path("x.svx"), bad), RuntimeError);
    EXPECT_THROW(writeSurvex(morpho::Skeleton{}, cave, 0.5, path("x.svx")), RuntimeError);
}

TEST_F(FormatsTest, CsvTables) {
    writeHistoryCsv(s_.stage2.history, path("history.csv"));
    EXPECT_EQ(slurp(path("history.csv")),
              "iteration,injected,drained,stored,flow,eroded,channel_voxels,pressure_updates,sources_connected,"
              "balance_error\n"
              "1,1.5,0.25,11,0.1,0.125,41,7,0,1e-12\n2,3,0.25,12,0.2,0.125,42,7,1,1e-12\n"
              "3,4.5,0.25,13,0.30000000000000004,0.125,43,7,1,1e-12\n");

    // Flow paths: source 0 runs west → east along the main passage to a sink; source 1 comes down
    // the side passage and is captured at the junction (node 2).
    morpho::NetworkCounts net;
    morpho::FlowPath a, b;
    a.source = 0;
    a.sink = 0;
    a.nodes = {0, 1, 2, 3, 4};
    a.loopTroughs = {3};
    b.source = 1;
    b.sink = 0;
    b.nodes = {6, 5, 2, 3, 4};
    b.capturedBy = 0;
    b.joinNode = 2;
    net.paths = {a, b};
    const auto rows = branchRows(s_.skeleton, caveMask(s_.domain, CaveExtent::kChannels), 0.5, &s_.domain.flow, &net);
    ASSERT_EQ(rows.size(), 3u);
    // Passage 0: nodes 0, 1, 2 along x; widths 1, 1 and 2.5 (the junction opens north); height 1.
    EXPECT_EQ(rows[0].fromNode, 0);
    EXPECT_EQ(rows[0].toNode, 2);
    EXPECT_DOUBLE_EQ(rows[0].length_m, 2.0);
    EXPECT_DOUBLE_EQ(rows[0].meanWidth_m, 1.5);
    EXPECT_DOUBLE_EQ(rows[0].meanHeight_m, 1.0);
    EXPECT_DOUBLE_EQ(*rows[0].azimuth_deg, 90.0);  // horizontal: the azimuth in [0, 180)
    EXPECT_DOUBLE_EQ(*rows[0].dip_deg, 0.0);
    EXPECT_DOUBLE_EQ(*rows[0].meanFlow, 4.0);  // flow = i at voxels i = 2, 4, 6
    EXPECT_EQ(rows[0].role, "main");
    EXPECT_EQ(rows[1].role, "main");
    EXPECT_EQ(rows[1].loopTroughs, 1);
    EXPECT_EQ(rows[2].role, "tributary");
    EXPECT_DOUBLE_EQ(*rows[2].azimuth_deg, 0.0);
    writeBranchesCsv(rows, path("branches.csv"));
    const std::string csv = slurp(path("branches.csv"));
    EXPECT_NE(csv.find("\n0,0,2,3,2,2,0.5,1.5,1,90,0,4,main,0\n"), std::string::npos) << csv;
    // Without a network: no role; an inclined branch plunges.
    morpho::Skeleton tilt;
    tilt.nodes.resize(2);
    tilt.nodes[0].position = {1, 2, 1.9};
    tilt.nodes[1].position = {2, 2, 1.1};
    tilt.edges = {{0, 1}};
    const auto t = branchRows(tilt, caveMask(s_.domain, CaveExtent::kChannels), 0.5);
    EXPECT_EQ(t[0].role, "");
    EXPECT_FALSE(t[0].meanFlow);
    EXPECT_DOUBLE_EQ(*t[0].azimuth_deg, 90.0);
    EXPECT_NEAR(*t[0].dip_deg, std::atan2(0.8, 1.0) * 180.0 / M_PI, 1e-12);
}

TEST_F(FormatsTest, VtkXmlHeaders) {
    const Cave cave = makeCave(s_.domain, CaveExtent::kChannels);
    writeStateVti(s_.domain, path("state.vti"), &cave);
    const std::string vti = slurp(path("state.vti"));
    EXPECT_NE(vti.find("<ImageData WholeExtent=\"0 12 0 8 0 6\" Origin=\"0 0 0\" Spacing=\"0.5 0.5 0.5\">"),
              std::string::npos);
    // Offsets: 576 float32 values = 2304 bytes + an 8-byte header per array.
    EXPECT_NE(vti.find("Name=\"porosity0\" NumberOfComponents=\"1\" format=\"appended\" offset=\"2312\""),
              std::string::npos);
    EXPECT_NE(vti.find("type=\"UInt8\" Name=\"cave\""), std::string::npos);
    writeSkeletonVtp(s_.skeleton, path("skeleton.vtp"));  // without a domain: no flow or pressure
    const std::string vtp = slurp(path("skeleton.vtp"));
    EXPECT_NE(vtp.find("NumberOfPoints=\"7\" NumberOfVerts=\"0\" NumberOfLines=\"3\""), std::string::npos);
    EXPECT_EQ(vtp.find("Name=\"flow\""), std::string::npos);
}

TEST_F(FormatsTest, FailedWritesNameTheFile) {
    const std::string bad = path("missing/cave.stl");
    try {
        writeStl(s_.box, bad);
        FAIL();
    } catch (const RuntimeError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("cannot write " + bad + ": ", 0), 0u) << e.what();
        EXPECT_NE(std::string(e.what()).find("No such file or directory"), std::string::npos) << e.what();
    }
    EXPECT_THROW(writeHistoryCsv({}, path("missing/history.csv")), RuntimeError);
    EXPECT_THROW(writeStateVti(s_.domain, path("missing/state.vti")), RuntimeError);
    EXPECT_THROW(mesh::writeExportVdb(path("missing/cave.vdb"), s_.domain, makeCave(s_.domain, CaveExtent::kChannels)),
                 RuntimeError);
    EXPECT_THROW(writeGlb(SurfaceMesh{}, path("cave.glb")), RuntimeError);
    EXPECT_THROW(writeExports({}, path("missing"), parseFormatSet("all")), RuntimeError);
    EXPECT_TRUE(fs::is_empty(dir_));  // no temporary left behind
}

TEST_F(FormatsTest, WriteExportsSkipsWhatItHasNoInputFor) {
    ExportInputs in;
    in.skeleton = &s_.skeleton;
    in.mesh = &s_.box;
    EXPECT_EQ(writeExports(in, dir_.string(), parseFormatSet("all")),
              (std::vector<std::string>{"cave.glb", "skeleton.vtp", "cave.stl", "cave.ts", "skeleton.pl"}));
    in.domain = &s_.domain;
    in.stage2 = &s_.stage2;
    EXPECT_EQ(
        writeExports(in, dir_.string(), parseFormatSet(kDefaultFormats)),
        (std::vector<std::string>{"cave.glb", "state.vti", "skeleton.vtp", "cave.svx", "history.csv", "branches.csv"}));
}

TEST_F(FormatsTest, CaveMeshAndVdbExport) {
    const Cave cave = makeCave(s_.domain, CaveExtent::kChannels);
    const SurfaceMesh m = mesh::buildCaveSurfaceMesh(cave);
    ASSERT_FALSE(m.triangles.empty());
    ASSERT_EQ(m.normals.size(), m.vertices.size());
    // Bounds: the cave voxels' box (the side passage reaches the block face y = 4), give or take
    // the smoothing; normals unit and, at the top of the passage, pointing up (out of the cave).
    float lo[3] = {1e9f, 1e9f, 1e9f}, hi[3] = {-1e9f, -1e9f, -1e9f};
    for (std::size_t v = 0; v < m.vertices.size(); ++v) {
        for (int c = 0; c < 3; ++c) {
            lo[c] = std::min(lo[c], m.vertices[v][c]);
            hi[c] = std::max(hi[c], m.vertices[v][c]);
        }
        const auto& n = m.normals[v];
        EXPECT_NEAR(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 1.0, 1e-5);
        if (m.vertices[v][2] > 2.0f && std::abs(m.vertices[v][0] - 2.0f) < 0.3f) { EXPECT_GT(n[2], 0.5f); }
    }
    EXPECT_NEAR(lo[0], 0.5, 0.1);
    EXPECT_NEAR(hi[0], 5.5, 0.1);
    EXPECT_NEAR(lo[2], 1.0, 0.1);
    EXPECT_NEAR(hi[2], 2.0, 0.1);
    // The same mesh as writeCaveMesh's.
    SurfaceMesh built;
    mesh::writeCaveMesh(cave, dir_.string(), {}, &built);
    EXPECT_EQ(built.vertices, m.vertices);
    EXPECT_EQ(built.triangles, m.triangles);
    // cave.vdb: same domain, same bytes.
    mesh::writeExportVdb(path("a.vdb"), s_.domain, cave);
    mesh::writeExportVdb(path("b.vdb"), s_.domain, cave);
    EXPECT_EQ(slurp(path("a.vdb")), slurp(path("b.vdb")));
    EXPECT_EQ(mesh::readVdbFloat(path("a.vdb"), "flags", s_.domain.dims).at(3, 3, 2), 8.f);
    EXPECT_EQ(mesh::readVdbFloat(path("a.vdb"), "zone", s_.domain.dims).at(0, 0, 0), -1.f);
}

}  // namespace

TEST(FormatSet, DefaultListMatchesTheScenarioDefault) {
    EXPECT_EQ(toString(formatSet(OutputOptions{}.formats)), kDefaultFormats);
    EXPECT_EQ(formatList(parseFormatSet("all")).size(), 8u);
    EXPECT_EQ(formatSet(formatList(parseFormatSet("svx,glb"))), parseFormatSet("glb,svx"));
}

}  // namespace cavesim::formats

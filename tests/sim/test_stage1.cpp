// Stage 1: zone sizes against the bisector and the Apollonius sphere, protochannel trees inside
// their zones and rooted at their sources, thread-count independence, reproducible clusters, 2D
// sections, box sources, the memory limit, degenerate domains, and the [stage1] keys.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <deque>
#include <string>

#include "core/error.h"
#include "sim/connectivity.h"
#include "sim/domain.h"
#include "sim/scenario_io.h"
#include "sim/simulate.h"
#include "sim/stage1.h"
#include "sim/stage2.h"

using namespace cavesim;

namespace {

struct Stage1Run {
    Domain domain;
    Stage1Result result;
};

Stage1Run runStage1On(const Scenario& s) {
    Rng rng(s.seed);
    Stage1Run r{buildDomain(s, rng), {}};
    r.result = runStage1(r.domain, s.stage1, rng);
    return r;
}

Stage1Run runText(const std::string& text) {
    return runStage1On(parseScenarioString(text, "test.toml"));
}

std::string header(const std::string& name, int nx, int ny, int nz, int seed = 3) {
    return "name = \"" + name + "\"\nseed = " + std::to_string(seed) + "\n[domain]\nsize = [" + std::to_string(nx) +
           ", " + std::to_string(ny) + ", " + std::to_string(nz) + "]\n";
}

const char* kNoStage2 = "[stage2]\nenabled = false\n";

/// Every protochannel voxel lies in a zone and is joined, through 26-neighbour protochannel
/// voxels of that zone, to a source voxel of that zone.
void expectTreesInsideZones(const Domain& d) {
    const Dims& D = d.dims;
    std::vector<std::uint8_t> reached(D.count(), 0);
    for (std::size_t z = 0; z < d.sourceVoxels.size(); ++z) {
        std::deque<std::size_t> queue;
        for (std::size_t v : d.sourceVoxels[z])
            if (d.zone[v] == int(z)) {
                reached[v] = 1;
                queue.push_back(v);
            }
        while (!queue.empty()) {
            const Index3 p = D.coord(queue.front());
            queue.pop_front();
            for (const auto& o : allNeighbours()) {
                if (!D.contains(p.i + o.di, p.j + o.dj, p.k + o.dk)) continue;
                const std::size_t w = D.index(p.i + o.di, p.j + o.dj, p.k + o.dk);
                if (reached[w] || d.zone[w] != int(z) || !(d.flags[w] & kProtochannel)) continue;
                reached[w] = 1;
                queue.push_back(w);
            }
        }
    }
    long unreached = 0;
    for (std::size_t v = 0; v < D.count(); ++v) {
        if (!(d.flags[v] & kProtochannel)) continue;
        EXPECT_GE(d.zone[v], 0);
        EXPECT_FALSE(d.flags[v] & (kSource | kSink)) << "voxel " << v;
        const Index3 p = D.coord(v);  // never next to another zone: channels of two zones never touch
        for (const auto& o : faceNeighbours())
            if (D.contains(p.i + o.di, p.j + o.dj, p.k + o.dk)) {
                const int z = d.zone.at(p.i + o.di, p.j + o.dj, p.k + o.dk);
                EXPECT_TRUE(z == d.zone[v] || z < 0) << "voxel " << v;
            }
        if (!reached[v]) ++unreached;
    }
    EXPECT_EQ(unreached, 0) << "protochannel voxels not connected to their source";
}

long countFlag(const Domain& d, std::uint8_t flag) {
    long n = 0;
    for (auto f : d.flags.data) n += (f & flag) != 0;
    return n;
}

}  // namespace

TEST(Stage1, EqualPressuresSplitOnTheBisector) {
    const Stage1Run r =
        runText(header("eq", 40, 20, 16) + "[[source]]\nat = [10, 10, 8]\n[[source]]\nat = [29, 10, 8]\n" + kNoStage2);
    ASSERT_EQ(r.result.zones, 2);
    const long a = r.result.zoneVoxels[0], b = r.result.zoneVoxels[1];
    EXPECT_EQ(a + b, 40L * 20 * 16);
    EXPECT_LE(std::abs(a - b), 0.05 * std::max(a, b)) << a << " vs " << b;
    EXPECT_EQ(a, b);  // the block and the sources are mirror-symmetric about x = 19.5
    const Dims& D = r.domain.dims;
    for (std::size_t v = 0; v < D.count(); ++v) {
        const int i = D.coord(v).i;
        if (i <= 18) {
            EXPECT_EQ(r.domain.zone[v], 0);
        }
        if (i >= 21) {
            EXPECT_EQ(r.domain.zone[v], 1);
        }
    }
}

TEST(Stage1, PressureRatioTwoGivesTheApolloniusSphere) {
    // Uniform rock, pressures 2 : 1. The weak source B keeps the points twice as far from A as
    // from B: |x − A| > 2 |x − B|, a sphere of radius 2D/3 around B + (B − A)/3 (D = 29).
    const Stage1Run r = runText(header("ratio", 60, 40, 20) +
                                "[[source]]\nat = [15, 20, 10]\npressure = 2.0\n[[source]]\nat = [44, 20, 10]\n"
                                "pressure = 1.0\n[stage1]\npermeability = \"uniform\"\n" +
                                kNoStage2);
    const Dims& D = r.domain.dims;
    long analytic = 0, agree = 0;
    for (std::size_t v = 0; v < D.count(); ++v) {
        const Index3 p = D.coord(v);
        const double da = std::hypot(p.i - 15.0, p.j - 20.0, p.k - 10.0);
        const double db = std::hypot(p.i - 44.0, p.j - 20.0, p.k - 10.0);
        const int expected = da > 2 * db ? 1 : 0;
        analytic += expected;
        agree += r.domain.zone[v] == expected;
    }
    const long strong = r.result.zoneVoxels[0], weak = r.result.zoneVoxels[1];
    // First-order fast marching from a point overestimates distances by a few per cent, more off
    // the grid axes, so the discrete sphere is slightly smaller; they differ only in a thin shell.
    EXPECT_NEAR(double(weak), double(analytic), 0.06 * analytic);
    EXPECT_GE(double(agree), 0.97 * double(D.count()));
    const double ratio = double(strong) / double(weak);
    EXPECT_GT(ratio, 2.0);
    RecordProperty("zone_ratio_strong_over_weak", std::to_string(ratio));
    std::printf("[ stage 1 ] pressure 2:1 zone voxels %ld : %ld (ratio %.2f), Apollonius sphere in the block %ld\n",
                strong, weak, ratio, analytic);
}

TEST(Stage1, ShippedFigure5ScenariosMeetTheirTargets) {
    const std::string dir = std::string(CAVESIM_SOURCE_DIR) + "/scenarios/";
    const Scenario eq = parseScenarioFile(dir + "fig05_equal.toml");
    const Scenario r2 = parseScenarioFile(dir + "fig05_ratio2.toml");
    EXPECT_FALSE(eq.stage2.enabled);
    EXPECT_FALSE(r2.stage2.enabled);
    const auto counts = [](const Scenario& s) {
        Rng rng(s.seed);
        const Domain d = buildDomain(s, rng);
        const Grid3<std::int32_t> zone = pressureZones(d, s.stage1.permeability);
        std::vector<long> n(2, 0);
        for (auto z : zone.data) ++n[std::size_t(z)];
        return n;
    };
    const auto a = counts(eq);
    EXPECT_LT(std::abs(a[0] - a[1]), 0.05 * std::max(a[0], a[1])) << a[0] << " vs " << a[1];
    const auto b = counts(r2);
    EXPECT_GT(double(b[0]) / double(b[1]), 2.0) << b[0] << " vs " << b[1];
    std::printf("[ stage 1 ] fig05_equal zones %ld : %ld; fig05_ratio2 zones %ld : %ld (ratio %.2f)\n", a[0], a[1],
                b[0], b[1], double(b[0]) / double(b[1]));
    const Scenario f6 = parseScenarioFile(dir + "fig06.toml");
    EXPECT_FALSE(f6.stage2.enabled);
    EXPECT_EQ(f6.sources.size(), 6u);
}

const std::string kThreeSources = header("three", 36, 24, 14, 9) +
                                  "[rock]\nporosity = 0.05\nnoise = { amplitude = 0.02, scale = 5.0 }\n"
                                  "[[rock.sphere]]\ncenter = [18, 12, 6]\nradius = 4\n"
                                  "[[source]]\nat = [6, 6, 10]\n[[source]]\nat = [30, 8, 9]\npressure = 1.5\n"
                                  "[[source]]\nbox = [[16, 19, 10], [17, 20, 11]]\n"
                                  "[[sink]]\nbox = [[33, 20, 0], [35, 23, 2]]\n" +
                                  kNoStage2;

TEST(Stage1, ProtochannelsAreTreesInsideTheirZones) {
    const Stage1Run r = runText(kThreeSources);
    const Domain& d = r.domain;
    ASSERT_EQ(r.result.zones, 3);
    long total = 0;
    for (long n : r.result.zoneVoxels) total += n;
    EXPECT_EQ(total, long(d.dims.count()));
    EXPECT_EQ(r.result.protochannelVoxels, countFlag(d, kProtochannel));
    ASSERT_EQ(r.result.perZone.size(), 3u);
    for (std::size_t z = 0; z < 3; ++z) {
        const ZoneStats& s = r.result.perZone[z];
        EXPECT_EQ(s.source, int(z));
        EXPECT_EQ(s.voxels, r.result.zoneVoxels[z]);
        EXPECT_GT(s.protochannelVoxels, 10);
        EXPECT_GT(s.branches, 1);
        EXPECT_GT(s.maxFlow, 0);
        EXPECT_GT(s.graphEdges, s.graphNodes);
        EXPECT_GT(s.graphBytes, 100 * s.graphNodes);
        EXPECT_GT(s.protosinks, 0);
        EXPECT_LE(s.protosinksWithFlow, s.protosinks);
    }
    // Sinks and the rock within `sink_gap` (2) of them are not part of stage 1's networks.
    long nearSink = 0;
    for (std::size_t v = 0; v < d.dims.count(); ++v) {
        if (d.zone[v] != 1 || (d.flags[v] & kSource)) continue;
        const Index3 p = d.dims.coord(v);
        bool near = false;
        for (const auto& sink : d.sinkVoxels)
            for (std::size_t w : sink) {
                const Index3 q = d.dims.coord(w);
                near = near || std::max({std::abs(p.i - q.i), std::abs(p.j - q.j), std::abs(p.k - q.k)}) <= 2;
            }
        nearSink += near;
    }
    EXPECT_GT(nearSink, 0);
    EXPECT_EQ(r.result.perZone[1].graphNodes, r.result.perZone[1].voxels - nearSink);
    expectTreesInsideZones(d);
    // Stage 1 leaves porosity alone; the display erosion is a view: max(R0, 0.35) on
    // protochannels, untouched elsewhere.
    const Grid3<float> shown = stage1DisplayPorosity(d, 0.35);
    for (std::size_t v = 0; v < d.dims.count(); ++v) {
        EXPECT_EQ(d.porosity[v], d.porosity0[v]);
        if (d.flags[v] & kProtochannel) {
            EXPECT_EQ(shown[v], std::max(d.porosity0[v], 0.35f));
        } else {
            EXPECT_EQ(shown[v], d.porosity0[v]);
        }
    }
}

TEST(Stage1, SameResultForOneAndTwoThreads) {
    const Scenario s = parseScenarioString(kThreeSources, "three.toml");
    Stage1Run one, two;
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
        one = runStage1On(s);
    }
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
        two = runStage1On(s);
    }
    EXPECT_EQ(one.domain.zone.data, two.domain.zone.data);
    EXPECT_EQ(one.domain.flags.data, two.domain.flags.data);
    EXPECT_EQ(one.domain.porosity.data, two.domain.porosity.data);
    ASSERT_EQ(one.result.perZone.size(), two.result.perZone.size());
    for (std::size_t z = 0; z < one.result.perZone.size(); ++z) {
        EXPECT_EQ(one.result.perZone[z].maxFlow, two.result.perZone[z].maxFlow);
        EXPECT_EQ(one.result.perZone[z].protochannelVoxels, two.result.perZone[z].protochannelVoxels);
        EXPECT_EQ(one.result.perZone[z].graphBytes, two.result.perZone[z].graphBytes);
    }
}

TEST(Stage1, ClusteredProtosinksAreReproducibleForASeed) {
    const std::string text = header("clu", 40, 30, 12, 21) +
                             "[rock]\nnoise = { amplitude = 0.02, scale = 5.0 }\n[[source]]\nat = [20, 15, 6]\n"
                             "[stage1]\nprotosinks = \"clustered\"\nclusters = 3\ncluster_radius = 2.0\n" +
                             kNoStage2;
    Scenario s = parseScenarioString(text, "clu.toml");
    const Stage1Run a = runStage1On(s), b = runStage1On(s);
    EXPECT_EQ(a.domain.flags.data, b.domain.flags.data);
    EXPECT_EQ(a.result.perZone[0].protosinks, b.result.perZone[0].protosinks);
    EXPECT_LE(a.result.perZone[0].protosinks, 3 * 13);  // three discs of radius 2 on the boundary
    expectTreesInsideZones(a.domain);
    s.seed = 22;
    const Stage1Run c = runStage1On(s);
    EXPECT_NE(a.domain.flags.data, c.domain.flags.data);

    // Aimed: the protochannels reach the boundary next to the aim point.
    Scenario aimed = parseScenarioString(text + "", "clu.toml");
    aimed.stage1.aim = {{39, 29, 6}};
    const Stage1Run t = runStage1On(aimed);
    double nearest = 1e9;
    for (std::size_t v = 0; v < t.domain.dims.count(); ++v)
        if (t.domain.flags[v] & kProtochannel) {
            const Index3 p = t.domain.dims.coord(v);
            nearest = std::min(nearest, std::hypot(p.i - 39.0, p.j - 29.0, p.k - 6.0));
        }
    EXPECT_LE(nearest, 2.0 + 1.5);  // cluster radius plus the unmarked protosink layer
    expectTreesInsideZones(t.domain);
}

TEST(Stage1, TwoDimensionalSection) {
    const Stage1Run r = runText(header("sec", 60, 1, 30, 4) +
                                "[rock]\nnoise = { amplitude = 0.02, scale = 5.0 }\n"
                                "[[source]]\nat = [15, 0, 25]\n[[source]]\nat = [45, 0, 25]\n" +
                                kNoStage2);
    EXPECT_EQ(r.result.zones, 2);
    EXPECT_GT(r.result.protochannelVoxels, 20);
    expectTreesInsideZones(r.domain);
}

TEST(Stage1, BoxSourceRootsTheTree) {
    const Stage1Run r = runText(header("box", 30, 30, 20, 5) +
                                "[rock]\nnoise = { amplitude = 0.02, scale = 5.0 }\n"
                                "[[source]]\nbox = [[13, 13, 9], [15, 15, 11]]\n" +
                                kNoStage2);
    EXPECT_EQ(r.result.zones, 1);
    EXPECT_GT(r.result.protochannelVoxels, 20);
    expectTreesInsideZones(r.domain);
}

TEST(Stage1, ZoneLargerThanTheLimitIsAnInputError) {
    const std::string text =
        header("big", 20, 20, 10) + "[[source]]\nat = [5, 5, 5]\n[stage1]\nmax_graph_voxels = 1000\n" + kNoStage2;
    try {
        runText(text);
        FAIL() << "no error";
    } catch (const Stage1LimitError& e) {
        // Where in the scenario (file, line, key) is added by the application layer (tests/app).
        const std::string m = e.what();
        EXPECT_EQ(e.source, 0);
        EXPECT_NE(m.find("source 1"), std::string::npos) << m;
        EXPECT_NE(m.find("4,000 voxels"), std::string::npos) << m;
        EXPECT_NE(m.find("limit of 1,000"), std::string::npos) << m;
    }
}

TEST(Stage1, NoBoundaryMeansNoProtochannels) {
    const Stage1Run r =
        runText(header("alone", 12, 10, 8) + "[[source]]\nat = [5, 5, 4]\n[stage1]\nboundary_faces = []\n" + kNoStage2);
    EXPECT_EQ(r.result.zones, 1);
    EXPECT_EQ(r.result.protochannelVoxels, 0);
    EXPECT_EQ(r.result.perZone[0].protosinks, 0);
    EXPECT_EQ(r.result.perZone[0].maxFlow, 0.0);
}

TEST(Stage1, DegenerateDomains) {
    const Stage1Run one = runText(header("one", 1, 1, 1) + "[[source]]\nat = [0, 0, 0]\n" + kNoStage2);
    EXPECT_EQ(one.result.zones, 1);
    EXPECT_EQ(one.result.protochannelVoxels, 0);
    const Stage1Run two = runText(header("two", 2, 1, 1) +
                                  "[[source]]\nat = [0, 0, 0]\n[stage1]\nboundary_faces = [\"+x\"]\n" + kNoStage2);
    EXPECT_EQ(two.result.protochannelVoxels, 0);  // the only other voxel is the protosink
    EXPECT_GT(two.result.perZone[0].maxFlow, 0.0);
    // Impermeable rock everywhere: no link has capacity, nothing flows (the fronts move
    // uniformly when there is no porosity at all to scale them).
    const Stage1Run tight =
        runText(header("tight", 8, 8, 8) + "[rock]\nporosity = 0.0\n[[source]]\nat = [4, 4, 4]\n" + kNoStage2);
    EXPECT_EQ(tight.result.zoneVoxels[0], 512);
    EXPECT_EQ(tight.result.perZone[0].maxFlow, 0.0);
    EXPECT_EQ(tight.result.protochannelVoxels, 0);
    // An impermeable wall (porosity 0 where the obstacle's core is): fronts do not cross it.
    const Stage1Run wall = runText(header("wall", 9, 1, 9) +
                                   "[[rock.sphere]]\ncenter = [4, 0, 4]\nradius = 0.9\ncore_porosity = 0.0\n"
                                   "[[source]]\nat = [0, 0, 4]\n[[source]]\nat = [8, 0, 4]\n" +
                                   kNoStage2);
    EXPECT_EQ(wall.domain.zone.at(4, 0, 4), -1);
    EXPECT_EQ(wall.result.zoneVoxels[0] + wall.result.zoneVoxels[1], 80);
    // Stage 1 with sources only on the domain's edge, thin slab.
    const Stage1Run slab =
        runText(header("slab", 30, 2, 1) + "[[source]]\nat = [0, 0, 0]\n[[source]]\nat = [29, 1, 0]\n" + kNoStage2);
    EXPECT_EQ(slab.result.zones, 2);
    expectTreesInsideZones(slab.domain);
}

TEST(Stage1, KeysAreValidatedAndRoundTrip) {
    const std::string base = header("keys", 10, 10, 10) + "[[source]]\nat = [5, 5, 5]\n" + kNoStage2 + "[stage1]\n";
    const auto expectError = [&](const std::string& line, const std::string& key) {
        try {
            parseScenarioString(base + line + "\n", "keys.toml");
            FAIL() << "accepted: " << line;
        } catch (const InputError& e) {
            const std::string m = e.what();
            EXPECT_NE(m.find("keys.toml:"), std::string::npos) << m;
            EXPECT_NE(m.find("'stage1." + key + "'"), std::string::npos) << m;
        }
    };
    expectError("boundary_faces = [\"+w\"]", "boundary_faces");
    expectError("boundary_faces = [\"+x\", \"+x\"]", "boundary_faces");
    expectError("boundary_faces = \"+x\"", "boundary_faces");
    expectError("protosink_share = 0", "protosink_share");
    expectError("protosink_share = 1.5", "protosink_share");
    expectError("branch_flow = -0.1", "branch_flow");
    expectError("resistance_noise = 2", "resistance_noise");

    const Scenario s = parseScenarioString(
        base + "boundary_faces = [\"-z\", \"+x\"]\nprotosink_share = 0.25\nbranch_flow = 0.05\nresistance_noise = 0\n",
        "keys.toml");
    EXPECT_EQ(s.stage1.boundaryFaces, (std::vector<GridFace>{GridFace::kMinusZ, GridFace::kPlusX}));
    EXPECT_EQ(s.stage1.protosinkShare, 0.25);
    EXPECT_EQ(s.stage1.branchFlow, 0.05);
    EXPECT_EQ(s.stage1.resistanceNoise, 0.0);
    const Scenario back = parseScenarioString(scenarioToToml(s), "effective.toml");
    EXPECT_EQ(back.stage1.boundaryFaces, s.stage1.boundaryFaces);
    EXPECT_EQ(back.stage1.protosinkShare, s.stage1.protosinkShare);
    EXPECT_EQ(back.stage1.branchFlow, s.stage1.branchFlow);
    EXPECT_EQ(back.stage1.resistanceNoise, s.stage1.resistanceNoise);
    const Scenario d = parseScenarioString(base, "keys.toml");
    EXPECT_EQ(d.stage1.boundaryFaces, (std::vector<GridFace>{GridFace::kMinusX, GridFace::kPlusX, GridFace::kMinusY,
                                                             GridFace::kPlusY, GridFace::kMinusZ}));
    EXPECT_EQ(parseScenarioString(scenarioToToml(d), "e.toml").stage1.boundaryFaces, d.stage1.boundaryFaces);
}

namespace {

/// A small 3D scenario without planes or rock noise, its x coordinates mirrored when `mx`, its y
/// coordinates when `my`. Sources of unequal pressure, an obstacle and a sink, all off-centre.
std::string mirrorScenario(bool mx, bool my, const std::string& stage1Extra = "") {
    const int nx = 26, ny = 22;
    const auto X = [&](int x) { return std::to_string(mx ? nx - 1 - x : x); };
    const auto Y = [&](int y) { return std::to_string(my ? ny - 1 - y : y); };
    const auto point = [&](int x, int y, int z) { return "[" + X(x) + ", " + Y(y) + ", " + std::to_string(z) + "]"; };
    const auto box = [&](int x0, int y0, int z0, int x1, int y1, int z1) {
        return "[[" + std::to_string(mx ? nx - 1 - x1 : x0) + ", " + std::to_string(my ? ny - 1 - y1 : y0) + ", " +
               std::to_string(z0) + "], [" + std::to_string(mx ? nx - 1 - x0 : x1) + ", " +
               std::to_string(my ? ny - 1 - y0 : y1) + ", " + std::to_string(z1) + "]]";
    };
    return header("mirror", nx, ny, 10, 11) + "[rock]\nporosity = 0.05\nnoise = { amplitude = 0.0 }\n" +
           "[[rock.sphere]]\ncenter = " + point(13, 9, 4) + "\nradius = 3\ncore_porosity = 0.01\n" +
           "[[source]]\nat = " + point(3, 4, 9) + "\npressure = 1.0\n" + "[[source]]\nat = " + point(6, 17, 8) +
           "\npressure = 0.7\n" + "[[sink]]\nbox = " + box(23, 8, 1, 25, 13, 3) + "\n[stage1]\n" + stage1Extra +
           "[stage2]\niterations = 40\np_rate = 0.5\np_rate_channel = 0.001\n";
}

/// Expects `b` to be `a` mirrored in x (mx) and/or y (my), voxel for voxel.
template <typename T>
void expectMirrored(const Grid3<T>& a, const Grid3<T>& b, bool mx, bool my, const char* what) {
    ASSERT_EQ(a.dims, b.dims);
    const Dims& d = a.dims;
    long differ = 0;
    for (std::size_t v = 0; v < d.count(); ++v) {
        Index3 p = d.coord(v);
        if (mx) p.i = d.nx - 1 - p.i;
        if (my) p.j = d.ny - 1 - p.j;
        differ += a[v] != b.at(p.i, p.j, p.k);
    }
    EXPECT_EQ(differ, 0) << what << " (mirrored x " << mx << ", y " << my << ")";
}

}  // namespace

TEST(Stage1, MirroredScenariosGiveMirroredProtochannelsAndCaves) {
    // Noise off (the rock's; the resistance noise is drawn in each zone's canonical frame, so it
    // may stay on): mirroring in x, in y or in both mirrors the zones and protochannels of stage
    // 1 and the porosity and flags after stage 2, voxel for voxel.
    for (const std::string extra : {std::string(), std::string("protosinks = \"clustered\"\naim = [[20, 3, 2]]\n")}) {
        const Scenario s0 = parseScenarioString(mirrorScenario(false, false, extra), "test.toml");
        const Stage1Run plain = runStage1On(s0);
        const Domain cave = simulate(s0);
        ASSERT_GT(countFlag(plain.domain, kProtochannel), 20);
        ASSERT_GT(countFlag(cave, kChannel), 20);
        for (const auto& [mx, my] : {std::pair{true, false}, std::pair{false, true}, std::pair{true, true}}) {
            std::string m = extra;
            if (!m.empty())
                m = "protosinks = \"clustered\"\naim = [[" + std::to_string(mx ? 5 : 20) + ", " +
                    std::to_string(my ? 18 : 3) + ", 2]]\n";
            const Scenario s = parseScenarioString(mirrorScenario(mx, my, m), "test.toml");
            const Stage1Run mirrored = runStage1On(s);
            expectMirrored(plain.domain.zone, mirrored.domain.zone, mx, my, "stage-1 zones");
            expectMirrored(plain.domain.flags, mirrored.domain.flags, mx, my, "stage-1 protochannels");
            const Domain mirroredCave = simulate(s);
            expectMirrored(cave.flags, mirroredCave.flags, mx, my, "flags after stage 2");
            expectMirrored(cave.porosity, mirroredCave.porosity, mx, my, "porosity after stage 2");
        }
    }
}

TEST(Stage1, ProtochannelsKeepTheSinkGapAndNoSourceStartsConnected) {
    for (int gap : {2, 4}) {
        Scenario s = parseScenarioString(mirrorScenario(false, false), "test.toml");
        s.stage1.sinkGap = gap;
        const Stage1Run r = runStage1On(s);
        const Dims& d = r.domain.dims;
        int nearest = 1 << 30;
        for (std::size_t v = 0; v < d.count(); ++v) {
            if (!(r.domain.flags[v] & kProtochannel)) continue;
            const Index3 p = d.coord(v);
            for (const auto& sink : r.domain.sinkVoxels)
                for (std::size_t w : sink) {
                    const Index3 q = d.coord(w);
                    nearest =
                        std::min(nearest, std::max({std::abs(p.i - q.i), std::abs(p.j - q.j), std::abs(p.k - q.k)}));
                }
        }
        EXPECT_GT(nearest, gap);
        EXPECT_LT(nearest, gap + 4) << "the protochannels still grow toward the sink";
        Domain d2 = r.domain;
        prepareStage2(d2, s.stage2);
        EXPECT_EQ(sourcesConnectedAtStart(d2), 0);
    }
}

TEST(Stage1, ConnectivityCountsSourcesJoinedThroughPassages) {
    // A source at x = 0 and a sink at x = 6 on one row: joined once the voxels between are
    // protochannel or channel (26-neighbours: a diagonal step joins too), not before.
    Domain d = emptyDomain(Dims{7, 5, 5}, 1.0, 0.05f);
    d.sourceVoxels = {{d.dims.index(0, 2, 2)}, {d.dims.index(0, 0, 0)}};
    d.sinkVoxels = {{d.dims.index(6, 2, 2)}};
    d.flags[d.sourceVoxels[0][0]] |= kSource;
    d.flags[d.sourceVoxels[1][0]] |= kSource;
    d.flags[d.sinkVoxels[0][0]] |= kSink;
    EXPECT_EQ(sourcesConnectedAtStart(d), 0);
    for (int i = 1; i <= 4; ++i) d.flags.at(i, 2, 2) |= kProtochannel;
    EXPECT_EQ(sourcesConnectedAtStart(d), 0);
    d.flags.at(5, 3, 3) |= kChannel;  // diagonal from (4, 2, 2) to the sink
    EXPECT_EQ(sourcesJoinedThroughPassages(d), (std::vector<bool>{true, false}));
    EXPECT_EQ(sourcesConnectedAtStart(d), 1);
}

TEST(Stage1, AimInsideOrNextToASinkIsRefused) {
    const std::string base = header("aim", 30, 20, 10) +
                             "[[source]]\nat = [2, 10, 9]\n[[sink]]\nbox = [[27, 8, 2], [29, 12, 4]]\n"
                             "[stage1]\nprotosinks = \"clustered\"\n";
    EXPECT_NO_THROW(parseScenarioString(base + "aim = [[24, 10, 3]]\n", "test.toml"));  // 3 voxels off
    for (const std::string aim : {"[[28, 10, 3]]", "[[25, 10, 3]]", "[[10, 10, 5], [26, 13, 6]]"}) {
        try {
            parseScenarioString(base + "aim = " + aim + "\n", "test.toml");
            ADD_FAILURE() << "aim " << aim << " accepted";
        } catch (const InputError& e) {
            const std::string m = e.what();
            EXPECT_NE(m.find("test.toml"), std::string::npos) << m;
            EXPECT_NE(m.find("'stage1.aim'"), std::string::npos) << m;
            EXPECT_NE(m.find("'stage1.sink_gap' = 2"), std::string::npos) << m;
        }
    }
    EXPECT_NO_THROW(parseScenarioString(base + "sink_gap = 1\naim = [[25, 10, 3]]\n", "test.toml"));
}

TEST(Stage1, LargeZoneNetworkIsTheNeighbourhoodOfItsSource) {
    // One source in the middle of uniform rock (no noise): the zone is the whole 24 × 24 × 12 block,
    // the network its 1,000 voxels the front reached first — a ball around the source, bent only
    // by the porosity (uniform here).
    const std::string base = header("ball", 24, 24, 12) + "[rock]\nporosity = 0.1\n[[source]]\nat = [12, 12, 6]\n";
    const Stage1Run whole = runText(base + "[stage1]\nboundary_faces = []\n" + kNoStage2);
    const Stage1Run r = runText(base + "[stage1]\nnetwork_voxels = 1000\nboundary_faces = []\n" + kNoStage2);
    ASSERT_EQ(r.result.zones, 1);
    EXPECT_EQ(r.result.zoneVoxels[0], 24 * 24 * 12);   // the zone itself is not cut
    EXPECT_EQ(whole.result.perZone[0].protosinks, 0);  // no boundary faces, no other zone: no protosinks
    const ZoneStats& z = r.result.perZone[0];
    // At most 1,000 voxels, more only on arrival-time ties at the cut.
    EXPECT_GE(z.graphNodes, 1000);
    EXPECT_LE(z.graphNodes, 1100);
    // The neighbourhood's edge drains: protosinks there, flow and protochannels rooted at the source.
    EXPECT_GT(z.protosinks, 0);
    EXPECT_GT(z.maxFlow, 0.0);
    EXPECT_GT(r.result.protochannelVoxels, 0);
    expectTreesInsideZones(r.domain);
    // Every protochannel voxel lies within the ball: about (3·1000 / 4π)^(1/3) ≈ 6.2 voxels of the source.
    for (std::size_t v = 0; v < r.domain.flags.size(); ++v) {
        if (!(r.domain.flags[v] & kProtochannel)) continue;
        const Index3 p = r.domain.dims.coord(v);
        const double dist =
            std::sqrt(double((p.i - 12) * (p.i - 12) + (p.j - 12) * (p.j - 12) + (p.k - 6) * (p.k - 6)));
        EXPECT_LE(dist, 8.0) << "voxel " << v;
    }
    // The zone labels are the zone's again after the neighbourhood's edge was found.
    for (std::int32_t label : r.domain.zone.data) EXPECT_EQ(label, 0);
}

TEST(Stage1, NetworkLargerThanTheLimitIsRefusedEvenWithinTheNeighbourhood) {
    const std::string text = header("big", 20, 20, 10) +
                             "[[source]]\nat = [5, 5, 5]\n[stage1]\nmax_graph_voxels = 1000\nnetwork_voxels = 2000\n" +
                             kNoStage2;
    try {
        runText(text);
        FAIL() << "no error";
    } catch (const Stage1LimitError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("flow network of source 1"), std::string::npos) << m;
        EXPECT_NE(m.find("2,000 voxels"), std::string::npos) << m;
        EXPECT_NE(m.find("limit of 1,000"), std::string::npos) << m;
    }
}

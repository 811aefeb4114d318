// Geology of the rock and recharge: Fisher sampling (mean direction and concentration measured
// back), power-law lengths (fitted exponent), a deterministic fracture network, one disc rasterised
// by hand, recharge expanded into sources, inception horizons raising stage-1 capacity and lowering
// the stage-2 rate, and the bad-input messages of the new keys.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/error.h"
#include "sim/domain.h"
#include "sim/fractures.h"
#include "sim/recharge.h"
#include "sim/scenario_io.h"
#include "sim/stage1.h"
#include "sim/stage2_steps.h"

using namespace cavesim;

namespace {

constexpr double kPi = 3.14159265358979323846;

double angleDegrees(const Vec3d& a, const Vec3d& b) {
    const double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    const double na = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    const double nb = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    return std::acos(std::clamp(d / (na * nb), -1.0, 1.0)) * 180.0 / kPi;
}

std::string errorOf(const std::string& text) {
    try {
        parseScenarioString(text, "bad.toml");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

const char* kBlock = R"(name = "g"
seed = 7
[domain]
size = [40, 30, 12]
[rock]
porosity = 0.05
[[sink]]
box = [[0, 0, 0], [1, 29, 1]]
[stage2]
iterations = 5
)";

}  // namespace

TEST(Fractures, PoleAndOrientationRoundTrip) {
    const Vec3d east = poleFromOrientation(90, 90);
    EXPECT_NEAR(east[0], 1.0, 1e-15);
    EXPECT_NEAR(east[1], 0.0, 1e-15);
    EXPECT_NEAR(east[2], 0.0, 1e-15);
    const Vec3d flat = poleFromOrientation(200, 0);
    EXPECT_DOUBLE_EQ(flat[2], 1.0);
    double dd = 0, dip = 0;
    orientationFromPole(poleFromOrientation(123, 37), dd, dip);
    EXPECT_NEAR(dd, 123, 1e-9);
    EXPECT_NEAR(dip, 37, 1e-9);
    orientationFromPole({0, 0, -2}, dd, dip);  // either sense of the pole
    EXPECT_EQ(dd, 0.0);
    EXPECT_NEAR(dip, 0.0, 1e-12);
}

TEST(Fractures, FisherSamplesMeasureBackMeanAndKappa) {
    const Vec3d mean = poleFromOrientation(120, 60);
    for (double kappa : {5.0, 20.0, 100.0, 1000.0}) {
        Rng rng(familySeed(11, std::size_t(kappa)));
        std::vector<Vec3d> v;
        Vec3d sum{0, 0, 0};
        for (int n = 0; n < 40000; ++n) {
            v.push_back(sampleFisher(mean, kappa, rng));
            for (int a = 0; a < 3; ++a) sum[a] += v.back()[a];
            ASSERT_NEAR(std::hypot(v.back()[0], v.back()[1], v.back()[2]), 1.0, 1e-12);
        }
        // The mean resultant's direction: its standard error is about 1 / sqrt(kappa · N) radians.
        EXPECT_LT(angleDegrees(sum, mean), 0.5) << "kappa " << kappa;
        EXPECT_NEAR(estimateKappa(v) / kappa, 1.0, 0.10) << "kappa " << kappa;
    }
}

TEST(Fractures, FisherSamplesOfTinyKappaAreUniform) {
    // κ → 0 is the uniform distribution on the sphere: cos θ uniform in [−1, 1], mean 0, variance 1/3.
    // (e^(−2κ) rounding to 1 once put every pole on the mean pole.)
    const Vec3d mean = poleFromOrientation(0, 90);
    for (double kappa : {1e-300, 1e-17, 1e-9, 1e-4}) {
        Rng rng(familySeed(3, 1));
        double sum = 0, sumSq = 0;
        const int n = 40000;
        for (int i = 0; i < n; ++i) {
            const Vec3d p = sampleFisher(mean, kappa, rng);
            const double c = p[0] * mean[0] + p[1] * mean[1] + p[2] * mean[2];
            sum += c;
            sumSq += c * c;
        }
        EXPECT_NEAR(sum / n, 0.0, 0.02) << "kappa " << kappa;
        EXPECT_NEAR(sumSq / n, 1.0 / 3.0, 0.02) << "kappa " << kappa;
    }
}

TEST(Fractures, ReachesBlockAgreesWithTheNetwork) {
    // A 20 × 2 × 2 block and 20-voxel discs: about 3 are drawn in the grown box and often none
    // reaches the block (the run once went on with an empty family and a mean dip of 0).
    FractureFamily f;
    f.spacing = 20;
    f.minLength = f.maxLength = 20;
    f.dip = 0;
    f.kappa = 1000;
    const std::vector<FractureFamily> families{f, f};
    const Dims dims{20, 2, 2};
    int empty = 0, kept = 0;
    for (std::uint64_t seed = 1; seed <= 24; ++seed) {
        const FractureNetwork net = generateFractureNetwork(families, dims, seed);
        for (std::size_t fi = 0; fi < families.size(); ++fi) {
            const bool reaches = fractureFamilyReachesBlock(families, fi, dims, seed);
            EXPECT_EQ(reaches, net.families[fi].count > 0) << "seed " << seed << " family " << fi;
            (reaches ? kept : empty) += 1;
        }
    }
    EXPECT_GT(empty, 0);
    EXPECT_GT(kept, 0);
}

TEST(Fractures, PowerLawLengthsFitTheirExponent) {
    for (double a : {1.5, 2.5, 3.5}) {
        Rng rng(5);
        // Essentially untruncated: the maximum-likelihood exponent is 1 + N / Σ ln(l / lo).
        double logSum = 0;
        const int n = 40000;
        for (int i = 0; i < n; ++i) {
            const double l = samplePowerLaw(a, 2.0, 1e12, rng);
            ASSERT_GE(l, 2.0);
            logSum += std::log(l / 2.0);
        }
        EXPECT_NEAR(1.0 + n / logSum, a, 0.05);
    }
    Rng rng(6);
    for (int i = 0; i < 1000; ++i) {
        const double l = samplePowerLaw(2.0, 3.0, 9.0, rng);
        ASSERT_GE(l, 3.0);
        ASSERT_LE(l, 9.0);
    }
    // E[π l² / 4] of a single length, and of l^-3 on [1, 2]: π/4 · ln 2 / (3/8).
    EXPECT_DOUBLE_EQ(meanDiscArea(2.5, 2.0, 2.0), kPi);
    EXPECT_NEAR(meanDiscArea(3.0, 1.0, 2.0), kPi / 4 * std::log(2.0) / 0.375, 1e-12);
}

TEST(Fractures, CountFollowsSpacingOrDensity) {
    FractureFamily f;
    f.minLength = f.maxLength = 2.0;  // discs of area π
    f.spacing = 1.0;
    // Centres are drawn in the block grown by max_length / 2 = 1 on every side: 12³ voxels³.
    EXPECT_DOUBLE_EQ(fractureDrawVolume(f, Dims{10, 10, 10}), 1728.0);
    EXPECT_EQ(fractureCount(f, Dims{10, 10, 10}), std::round(1728 / kPi));
    f.spacing = 0;
    f.density = 0.01;
    EXPECT_EQ(fractureCount(f, Dims{10, 10, 10}), std::round(17.28));
}

TEST(Fractures, SpacingGivesP32InsideAThinBlock) {
    // Vertical discs much taller than the block: counting centres in the block alone kept about a
    // third of the asked P32 (the discs are cut by the top and floor); drawn in the grown box, the
    // measured P32 is 1/spacing to within the sampling noise.
    FractureFamily f;
    f.dipDirection = 90;
    f.dip = 90;
    f.kappa = 400;
    f.minLength = f.maxLength = 60.0;
    f.spacing = 5.0;
    f.aperture = 1.0;
    const Dims d{80, 80, 8};
    double sum = 0;
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
        FractureNetwork net = generateFractureNetwork({f}, d, seed);
        measureFractureNetwork(net, {f}, d);
        sum += net.families[0].p32;
    }
    EXPECT_NEAR(sum / 20, 1.0 / 5.0, 0.1 / 5.0);  // the mean of 20 seeds within 10 %
}

TEST(Fractures, NetworkIsDeterministicPerSeed) {
    std::vector<FractureFamily> fam(2);
    fam[0].dipDirection = 30;
    fam[0].dip = 80;
    fam[1].dipDirection = 120;
    fam[1].dip = 75;
    fam[1].spacing = 20;
    const Dims d{50, 40, 20};
    const FractureNetwork a = generateFractureNetwork(fam, d, 3), b = generateFractureNetwork(fam, d, 3);
    const FractureNetwork c = generateFractureNetwork(fam, d, 4);
    ASSERT_EQ(a.discs.size(), b.discs.size());
    ASSERT_GT(a.discs.size(), 10u);
    EXPECT_EQ(a.families[0].count + a.families[1].count, long(a.discs.size()));
    bool differs = c.discs.size() != a.discs.size();
    for (std::size_t i = 0; i < a.discs.size(); ++i) {
        EXPECT_EQ(a.discs[i].centre, b.discs[i].centre);
        EXPECT_EQ(a.discs[i].normal, b.discs[i].normal);
        EXPECT_EQ(a.discs[i].radius, b.discs[i].radius);
        EXPECT_EQ(a.discs[i].family, b.discs[i].family);
        if (!differs && a.discs[i].centre != c.discs[i].centre) differs = true;
        for (int ax = 0; ax < 3; ++ax) {  // centres in the block grown by the largest radius
            const double grow = 0.5 * fam[std::size_t(a.discs[i].family)].maxLength;
            EXPECT_GE(a.discs[i].centre[ax], -0.5 - grow);
            EXPECT_LE(a.discs[i].centre[ax], (ax == 0 ? 50 : ax == 1 ? 40 : 20) - 0.5 + grow);
        }
    }
    EXPECT_TRUE(differs);
    // Adding a family leaves the first family's discs as they were (each family its own stream).
    const FractureNetwork one = generateFractureNetwork({fam[0]}, d, 3);
    ASSERT_EQ(long(one.discs.size()), a.families[0].count);
    for (std::size_t i = 0; i < one.discs.size(); ++i) EXPECT_EQ(one.discs[i].centre, a.discs[i].centre);
}

TEST(Fractures, OneHorizontalDiscRasterisedByHand) {
    const Dims d{11, 11, 11};
    Grid3<float> R(d, 0.05f);
    Grid3<std::uint8_t> flags(d, 0);
    FractureDisc disc;
    disc.centre = {5, 5, 5};
    disc.normal = {0, 0, 1};
    disc.radius = 2.0;
    // Layer k = 5 only (|h| = 1 > 1/2 above and below); dx² + dy² ≤ 4: 5 + 3 + 3 + 1 + 1 = 13 voxels.
    EXPECT_EQ(rasteriseDisc(disc, 1.0, 0.3f, R, flags), 13);
    long raised = 0;
    for (int k = 0; k < 11; ++k)
        for (int j = 0; j < 11; ++j)
            for (int i = 0; i < 11; ++i) {
                const bool in = k == 5 && (i - 5) * (i - 5) + (j - 5) * (j - 5) <= 4;
                EXPECT_EQ(R.at(i, j, k), in ? 0.3f : 0.05f);
                EXPECT_EQ(flags.at(i, j, k), in ? kFracture : 0);
                raised += in;
            }
    EXPECT_EQ(raised, 13);
    // A thicker slab takes layers 4..6 (|h| ≤ 1.5); the mid-plane count stays 13.
    EXPECT_EQ(rasteriseDisc(disc, 3.0, 0.3f, R, flags), 13);
    long thick = 0;
    for (float r : R.data) thick += r == 0.3f;
    EXPECT_EQ(thick, 39);
}

TEST(Fractures, TiltedDiscMatchesBruteForce) {
    const Dims d{30, 25, 20};
    FractureDisc disc;
    disc.centre = {14.3, 11.7, 9.2};
    disc.normal = poleFromOrientation(37, 63);
    disc.radius = 8.5;
    const double t = 2.2;
    Grid3<float> R(d, 0.f);
    Grid3<std::uint8_t> flags(d, 0);
    rasteriseDisc(disc, t, 1.f, R, flags);
    long mismatches = 0, inside = 0;
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                const Vec3d rel{i - disc.centre[0], j - disc.centre[1], k - disc.centre[2]};
                const double h = rel[0] * disc.normal[0] + rel[1] * disc.normal[1] + rel[2] * disc.normal[2];
                const double r2 = rel[0] * rel[0] + rel[1] * rel[1] + rel[2] * rel[2] - h * h;
                const bool in = std::abs(h) <= t / 2 && r2 <= disc.radius * disc.radius;
                inside += in;
                mismatches += in != (R.at(i, j, k) == 1.f);
            }
    EXPECT_EQ(mismatches, 0);
    EXPECT_GT(inside, 400);
}

TEST(Fractures, ScenarioFamiliesRaisePorosityAndCheckFit) {
    const std::string fam = R"(
[[rock.fracture_family]]
dip_direction = 90.0
dip = 85.0
kappa = 50.0
spacing = 8.0
min_length = 4.0
max_length = 30.0
porosity = 0.3
[[source]]
at = [35, 15, 11]
)";
    const Scenario s = parseScenarioString(std::string(kBlock) + fam, "f.toml");
    ASSERT_EQ(s.fractureFamilies.size(), 1u);
    Rng rng(s.seed);
    const Domain dom = buildDomain(s, rng);
    long raised = 0;
    for (float r : dom.porosity0.data) raised += r == 0.3f;
    EXPECT_GT(raised, 100);
    // A family's fractures are early-flow paths like inception horizons: stage 2 reads their rate
    // from their porosity against the rock's; the rock between them keeps p_rate.
    ASSERT_EQ(dom.inception.size(), dom.porosity.size());
    const Stage2Options g;
    const Grid3<float> rate = stage2::rateField(dom, g);
    long early = 0;
    for (std::size_t v = 0; v < dom.porosity0.data.size(); ++v) {
        if (dom.flags.data[v] & ~kFracture) continue;  // sources and sinks have their own rate
        const bool inFracture = dom.porosity0.data[v] == 0.3f;
        EXPECT_EQ(dom.inception.data[v], inFracture ? 1 : 0);
        EXPECT_EQ(rate.data[v], inFracture ? stage2::porosityRate(0.3f, dom.rockPorosity, g) : float(g.pRate));
        early += inFracture;
    }
    EXPECT_GT(early, 100);
    // The effective scenario reads back to the same text.
    EXPECT_EQ(scenarioToToml(parseScenarioString(scenarioToToml(s), "e.toml")), scenarioToToml(s));

    const auto bad = [&](const std::string& key, const std::string& value, const std::string& key2 = "",
                         const std::string& value2 = "") {
        std::string text = std::string(kBlock) + fam;
        for (const auto& [k, v] : {std::pair{key, value}, std::pair{key2, value2}}) {
            if (k.empty()) continue;
            const std::size_t at = text.find(k + " = ");
            const std::size_t end = text.find('\n', at);
            text.replace(at, end - at, k + " = " + v);
        }
        return errorOf(text);
    };
    EXPECT_NE(bad("min_length", "45.0").find("key 'rock.fracture_family.min_length' = 45"), std::string::npos);
    EXPECT_NE(bad("min_length", "45.0").find("cannot fit"), std::string::npos);
    EXPECT_NE(bad("min_length", "35.0").find("at most max_length"), std::string::npos);
    EXPECT_NE(bad("spacing", "100.0").find("spacing is larger than the block"), std::string::npos);
    // Centres drawn in the block grown by max_length / 2: 70 × 60 × 42 voxels³ × 2·10⁻⁶ = 0.35 discs.
    EXPECT_NE(bad("spacing", "0.0", "kappa", "50.0\ndensity = 0.000002").find("gives no fracture"), std::string::npos);
    EXPECT_NE(bad("kappa", "50.0\ndensity = 0.001").find("not both"), std::string::npos);
    EXPECT_NE(bad("kappa", "0.0").find("must be a number in (0, "), std::string::npos);
    EXPECT_NE(bad("spacing", "0.0").find("give spacing > 0 or density > 0"), std::string::npos);
    EXPECT_NE(bad("dip", "95.0").find("bad.toml:"), std::string::npos);
    EXPECT_EQ(bad("kappa", "0.0").rfind("bad.toml:", 0), 0u);
}

// An area exactly 2r + 1 columns wide holds one sinkhole, which fills it, whatever the seed; at the
// block's corner too (it was clipped there to fewer columns).
TEST(Recharge, ASinkholeFillsAnAreaOfItsOwnSize) {
    for (const auto& [x0, y0] : {std::pair{10, 10}, std::pair{0, 0}})
        for (std::uint64_t seed = 1; seed <= 8; ++seed) {
            const std::string text = std::string(kBlock) + "\n[[recharge]]\nkind = \"sinkholes\"\narea = [" +
                                     std::to_string(x0) + ", " + std::to_string(y0) + ", " + std::to_string(x0 + 8) +
                                     ", " + std::to_string(y0 + 8) + "]\ncount = 1\nradius = 4\n";
            Scenario s = parseScenarioString(text, "r.toml");
            s.seed = seed;
            const std::vector<SourceSpec> a = rechargeSources(s);
            ASSERT_EQ(a.size(), 1u);
            EXPECT_EQ(a[0].box.lo[0], x0) << "seed " << seed;
            EXPECT_EQ(a[0].box.lo[1], y0) << "seed " << seed;
            EXPECT_EQ(a[0].box.hi[0], x0 + 8) << "seed " << seed;
            EXPECT_EQ(a[0].box.hi[1], y0 + 8) << "seed " << seed;
        }
}

TEST(Recharge, SinkholesAreDrawnInsideTheirAreaDeterministically) {
    const std::string text = std::string(kBlock) + R"(
[[recharge]]
kind = "sinkholes"
area = [10, 5, 30, 25]
count = 6
radius = 1
pressure = 2.0
)";
    const Scenario s = parseScenarioString(text, "r.toml");
    const std::vector<SourceSpec> a = rechargeSources(s), b = rechargeSources(s);
    ASSERT_EQ(a.size(), 6u);
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].box.lo, b[i].box.lo);
        EXPECT_EQ(a[i].pressure, 2.0);
        EXPECT_EQ(a[i].box.hi[2], 11);  // the top layer
        EXPECT_EQ(a[i].box.lo[2], 10);  // radius 1: two layers
        // The whole 3 × 3 box in the area (its centre once landed anywhere in it, the box hanging out).
        EXPECT_GE(a[i].box.lo[0], 10);
        EXPECT_LE(a[i].box.hi[0], 30);
        EXPECT_GE(a[i].box.lo[1], 5);
        EXPECT_LE(a[i].box.hi[1], 25);
        EXPECT_EQ(a[i].box.hi[0] - a[i].box.lo[0], 2);
        EXPECT_EQ(a[i].box.hi[1] - a[i].box.lo[1], 2);
        for (std::size_t k = 0; k < i; ++k)  // 3 × 3 boxes that do not overlap
            EXPECT_GE(std::max(std::abs(a[k].box.lo[0] - a[i].box.lo[0]), std::abs(a[k].box.lo[1] - a[i].box.lo[1])),
                      3);
    }
    Scenario other = s;
    other.seed = 8;
    const std::vector<SourceSpec> c = rechargeSources(other);
    bool differs = false;
    for (std::size_t i = 0; i < a.size(); ++i) differs = differs || c[i].box.lo != a[i].box.lo;
    EXPECT_TRUE(differs);
    // They become the domain's sources.
    Rng rng(s.seed);
    const Domain dom = buildDomain(s, rng);
    ASSERT_EQ(dom.sourceVoxels.size(), 6u);
    EXPECT_EQ(dom.sourceVoxels[0].size(), 18u);
}

TEST(Recharge, DiffuseAndStreamShareTheirPressure) {
    const Scenario d = parseScenarioString(std::string(kBlock) + R"(
[[recharge]]
kind = "diffuse"
area = [10, 0, 39, 29]
spacing = 10.0
pressure = 6.0
)",
                                           "d.toml");
    const std::vector<SourceSpec> in = rechargeSources(d);
    ASSERT_EQ(in.size(), 9u);  // 3 × 3 cells of 10 columns
    for (std::size_t n = 0; n < in.size(); ++n) {
        EXPECT_DOUBLE_EQ(in[n].pressure, 6.0 / 9);
        const int u = int(n % 3), v = int(n / 3);  // one input in each cell
        EXPECT_EQ((in[n].box.lo[0] - 10) / 10, u);
        EXPECT_EQ(in[n].box.lo[1] / 10, v);
        EXPECT_EQ(in[n].box.lo[2], 11);
    }
    const Scenario st = parseScenarioString(std::string(kBlock) + R"(
[[recharge]]
kind = "stream"
points = [[38.0, 2.0, 11.0], [38.0, 22.0, 11.0], [20.0, 22.0, 11.0]]
spacing = 5.0
)",
                                            "s.toml");
    const std::vector<SourceSpec> line = rechargeSources(st);
    // Arc length 38: inputs at 0, 5, …, 35.
    ASSERT_EQ(line.size(), 8u);
    EXPECT_EQ(line[0].box.lo, (std::array<int, 3>{38, 2, 11}));
    EXPECT_EQ(line[4].box.lo, (std::array<int, 3>{38, 22, 11}));
    EXPECT_EQ(line[7].box.lo, (std::array<int, 3>{23, 22, 11}));
    for (const SourceSpec& q : line) EXPECT_DOUBLE_EQ(q.pressure, 1.0 / 8);
}

TEST(Recharge, BadRechargeIsAnErrorNamingTheKey) {
    const auto err = [](const std::string& entry) { return errorOf(std::string(kBlock) + "[[recharge]]\n" + entry); };
    EXPECT_NE(err("area = [0, 0, 40, 10]\n").find("key 'recharge.area' = [0, 0, 40, 10]: recharge outside the land"),
              std::string::npos);
    EXPECT_NE(err("area = [0, 0, 10]\n").find("must be [] or [x0, y0, x1, y1]"), std::string::npos);
    EXPECT_NE(err("area = [0, 0, 1, 1]\ncount = 5\n").find("cannot hold that many sinkholes"), std::string::npos);
    EXPECT_NE(err("kind = \"stream\"\npoints = [[1.0, 1.0, 11.0], [1.0, 1.0, 12.5]]\n").find("recharge outside"),
              std::string::npos);
    EXPECT_NE(err("kind = \"stream\"\n").find("at least 2 points"), std::string::npos);
    EXPECT_NE(err("kind = \"diffuse\"\nspacing = 1.0\n").find("more than the 256 sources"), std::string::npos);
    EXPECT_NE(err("kind = \"sinkholes\"\npoints = [[1.0, 1.0, 1.0]]\n").find("only a stream takes points"),
              std::string::npos);
    // The key's own line (12), not the entry's header (11); a rule on a key left at its default
    // names the header.
    EXPECT_EQ(err("area = [0, 0, 40, 10]\n").rfind("bad.toml:12:", 0), 0u) << err("area = [0, 0, 40, 10]\n");
    EXPECT_EQ(err("area = [0, 0, 1, 1]\ncount = 5\n").rfind("bad.toml:13: key 'recharge.count'", 0), 0u)
        << err("area = [0, 0, 1, 1]\ncount = 5\n");
    EXPECT_EQ(err("kind = \"stream\"\n").rfind("bad.toml:11: key 'recharge.points'", 0), 0u)
        << err("kind = \"stream\"\n");
    // A stage with recharge needs no [[source]].
    EXPECT_EQ(err("count = 2\n"), "");
}

TEST(Recharge, SinkholeKeysOnAnotherKindAreRefusedAndNotWritten) {
    const auto err = [](const std::string& entry) { return errorOf(std::string(kBlock) + "[[recharge]]\n" + entry); };
    const std::string stream = "kind = \"stream\"\npoints = [[1.0, 1.0, 11.0], [9.0, 1.0, 11.0]]\n";
    // Line 11 is the entry's header: the key is on the line after the entry's two lines.
    EXPECT_EQ(err(stream + "count = 5\n"),
              "bad.toml:14: key 'recharge.count' = 5: only sinkholes take a count; leave it out for this kind");
    EXPECT_EQ(err(stream + "radius = 0\n"),
              "bad.toml:14: key 'recharge.radius' = 0: only sinkholes take a radius; leave it out for this kind");
    EXPECT_NE(err("kind = \"diffuse\"\ncount = 3\n").find("key 'recharge.count' = 3: only sinkholes"),
              std::string::npos);
    EXPECT_EQ(err("kind = \"sinkholes\"\ncount = 3\nradius = 1\n"), "");
    // The effective scenario leaves them out, so it reads back.
    const Scenario s = parseScenarioString(std::string(kBlock) + "[[recharge]]\n" + stream, "s.toml");
    const std::string text = scenarioToToml(s);
    EXPECT_EQ(text.find("\ncount ="), std::string::npos) << text;
    EXPECT_EQ(text.find("\nradius ="), std::string::npos) << text;
}

TEST(Inception, HorizonRaisesStage1CapacityAndLowersTheStage2Rate) {
    const std::string base = R"(name = "i"
seed = 2
[domain]
size = [24, 8, 12]
[rock]
porosity = 0.05
[[source]]
at = [20, 4, 6]
[stage1]
boundary_faces = ["-x"]
[stage2]
enabled = false
)";
    const std::string horizon = R"(
[[rock.inception_horizon]]
point = [0.0, 0.0, 6.0]
normal = [0.0, 0.0, 1.0]
thickness = 1.0
porosity = 0.2
)";
    const auto stage1Flow = [](const std::string& text, Domain* out) {
        const Scenario s = parseScenarioString(text, "i.toml");
        Rng rng(s.seed);
        Domain dom = buildDomain(s, rng);
        const Stage1Result r = runStage1(dom, s.stage1, rng);
        if (out) *out = dom;
        return r.perZone.at(0).maxFlow;
    };
    Domain withHorizon;
    const double plain = stage1Flow(base, nullptr);
    const double raised = stage1Flow(base + horizon, &withHorizon);
    EXPECT_GT(raised, plain * 1.5);
    ASSERT_EQ(withHorizon.inception.size(), withHorizon.porosity.size());
    EXPECT_EQ(withHorizon.inception.at(3, 3, 6), 1);
    EXPECT_EQ(withHorizon.inception.at(3, 3, 5), 0);
    EXPECT_EQ(withHorizon.porosity0.at(3, 3, 6), 0.2f);
    EXPECT_TRUE(withHorizon.flags.at(3, 3, 6) & kFracture);

    // Stage 2: the horizon's rate is the porosity rule against the rock's porosity, under both rules.
    Stage2Options g;
    const Grid3<float> rate = stage2::rateField(withHorizon, g);
    EXPECT_EQ(rate.at(3, 3, 5), float(g.pRate));
    EXPECT_EQ(rate.at(3, 3, 6), stage2::porosityRate(0.2f, 0.05f, g));
    EXPECT_LT(rate.at(3, 3, 6), float(g.pRate));
    g.rateRule = RateRule::kChannelFlag;
    EXPECT_EQ(stage2::rateField(withHorizon, g).at(3, 3, 6), stage2::porosityRate(0.2f, 0.05f, g));
}

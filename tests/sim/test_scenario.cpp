// Scenario parsing and validation: every bad-input case gives an InputError naming file, line,
// key, value and what is allowed; the effective scenario round-trips.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "core/error.h"
#include "sim/domain.h"
#include "sim/scenario_io.h"

using namespace cavesim;

namespace {

const char* kBase = R"(name = "t"
seed = 3
[domain]
size = [20, 10, 8]
voxel_size = 2.0
[rock]
porosity = 0.05
[[source]]
at = [2, 5, 6]
pressure = 1.0
[[sink]]
box = [[17, 3, 0], [19, 6, 2]]
[stage2]
iterations = 10
)";

std::string errorOf(const std::string& text) {
    try {
        parseScenarioString(text, "bad.toml");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

void expectError(const std::string& text, std::initializer_list<const char*> parts) {
    const std::string msg = errorOf(text);
    ASSERT_FALSE(msg.empty()) << "no error for:\n" << text;
    EXPECT_NE(msg.find("bad.toml"), std::string::npos) << msg;
    for (const char* p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' missing in: " << msg;
}

}  // namespace

TEST(Scenario, BaseParses) {
    const Scenario s = parseScenarioString(kBase, "base.toml");
    EXPECT_EQ(s.name, "t");
    EXPECT_EQ(s.size[0], 20);
    EXPECT_DOUBLE_EQ(s.voxelSize, 2.0);
    ASSERT_EQ(s.sources.size(), 1u);
    EXPECT_EQ(s.sources[0].box.lo[2], 6);
    EXPECT_EQ(s.sinks[0].box.hi[0], 19);
    EXPECT_EQ(s.stage2.iterations, 10);
    EXPECT_DOUBLE_EQ(s.stage2.pRate, 0.5);  // default
}

TEST(Scenario, UnknownKeyNamesLineKeyAndAllowed) {
    expectError(std::string(kBase) + "p_rat = 0.3\n", {":15", "stage2.p_rat", "0.3", "allowed keys", "p_rate"});
}

TEST(Scenario, MisspeltTopLevelTable) {
    expectError(std::string(kBase) + "[stage3]\nenabled = true\n", {"stage3", "allowed keys"});
}

TEST(Scenario, WrongType) {
    std::string t = kBase;
    t.replace(t.find("porosity = 0.05"), 15, "porosity = \"high\"");
    expectError(t, {":7", "rock.porosity", "\"high\"", "must be a number in [0, 1]"});
}

TEST(Scenario, OutOfRange) {
    std::string t = kBase;
    t.replace(t.find("porosity = 0.05"), 15, "porosity = 1.5");
    expectError(t, {":7", "rock.porosity", "1.5", "[0, 1]"});
    expectError(std::string(kBase) + "w0 = -1\n", {"stage2.w0", "-1", "[0, 10]"});
    expectError(std::string(kBase) + "iterations2 = 1\n", {"iterations2"});
}

TEST(Scenario, ChannelRateAboveRockRateRefused) {
    expectError(std::string(kBase) + "p_rate = 0.1\np_rate_channel = 0.2\n",
                {"stage2.p_rate_channel", "0.2", "p_rate"});
}

TEST(Scenario, SourceOutsideDomain) {
    std::string t = kBase;
    t.replace(t.find("at = [2, 5, 6]"), 14, "at = [2, 5, 8]");
    expectError(t, {":9", "'source.at'", "[2, 5, 8]", "inside the domain"});
}

TEST(Scenario, SinkOutsideDomain) {
    std::string t = kBase;
    t.replace(t.find("[19, 6, 2]"), 10, "[20, 6, 2]");
    expectError(t, {":12", "sink.box", "inside the domain"});
}

TEST(Scenario, SourceOverlappingSink) {
    std::string t = kBase;
    t.replace(t.find("at = [2, 5, 6]"), 14, "at = [18, 4, 1]");
    expectError(t, {"sink", "overlaps", "source"});
}

TEST(Scenario, Stage2WithoutSinks) {
    std::string t = kBase;
    t.replace(t.find("[[sink]]"), std::string("[[sink]]\nbox = [[17, 3, 0], [19, 6, 2]]\n").size(), "");
    expectError(t, {"stage2.enabled", "[[sink]]"});
    // ... but a stage-1-only scenario needs none.
    EXPECT_NO_THROW(parseScenarioString(t + "enabled = false\n", "ok.toml"));
}

TEST(Scenario, MalformedToml) {
    expectError("name = \"x\"\n[domain\nsize = [1,2,3]\n", {":2", "malformed TOML"});
}

TEST(Scenario, MissingFile) {
    try {
        parseScenarioFile("/nonexistent/nope.toml");
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/nope.toml"), std::string::npos);
    }
}

TEST(Scenario, BadBoxAndBothForms) {
    std::string t = kBase;
    t.replace(t.find("at = [2, 5, 6]"), 14, "at = [2, 5, 6]\nbox = [[1,1,1],[2,2,2]]");
    expectError(t, {"not both"});
    std::string u = kBase;
    u.replace(u.find("[[17, 3, 0], [19, 6, 2]]"), 24, "[[19, 3, 0], [17, 6, 2]]");
    expectError(u, {"sink.box", "x0 <= x1"});
}

TEST(Scenario, BadName) {
    expectError(std::string("name = \"a b\"\n") + (kBase + 10), {"'name'", "letters"});
}

TEST(Scenario, EffectiveScenarioRoundTrips) {
    std::string t = std::string(kBase) + R"(snapshots = [2, 5]
[[rock.sphere]]
center = [5, 5, 4]
radius = 3
[[rock.plane]]
point = [0, 0, 3]
normal = [0, 0.2, 1]
kind = "fracture"
[[rock.channel]]
points = [[3, 5, 6], [3, 5, 2], [6, 5, 2]]
radius = 0.7
)";
    const Scenario a = parseScenarioString(t, "a.toml");
    const std::string eff = scenarioToToml(a);
    const Scenario b = parseScenarioString(eff, "b.toml");
    EXPECT_EQ(scenarioToToml(b), eff);
    EXPECT_EQ(b.channels.at(0).points.size(), 3u);
    EXPECT_EQ(b.stage2.snapshots, (std::vector<int>{2, 5}));
    EXPECT_EQ(b.planes.at(0).kind, PlaneKind::kFracture);
    EXPECT_DOUBLE_EQ(b.stage2.w0, a.stage2.w0);
    EXPECT_NE(eff.find("p_rate_channel"), std::string::npos);  // defaults written out
}

TEST(Scenario, CaveExtentChoice) {
    EXPECT_EQ(parseScenarioString(kBase, "a.toml").output.cave, CaveExtent::kChannels);  // default
    const Scenario s = parseScenarioString(std::string(kBase) + "[output]\ncave = \"with_protochannels\"\n", "a.toml");
    EXPECT_EQ(s.output.cave, CaveExtent::kWithProtochannels);
    expectError(std::string(kBase) + "[output]\ncave = \"everything\"\n",
                {":16", "output.cave", "everything", "\"channels\"", "\"with_protochannels\""});
}

TEST(Scenario, ErrorsQuoteValuesAsWritten) {
    // A float where a whole number belongs is shown as a float, not as the whole number it equals.
    std::string t = kBase;
    t.replace(t.find("size = [20"), 10, "size = [20.0");
    expectError(t, {"domain.size", "[20.0,", "whole numbers"});
    // Control characters are escaped: the message stays on one line.
    const std::string msg = errorOf(std::string("name = \"a\\nb\\u0001\"\n") + (kBase + 10));
    EXPECT_NE(msg.find("\"a\\nb\\u0001\""), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    // An unknown key is echoed escaped and shortened.
    const std::string longKey = errorOf(std::string(kBase) + std::string(5000, 'k') + " = 1\n");
    EXPECT_LT(longKey.size(), 400u) << longKey.size();
    EXPECT_NE(longKey.find("kkk..."), std::string::npos) << longKey;
    // Shortening never cuts a UTF-8 character in half: 'é' is two bytes, the cut falls between them.
    std::string accents;
    for (int i = 0; i < 100; ++i) accents += "\xc3\xa9";
    const std::string utf8 = errorOf(std::string(kBase) + "\"" + accents + "\" = 1\n");
    const std::size_t dots = utf8.find("...");
    ASSERT_NE(dots, std::string::npos) << utf8;
    EXPECT_NE(static_cast<unsigned char>(utf8[dots - 1]), 0xc3) << "cut inside a character";
}

TEST(Scenario, DeeplyDottedKeysAreRefusedBeforeParsing) {
    // toml++ recurses once per key part; ~100 000 parts overflowed the stack.
    std::string deep = "a";
    for (int i = 0; i < 100000; ++i) deep += ".a";
    expectError(deep + " = 1\n" + kBase, {"more than 32 parts"});
    expectError("[" + deep + "]\nx = 1\n", {"more than 32 parts"});
    // A multi-line string may end in up to two extra quotes; the scan must not lose its place there.
    expectError("name = \"\"\"x\"\"\"\"\n" + deep + " = 1\n", {"more than 32 parts"});
    expectError("name = '''x''''\n" + deep + " = 1\n", {"more than 32 parts"});
    // Dots in numbers, strings and comments are not key parts.
    EXPECT_NO_THROW(parseScenarioString(
        std::string(kBase) + "# a.b.c.d.e.f.g.h.i.j.k.l.m.n.o.p.q.r.s.t.u.v.w.x.y.z.a.b.c.d.e.f.g\n", "ok.toml"));
}

TEST(Scenario, RockRateBelowTheDefaultChannelRateBlamesTheKeyInTheFile) {
    expectError(std::string(kBase) + "p_rate = 1e-9\n", {"stage2.p_rate' = 1e-09", "p_rate_channel (0.001"});
    expectError(std::string(kBase) + "p_rate = 0.1\np_rate_channel = 0.2\n",
                {"stage2.p_rate_channel' = 0.2", "p_rate (0.1)"});
}

TEST(Scenario, SizesThatWouldBreakTheRunAreRefused) {
    std::string t = kBase;
    t.replace(t.find("voxel_size = 2.0"), 16, "voxel_size = 1e-5");
    expectError(t, {"domain.voxel_size", "[0.001, 10000]"});
    expectError(std::string(kBase) + "[rock.noise]\nscale = 5e-324\n", {"rock.noise.scale", "[0.01,"});
    std::string many = kBase;
    for (int i = 0; i < 257; ++i) many += "[[source]]\nat = [1, 1, 1]\n";
    expectError(many, {"key 'source'", "at most 256"});
    std::string planes = kBase;
    for (int i = 0; i < 1025; ++i) planes += "[[rock.plane]]\npoint = [1, 1, 1]\n";
    expectError(planes, {"rock.plane", "at most 1024"});
    std::string pts = std::string(kBase) + "[[rock.channel]]\npoints = [";
    for (int i = 0; i < 65537; ++i) pts += "[1, 1, 1], ";
    expectError(pts + "]\n", {"rock.channel.points", "at most 65536"});
    std::string snaps = std::string(kBase) + "snapshots = [";
    for (int i = 0; i < 33; ++i) snaps += std::to_string(i) + ", ";
    expectError(snaps + "]\n", {"stage2.snapshots", "at most 32"});
}

TEST(Scenario, OnlyRegularFilesAreRead) {
    const auto dir = std::filesystem::temp_directory_path() / "cavesim_test_scenario_dir.toml";
    std::filesystem::create_directories(dir);
    try {
        parseScenarioFile(dir.string());
        FAIL() << "a directory was read as a scenario";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
    }
    EXPECT_THROW(parseScenarioFile("/dev/zero"), InputError);
    std::filesystem::remove(dir);
}

TEST(Scenario, DefaultIsFig10) {
    const Scenario s = defaultScenario();
    EXPECT_EQ(s.name, "fig10");
    EXPECT_EQ(s.size, (std::array<int, 3>{60, 60, 20}));
    EXPECT_EQ(s.sources.size(), 3u);
    EXPECT_EQ(s.stage2.iterations, 240);
}

TEST(Scenario, EveryShippedScenarioValidates) {
    int count = 0;
    for (const auto& e : std::filesystem::directory_iterator(std::string(CAVESIM_SOURCE_DIR) + "/scenarios")) {
        if (e.path().extension() != ".toml") continue;
        EXPECT_NO_THROW(parseScenarioFile(e.path().string())) << e.path();
        ++count;
    }
    EXPECT_GE(count, 1);
}

TEST(Domain, DeterministicAndFeaturesApplied) {
    const std::string t = std::string(kBase) + R"([[rock.sphere]]
center = [10, 5, 4]
radius = 3
core_porosity = 0.0
[[rock.plane]]
point = [0, 0, 1]
normal = [0, 0, 1]
porosity = 0.3
)";
    Scenario s = parseScenarioString(t, "d.toml");
    s.noise.amplitude = 0.02;
    Rng r1(s.seed), r2(s.seed), r3(s.seed + 1);
    const Domain a = buildDomain(s, r1), b = buildDomain(s, r2), c = buildDomain(s, r3);
    EXPECT_EQ(a.porosity.data, b.porosity.data);
    EXPECT_NE(a.porosity.data, c.porosity.data);
    EXPECT_FLOAT_EQ(a.porosity.at(10, 5, 4), 0.0f);  // sphere core
    EXPECT_TRUE(a.flags.at(10, 5, 4) & kObstacle);
    EXPECT_FLOAT_EQ(a.porosity.at(3, 3, 1), 0.3f);  // bedding plane slab
    EXPECT_TRUE(a.flags.at(3, 3, 1) & kFracture);
    EXPECT_TRUE(a.flags.at(2, 5, 6) & kSource);
    EXPECT_TRUE(a.flags.at(18, 4, 1) & kSink);
    EXPECT_EQ(a.sinkVoxels.at(0).size(), 3u * 4u * 3u);
    for (float R : a.porosity.data) {
        EXPECT_GE(R, 0.f);
        EXPECT_LE(R, 1.f);
    }
}

// toml++ 3.3 reaches code it marks unreachable on a non-ASCII character where a key is expected;
// such text is refused before toml++ sees it. Non-ASCII text inside strings and comments is fine.
TEST(Scenario, NonAsciiOutsideStringsIsRefusedBeforeTheParser) {
    expectError("\xc3\xa9 = 1\n", {"bad.toml:1", "non-ASCII"});
    expectError(std::string(kBase) + "[rock]\npor\xc3\xa9sity = 0.1\n", {":16", "non-ASCII"});
    expectError("name = \"x\"\n[domain\xe2\x80\x8b]\n", {":2", "non-ASCII"});
    const Scenario s = parseScenarioString(std::string(kBase) + "# caf\xc3\xa9\n", "test.toml");
    EXPECT_EQ(s.size[0], parseScenarioString(kBase, "test.toml").size[0]);
    // Inside a string it reaches the parser and the key's own check.
    const std::string named = "name = \"caf\xc3\xa9\"\n" + std::string(kBase).substr(std::string(kBase).find('\n') + 1);
    expectError(named, {":1", "key 'name'"});
    EXPECT_EQ(errorOf(named).find("non-ASCII"), std::string::npos);
}

// The effective scenario is read back before it is returned: small negative floats (which toml++
// 3.3 writes through an unsigned conversion) keep their exact values.
TEST(Scenario, EffectiveScenarioKeepsSmallNegativeFloats) {
    Scenario s = parseScenarioString(kBase, "test.toml");
    PlaneFeature p;
    p.normal = {-0.05, -1e-7, 1.0};
    p.point = {-0.09, 0.5, 0.5};
    s.planes.push_back(p);
    const Scenario back = parseScenarioString(scenarioToToml(s), "effective.toml");
    ASSERT_EQ(back.planes.size(), 1u);
    EXPECT_EQ(back.planes[0].normal, p.normal);
    EXPECT_EQ(back.planes[0].point, p.point);
}

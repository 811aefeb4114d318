// The checkpoint file of a run (app/checkpoint.h): what is written reads back the same, and a cut,
// changed or foreign file is refused with an InputError naming it, never a crash.
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "app/checkpoint.h"
#include "core/error.h"
#include "core/fnv.h"
#include "sim/domain.h"

using namespace cavesim;
using namespace cavesim::app;

namespace {

Checkpoint sample() {
    Checkpoint c;
    c.scenarioPath = "scenarios/x.toml";
    c.scenarioText = "name = \"x\"\n";
    c.seed = "12";
    c.formats = "all";
    c.meshStyle = MeshStyle::kVoxel;
    c.force = true;
    c.every = 25;
    c.scenarioHash = 0x1234567890abcdefull;
    c.domainHash = 42;
    c.iteration = 50;
    c.files = {{"images/iter_0010.png", std::string("\x89PNG\0\1", 6)}};
    render::Image f(3, 2);
    f.pixels[4] = 7;
    c.frames = {f};
    c.stage2 = std::string(100000, '\3') + "end";
    return c;
}

}  // namespace

TEST(Checkpoint, ReadsBackWhatWasWritten) {
    const Checkpoint c = sample();
    const std::string bytes = encodeCheckpoint(c);
    const Checkpoint d = decodeCheckpoint(bytes, "ck");
    EXPECT_EQ(d.scenarioPath, c.scenarioPath);
    EXPECT_EQ(d.scenarioText, c.scenarioText);
    EXPECT_EQ(d.seed, c.seed);
    EXPECT_EQ(d.formats, c.formats);
    EXPECT_EQ(d.meshStyle, c.meshStyle);
    EXPECT_EQ(d.meshNormals, c.meshNormals);
    EXPECT_EQ(d.force, c.force);
    EXPECT_EQ(d.every, c.every);
    EXPECT_EQ(d.scenarioHash, c.scenarioHash);
    EXPECT_EQ(d.domainHash, c.domainHash);
    EXPECT_EQ(d.iteration, c.iteration);
    EXPECT_EQ(d.files, c.files);
    ASSERT_EQ(d.frames.size(), 1u);
    EXPECT_EQ(d.frames[0].width, 3);
    EXPECT_EQ(d.frames[0].pixels, c.frames[0].pixels);
    EXPECT_EQ(d.stage2, c.stage2);
    EXPECT_EQ(encodeCheckpoint(d), bytes);  // save → load → save: the same bytes
}

TEST(Checkpoint, CutChangedOrForeignFilesAreRefused) {
    const std::string bytes = encodeCheckpoint(sample());
    for (std::size_t n = 0; n < bytes.size(); n += 1 + bytes.size() / 200)
        EXPECT_THROW(decodeCheckpoint(bytes.substr(0, n), "cut"), InputError) << n;
    for (std::size_t at = 0; at < bytes.size(); at += 1 + bytes.size() / 200) {
        std::string bad = bytes;
        bad[at] = char(bad[at] ^ 0x20);
        EXPECT_THROW(decodeCheckpoint(bad, "changed"), InputError) << at;
    }
    EXPECT_THROW(decodeCheckpoint("", "empty"), InputError);
    EXPECT_THROW(decodeCheckpoint(std::string(64, 'x'), "foreign"), InputError);
    try {
        decodeCheckpoint(bytes.substr(0, bytes.size() / 2), "dir/.x.checkpoint/checkpoint.cavesim");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("dir/.x.checkpoint/checkpoint.cavesim"), std::string::npos) << e.what();
    }
}

TEST(Checkpoint, ReadsVersionsOneAndTwoOnly) {
    // The version (u32 after the 16-byte magic) set to v, and the file checksum made to match.
    const auto withVersion = [](std::uint32_t v) {
        std::string bytes = encodeCheckpoint(sample());
        std::memcpy(bytes.data() + 16, &v, 4);
        Fnv1a64 h;
        h.add(bytes.data(), bytes.size() - 8);
        const std::uint64_t sum = h.value();
        std::memcpy(bytes.data() + bytes.size() - 8, &sum, 8);
        return bytes;
    };
    std::uint32_t written = 0;
    std::memcpy(&written, encodeCheckpoint(sample()).data() + 16, 4);
    EXPECT_EQ(written, 2u);
    // Version 1 has the same layout (its stage-2 state tells the rest: sim/stage2_checkpoint.h).
    EXPECT_EQ(decodeCheckpoint(withVersion(1), "v1").stage2, sample().stage2);
    for (std::uint32_t v : {0u, 3u}) {
        try {
            decodeCheckpoint(withVersion(v), "ck");
            FAIL() << v;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("versions 1 to 2"), std::string::npos) << e.what();
        }
    }
}

TEST(Checkpoint, FolderBesideTheTarget) {
    EXPECT_EQ(checkpointDir("/a/b/out").string(), "/a/b/.out.checkpoint");
    EXPECT_EQ(checkpointDir("/a/b/out/").string(), "/a/b/.out.checkpoint");
}

// A [site] reads stage 2's source pressures (sinkholes.csv) and water table (`from_site`) from
// files: a resume after either changed must be refused, so the fingerprint covers them (it once
// covered only the grids, and a changed water table resumed into different files).
TEST(Checkpoint, FingerprintCoversWhatStageTwoReadsFromSiteFiles) {
    Domain d = emptyDomain(Dims{4, 3, 2}, 1.0, 0.05f);
    d.sourcePressure = {1.0, 0.5};
    d.siteWaterTable.assign(12, 0.5);
    const std::uint64_t base = domainFingerprint(d);
    EXPECT_EQ(domainFingerprint(d), base);
    Domain pressure = d;
    pressure.sourcePressure[1] = 0.25;
    EXPECT_NE(domainFingerprint(pressure), base);
    Domain table = d;
    table.siteWaterTable[5] = 0.75;
    EXPECT_NE(domainFingerprint(table), base);
    Domain grids = d;
    grids.porosity.at(1, 1, 1) = 0.5f;
    EXPECT_NE(domainFingerprint(grids), base);
}

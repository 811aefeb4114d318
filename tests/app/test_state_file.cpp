// The checked state format (app/state_file.h): exact round trip, and every kind of damage refused
// with InputError (never a crash: the fuzz target fuzz/fuzz_state_file.cpp tries the rest).
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "app/state_file.h"
#include "core/error.h"
#include "core/fnv.h"

using namespace cavesim;
using namespace cavesim::app;

namespace {

struct Sample {
    Dims dims{5, 3, 2};
    Grid3<float> f{dims, 0.f};
    Grid3<std::int32_t> i{dims, 0};
    Sample() {
        for (std::size_t v = 0; v < f.size(); ++v) {
            f[v] = float(v) * 0.25f - 1.f;
            i[v] = int(v % 7) - 1;
        }
    }
    std::string bytes() const { return encodeState(dims, 0.5, {{"porosity", &f, nullptr}, {"zone", nullptr, &i}}); }
};

/// `b` with its trailing file checksum recomputed, so the damage reaches the structure checks.
std::string fixedUp(std::string b) {
    Fnv1a64 h;
    h.add(b.data(), b.size() - 8);
    const std::uint64_t v = h.value();
    std::memcpy(b.data() + b.size() - 8, &v, 8);
    return b;
}

}  // namespace

TEST(StateFile, RoundTripIsExact) {
    const Sample s;
    const StateContents back = decodeState(s.bytes(), "t", s.dims);
    EXPECT_EQ(back.dims, s.dims);
    EXPECT_EQ(back.voxelSize, 0.5);
    ASSERT_EQ(back.grids.size(), 2u);
    EXPECT_EQ(back.grids[0].name, "porosity");
    EXPECT_TRUE(back.grids[0].isFloat);
    EXPECT_EQ(back.grids[0].floats.data, s.f.data);
    EXPECT_EQ(back.grids[1].name, "zone");
    EXPECT_FALSE(back.grids[1].isFloat);
    EXPECT_EQ(back.grids[1].ints.data, s.i.data);
    EXPECT_EQ(s.bytes(), s.bytes());  // deterministic
}

TEST(StateFile, ManyChunksRoundTrip) {
    const Dims d{1024, 1024, 3};  // three chunks of 2^20 values
    Grid3<float> f(d, 0.f);
    for (std::size_t v = 0; v < f.size(); v += 997) f[v] = float(v);
    const StateContents back = decodeState(encodeState(d, 1.0, {{"water", &f, nullptr}}), "t", d);
    EXPECT_EQ(back.grids.at(0).floats.data, f.data);
}

TEST(StateFile, DamageIsRefused) {
    const Sample s;
    const std::string good = s.bytes();
    EXPECT_THROW(decodeState("", "t", s.dims), InputError);
    EXPECT_THROW(decodeState(good.substr(0, 30), "t", s.dims), InputError);
    EXPECT_THROW(decodeState(fixedUp(good.substr(0, good.size() - 20) + std::string(8, '\0')), "t", s.dims),
                 InputError);                                         // cut inside the data
    EXPECT_THROW(decodeState(good, "t", Dims{5, 3, 3}), InputError);  // another grid
    std::string flipped = good;
    flipped[good.size() / 2] ^= 1;
    EXPECT_THROW(decodeState(flipped, "t", s.dims), InputError);           // file checksum
    EXPECT_THROW(decodeState(fixedUp(flipped), "t", s.dims), InputError);  // grid data or checksum
    std::string huge = good;
    const std::uint32_t big = 0xffffffffu;
    std::memcpy(huge.data() + 20, &big, 4);  // nx
    EXPECT_THROW(decodeState(fixedUp(huge), "t", s.dims), InputError);
    std::string name = good;
    name[16 + 4 + 12 + 8 + 4 + 1] = 'P';  // the first grid's name: upper case is never written
    EXPECT_THROW(decodeState(fixedUp(name), "t", s.dims), InputError);
    try {
        decodeState(flipped, "dir/state.cavesim", s.dims);
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("dir/state.cavesim"), std::string::npos) << e.what();
    }
}

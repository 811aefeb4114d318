// The checkpoint's byte encoding: values and arrays round-trip, empty arrays included (an empty
// vector's data() may be null: nothing may be copied from or to it), and every inconsistency in
// the bytes is an InputError naming what was being read.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "core/bytes.h"
#include "core/error.h"

namespace cavesim {
namespace {

TEST(Bytes, ValuesAndArraysRoundTripEmptyOnesIncluded) {
    std::string out;
    ByteWriter w(out);
    w.put(std::int32_t(-7));
    w.putVector(std::vector<std::uint32_t>{});
    w.putVector(std::vector<double>{1.5, -2.25});
    w.putBools({true, false, true});
    w.putString("");
    w.putString("tile");
    ByteReader r(out.data(), out.size(), "test");
    EXPECT_EQ(r.get<std::int32_t>("int"), -7);
    std::vector<std::uint32_t> empty{9, 9};
    r.getVector(empty, "empty");
    EXPECT_TRUE(empty.empty());
    std::vector<double> two;
    r.getVector(two, "two", 2);
    EXPECT_EQ(two, (std::vector<double>{1.5, -2.25}));
    std::vector<bool> bits;
    r.getBools(bits, "bits");
    EXPECT_EQ(bits, (std::vector<bool>{true, false, true}));
    EXPECT_EQ(r.getString("nothing"), "");
    EXPECT_EQ(r.getString("word"), "tile");
}

TEST(Bytes, CutOrInconsistentBytesAreInputErrors) {
    std::string out;
    ByteWriter w(out);
    w.putVector(std::vector<std::uint32_t>{1, 2, 3});
    {
        ByteReader r(out.data(), out.size() - 1, "cut");  // the last element cut short
        std::vector<std::uint32_t> v;
        EXPECT_THROW(r.getVector(v, "ids"), InputError);
    }
    {
        ByteReader r(out.data(), out.size(), "count");  // a count other than the expected one
        std::vector<std::uint32_t> v;
        EXPECT_THROW(r.getVector(v, "ids", 4), InputError);
    }
    {
        std::string huge;
        ByteWriter(huge).put(std::uint64_t(1) << 60);  // a count far beyond the bytes left
        ByteReader r(huge.data(), huge.size(), "huge");
        std::vector<double> v;
        EXPECT_THROW(r.getVector(v, "values"), InputError);
    }
    {
        std::string bad;
        ByteWriter(bad).putVector(std::vector<std::uint8_t>{0, 2});
        ByteReader r(bad.data(), bad.size(), "bools");
        std::vector<bool> v;
        EXPECT_THROW(r.getBools(v, "flags"), InputError);
    }
}

}  // namespace
}  // namespace cavesim

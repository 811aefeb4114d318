// FNV-1a 64 against the published test vectors, and piecewise feeding.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <string>

#include "core/fnv.h"

namespace cavesim {
namespace {

std::uint64_t hashOf(const std::string& s) {
    Fnv1a64 h;
    h.add(s.data(), s.size());
    return h.value();
}

// The published FNV-1a 64 vectors start from the offset basis 14695981039346656037
// (0xcbf29ce484222325). core/fnv.h starts from 1469598103934665603 (the same digits without the
// final 7), as the three hashes it replaced did, so its values are not standard FNV-1a. Fixing the
// constant changes the .vdb tags and the report checksums of every run, so it is left for a change
// that may alter outputs; enable this test with that fix.
TEST(Fnv1a64, DISABLED_PublishedTestVectors) {
    EXPECT_EQ(hashOf(""), 0xcbf29ce484222325ull);  // the offset basis
    EXPECT_EQ(hashOf("a"), 0xaf63dc4c8601ec8cull);
    EXPECT_EQ(hashOf("foobar"), 0x85944171f73967e8ull);
    EXPECT_EQ(Fnv1a64().hex(), "cbf29ce484222325");
}

// What the outputs depend on today: the basis in use and the FNV-1a step (xor, then multiply by
// the 64-bit FNV prime 2^40 + 2^8 + 0xb3), byte by byte.
TEST(Fnv1a64, BasisAndStepInUse) {
    constexpr std::uint64_t kBasis = 1469598103934665603ull;
    constexpr std::uint64_t kPrime = 1099511628211ull;
    static_assert(kPrime == (1ull << 40) + (1ull << 8) + 0xb3);
    EXPECT_EQ(hashOf(""), kBasis);
    EXPECT_EQ(hashOf("a"), (kBasis ^ 0x61u) * kPrime);
    std::uint64_t h = kBasis;
    for (unsigned char c : std::string("foobar")) h = (h ^ c) * kPrime;
    EXPECT_EQ(hashOf("foobar"), h);
}

TEST(Fnv1a64, HexIsSixteenLowerCaseDigits) {
    EXPECT_EQ(Fnv1a64().hex(), "14650fb0739d0383");
    Fnv1a64 h;
    h.add("foobar", 6);
    char expected[17];
    std::snprintf(expected, sizeof expected, "%016llx", static_cast<unsigned long long>(h.value()));
    EXPECT_EQ(h.hex(), expected);
    EXPECT_EQ(h.hex().size(), 16u);
}

TEST(Fnv1a64, PiecesHashLikeTheWhole) {
    Fnv1a64 h;
    h.add("foo", 3);
    h.add("", 0);
    h.add("bar", 3);
    EXPECT_EQ(h.value(), hashOf("foobar"));
    EXPECT_NE(hashOf("foobar"), hashOf("barfoo"));
}

TEST(Fnv1a64, HashesRawBytesOfValues) {
    const double x = 1.5;
    unsigned char bytes[sizeof x];
    std::memcpy(bytes, &x, sizeof x);
    Fnv1a64 a, b;
    a.add(&x, sizeof x);
    b.add(bytes, sizeof bytes);
    EXPECT_EQ(a.value(), b.value());
}

}  // namespace
}  // namespace cavesim

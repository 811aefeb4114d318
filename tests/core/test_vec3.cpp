// Vec3d helpers against exact answers (all values exactly representable).
#include <gtest/gtest.h>

#include <cmath>

#include "core/vec3.h"

namespace cavesim {
namespace {

constexpr Vec3d kX{1, 0, 0}, kY{0, 1, 0}, kZ{0, 0, 1};

// std::array's operator== is not constexpr before C++20.
constexpr bool same(const Vec3d& a, const Vec3d& b) {
    return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

// The arithmetic helpers are usable in constant expressions.
static_assert(dot(Vec3d{1, 2, 3}, Vec3d{4, -5, 6}) == 12.0);
static_assert(same(cross(kX, kY), kZ));
static_assert(same(add(Vec3d{1, 2, 3}, Vec3d{0.5, 0.5, 0.5}), Vec3d{1.5, 2.5, 3.5}));
static_assert(same(sub(Vec3d{1, 2, 3}, Vec3d{1, 1, 1}), Vec3d{0, 1, 2}));
static_assert(same(scale(Vec3d{1, -2, 3}, 2.0), Vec3d{2, -4, 6}));

TEST(Vec3, CrossIsRightHandedAndAntisymmetric) {
    EXPECT_EQ(cross(kY, kZ), kX);
    EXPECT_EQ(cross(kZ, kX), kY);
    EXPECT_EQ(cross(kY, kX), (Vec3d{0, 0, -1}));
    const Vec3d a{2, 3, 5}, b{-1, 4, 7};
    EXPECT_EQ(cross(a, b), (Vec3d{3 * 7 - 5 * 4, 5 * -1 - 2 * 7, 2 * 4 - 3 * -1}));
    EXPECT_EQ(dot(cross(a, b), a), 0.0);
    EXPECT_EQ(dot(cross(a, b), b), 0.0);
}

TEST(Vec3, NormAndDistance) {
    EXPECT_EQ(norm(Vec3d{3, 4, 12}), 13.0);
    EXPECT_EQ(norm(Vec3d{0, 0, 0}), 0.0);
    EXPECT_EQ(distance(Vec3d{1, 1, 1}, Vec3d{4, 5, 13}), 13.0);
    EXPECT_EQ(distance(Vec3d{4, 5, 13}, Vec3d{1, 1, 1}), 13.0);
}

TEST(Vec3, Normalized) {
    EXPECT_EQ(normalized(Vec3d{0, 0, 8}), kZ);
    const Vec3d n = normalized(Vec3d{3, 4, 12});
    EXPECT_DOUBLE_EQ(n[0], 3.0 / 13.0);
    EXPECT_DOUBLE_EQ(n[1], 4.0 / 13.0);
    EXPECT_DOUBLE_EQ(n[2], 12.0 / 13.0);
    EXPECT_NEAR(norm(n), 1.0, 1e-15);
    EXPECT_EQ(normalized(Vec3d{0, 0, 0}), (Vec3d{0, 0, 0}));  // zero stays zero
}

}  // namespace
}  // namespace cavesim

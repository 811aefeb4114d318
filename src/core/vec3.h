/// @file vec3.h
/// @brief The one 3-vector of cavesim (`Vec3d`) and its free helpers.
///
/// `Vec3d` is a plain `std::array<double, 3>`: (x, y, z), z up, in whatever space the caller says
/// (world metres or voxel index units; the helpers do not care). The helpers evaluate their sums in a
/// fixed order (x, then y, then z), so results are reproducible bit for bit. `src/sim/scenario.h`
/// declares the same alias; identical alias declarations may coexist.
#pragma once

#include <array>
#include <cmath>

namespace cavesim {

/// π to double precision.
inline constexpr double kPi = 3.14159265358979323846;

/// A 3-vector (x, y, z).
using Vec3d = std::array<double, 3>;

/// a + b.
constexpr Vec3d add(const Vec3d& a, const Vec3d& b) {
    return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}

/// a − b.
constexpr Vec3d sub(const Vec3d& a, const Vec3d& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}

/// s · a.
constexpr Vec3d scale(const Vec3d& a, double s) {
    return {a[0] * s, a[1] * s, a[2] * s};
}

/// a · b, summed x + y + z.
constexpr double dot(const Vec3d& a, const Vec3d& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/// a × b (right-handed).
constexpr Vec3d cross(const Vec3d& a, const Vec3d& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

/// Euclidean length |a| = √(a · a).
inline double norm(const Vec3d& a) {
    return std::sqrt(dot(a, a));
}

/// a / |a| (computed as a · (1 / |a|)); a zero (or NaN-length) vector is returned unchanged.
inline Vec3d normalized(const Vec3d& a) {
    const double n = norm(a);
    return n > 0 ? scale(a, 1.0 / n) : a;
}

/// Euclidean distance |b − a|.
inline double distance(const Vec3d& a, const Vec3d& b) {
    return norm(sub(b, a));
}

}  // namespace cavesim

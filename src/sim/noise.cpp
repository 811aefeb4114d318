#include "sim/noise.h"

#include <cmath>
#include <numeric>

namespace cavesim {
namespace {

double fade(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }
double lerp(double t, double a, double b) { return a + t * (b - a); }
double grad(int hash, double x, double y, double z) {
    const int h = hash & 15;
    const double u = h < 8 ? x : y;
    const double v = h < 4 ? y : (h == 12 || h == 14 ? x : z);
    return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}

}  // namespace

GradientNoise::GradientNoise(std::mt19937_64& rng) {
    std::array<int, 256> p;
    std::iota(p.begin(), p.end(), 0);
    // Fisher–Yates with the engine's raw output (std::shuffle's result is library-specific).
    for (int i = 255; i > 0; --i) {
        const int j = int(rng() % std::uint64_t(i + 1));
        std::swap(p[i], p[j]);
    }
    for (int i = 0; i < 512; ++i) perm_[i] = std::uint8_t(p[i & 255]);
}

double GradientNoise::sample(double x, double y, double z) const {
    const double fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
    const int X = int(fx) & 255, Y = int(fy) & 255, Z = int(fz) & 255;
    x -= fx;
    y -= fy;
    z -= fz;
    const double u = fade(x), v = fade(y), w = fade(z);
    const int A = perm_[X] + Y, AA = perm_[A] + Z, AB = perm_[A + 1] + Z;
    const int B = perm_[X + 1] + Y, BA = perm_[B] + Z, BB = perm_[B + 1] + Z;
    return lerp(w,
                lerp(v, lerp(u, grad(perm_[AA], x, y, z), grad(perm_[BA], x - 1, y, z)),
                     lerp(u, grad(perm_[AB], x, y - 1, z), grad(perm_[BB], x - 1, y - 1, z))),
                lerp(v, lerp(u, grad(perm_[AA + 1], x, y, z - 1), grad(perm_[BA + 1], x - 1, y, z - 1)),
                     lerp(u, grad(perm_[AB + 1], x, y - 1, z - 1), grad(perm_[BB + 1], x - 1, y - 1, z - 1))));
}

double GradientNoise::fractal(double x, double y, double z, int octaves) const {
    double sum = 0, amp = 1, norm = 0, f = 1;
    for (int o = 0; o < octaves; ++o) {
        sum += amp * sample(x * f, y * f, z * f);
        norm += amp;
        amp *= 0.5;
        f *= 2.0;
    }
    const double v = sum / norm;
    return v < -1 ? -1 : (v > 1 ? 1 : v);
}

}  // namespace cavesim

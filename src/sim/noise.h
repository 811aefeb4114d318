/// @file noise.h
/// @brief Seeded 3D gradient noise (Perlin's improved noise with a shuffled permutation) for rock porosity.
#pragma once

#include <array>
#include <cstdint>
#include <random>

namespace cavesim {

/// Fractal gradient noise in roughly [-1, 1]. The permutation is drawn from the engine passed in,
/// so the field is a pure function of that engine's state: no global state.
class GradientNoise {
public:
    explicit GradientNoise(std::mt19937_64& rng);
    /// One octave at point p (any units; features have size ~1).
    double sample(double x, double y, double z) const;
    /// `octaves` octaves, each at double frequency and half amplitude, normalised to [-1, 1].
    double fractal(double x, double y, double z, int octaves) const;

private:
    std::array<std::uint8_t, 512> perm_{};
};

}  // namespace cavesim

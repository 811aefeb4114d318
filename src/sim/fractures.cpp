#include "sim/fractures.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "core/check.h"
#include "core/vec3.h"

namespace cavesim {
namespace {

constexpr double kDegree = kPi / 180.0;

Eigen::Vector3d eig(const Vec3d& v) {
    return {v[0], v[1], v[2]};
}

/// The draw box's margin around the block on every side: max_length / 2, so that every disc that
/// can reach the block has its centre in the box.
double drawMargin(const FractureFamily& f) {
    return 0.5 * std::max(0.0, f.maxLength);
}

/// rasteriseDisc, and with `inception` also sets the slab's voxels to 1 there, in the same walk.
long rasteriseSlab(const FractureDisc& disc, double thickness, float porosity, Grid3<float>& porosityGrid,
                   Grid3<std::uint8_t>& flags, Grid3<std::uint8_t>* inception) {
    long midPlane = 0;
    forEachDiscVoxel(disc, thickness, porosityGrid.dims, [&](int i, int j, int k, double h, bool inDisc) {
        if (!inDisc) return;
        if (std::abs(h) <= 0.5) ++midPlane;
        if (std::abs(h) > 0.5 * thickness) return;
        float& R = porosityGrid.at(i, j, k);
        R = std::max(R, porosity);
        flags.at(i, j, k) |= kFracture;
        if (inception) inception->at(i, j, k) = 1;
    });
    return midPlane;
}

}  // namespace

Vec3d poleFromOrientation(double dipDirection, double dip) {
    const double t = dipDirection * kDegree, d = dip * kDegree;
    return {std::sin(t) * std::sin(d), std::cos(t) * std::sin(d), std::cos(d)};
}

void orientationFromPole(const Vec3d& pole, double& dipDirection, double& dip) {
    Eigen::Vector3d n = eig(pole);
    const double len = n.norm();
    CAVESIM_CHECK(len > 0, "orientationFromPole: a zero pole");
    n /= len;
    if (n.z() < 0) n = -n;
    dip = std::acos(std::min(1.0, n.z())) / kDegree;
    const double horizontal = std::hypot(n.x(), n.y());
    dipDirection = horizontal > 1e-12 ? std::atan2(n.x(), n.y()) / kDegree : 0.0;
    if (dipDirection < 0) dipDirection += 360.0;
    if (dipDirection >= 360.0) dipDirection -= 360.0;
}

std::uint64_t familySeed(std::uint64_t seed, std::size_t family) {
    // SplitMix64 of the seed, then of that mixed with the family index.
    const auto mix = [](std::uint64_t z) {
        z += 0x9e3779b97f4a7c15ull;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    };
    return mix(mix(seed ^ 0x46524143ull /* "FRAC" */) + std::uint64_t(family));
}

double uniformOpen01(Rng& rng) {
    return (double(rng() >> 11) + 1.0) * 0x1.0p-53;
}

Vec3d sampleFisher(const Vec3d& mean, double kappa, Rng& rng) {
    CAVESIM_CHECK(kappa > 0, "sampleFisher: kappa must be positive");
    const double u = uniformOpen01(rng), v = uniformOpen01(rng);
    // cos θ from the inverse CDF, written to stay accurate for large kappa (e^(−2κ) underflows to 0).
    // For small kappa e^(−2κ) rounds to 1 and ln(…) / κ to 0 or noise (every pole on the mean below
    // κ ≈ 1e-16): there ln(1 − (1 − u)(1 − e^(−2κ))) is taken through log1p and expm1.
    const double lnTerm = kappa < 1e-3 ? std::log1p(-(1.0 - u) * -std::expm1(-2.0 * kappa))
                                       : std::log(u + (1.0 - u) * std::exp(-2.0 * kappa));
    const double w = std::clamp(1.0 + lnTerm / kappa, -1.0, 1.0);
    const double s = std::sqrt(std::max(0.0, 1.0 - w * w)), phi = 2.0 * kPi * v;
    const Eigen::Vector3d local(s * std::cos(phi), s * std::sin(phi), w);
    const Eigen::Vector3d m = eig(mean).normalized();
    const Eigen::Vector3d out = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), m) * local;
    const Eigen::Vector3d unit = out.normalized();
    return {unit.x(), unit.y(), unit.z()};
}

double samplePowerLaw(double exponent, double lo, double hi, Rng& rng) {
    CAVESIM_CHECK(lo > 0 && hi >= lo, "samplePowerLaw: needs 0 < lo <= hi");
    const double u = uniformOpen01(rng);
    if (hi == lo) return lo;
    if (std::abs(exponent - 1.0) < 1e-12) return lo * std::pow(hi / lo, u);
    const double g = 1.0 - exponent;
    const double a = std::pow(lo, g), b = std::pow(hi, g);
    return std::clamp(std::pow(a + u * (b - a), 1.0 / g), lo, hi);
}

double meanDiscArea(double exponent, double lo, double hi) {
    // E[l²] of p(l) = C l^(−a) on [lo, hi], times π / 4.
    if (hi <= lo) return kPi / 4.0 * lo * lo;
    const auto integral = [&](double power) {  // ∫ l^power dl over [lo, hi]
        if (std::abs(power + 1.0) < 1e-12) return std::log(hi / lo);
        return (std::pow(hi, power + 1.0) - std::pow(lo, power + 1.0)) / (power + 1.0);
    };
    return kPi / 4.0 * integral(2.0 - exponent) / integral(-exponent);
}

double estimateKappa(const std::vector<Vec3d>& unitVectors) {
    const double n = double(unitVectors.size());
    if (n < 2) return 0.0;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const Vec3d& v : unitVectors) sum += eig(v);
    const double r = sum.norm();
    return n - r > 0 ? (n - 1.0) / (n - r) : 0.0;
}

double fractureDrawVolume(const FractureFamily& f, const Dims& dims) {
    const double grow = 2 * drawMargin(f);
    return (double(dims.nx) + grow) * (double(dims.ny) + grow) * (double(dims.nz) + grow);
}

double fractureCount(const FractureFamily& f, const Dims& dims) {
    const double volume = fractureDrawVolume(f, dims);
    if (f.density > 0) return std::round(f.density * volume);
    if (!(f.spacing > 0)) return 0.0;
    return std::round(volume / (f.spacing * meanDiscArea(f.lengthExponent, f.minLength, f.maxLength)));
}

namespace {

/// Draws one disc of family `f` (centre, pole, diameter: four draws and one of the length) into
/// `d`; whether its axis-aligned extent overlaps the block.
bool drawDisc(const FractureFamily& f, const Vec3d& mean, double grow, const double size[3], Rng& rng,
              FractureDisc& d) {
    for (int ax = 0; ax < 3; ++ax)
        d.centre[ax] = -0.5 - grow + (uniformOpen01(rng) - 0x1.0p-54) * (size[ax] + 2 * grow);
    d.normal = sampleFisher(mean, f.kappa, rng);
    d.radius = 0.5 * samplePowerLaw(f.lengthExponent, f.minLength, f.maxLength, rng);
    bool reaches = true;
    for (int ax = 0; ax < 3; ++ax) {
        const double extent = d.radius * std::sqrt(std::max(0.0, 1.0 - d.normal[ax] * d.normal[ax]));
        reaches = reaches && d.centre[ax] + extent >= -0.5 && d.centre[ax] - extent <= size[ax] - 0.5;
    }
    return reaches;
}

}  // namespace

bool fractureFamilyReachesBlock(const std::vector<FractureFamily>& families, std::size_t family, const Dims& dims,
                                std::uint64_t seed) {
    const FractureFamily& f = families[family];
    const double count = fractureCount(f, dims);
    const double size[3] = {double(dims.nx), double(dims.ny), double(dims.nz)};
    Rng rng(familySeed(seed, family));
    const Vec3d mean = poleFromOrientation(f.dipDirection, f.dip);
    const double grow = drawMargin(f);
    for (long n = 0; n < long(count); ++n) {
        FractureDisc d;
        if (drawDisc(f, mean, grow, size, rng, d)) return true;
    }
    return false;
}

FractureNetwork generateFractureNetwork(const std::vector<FractureFamily>& families, const Dims& dims,
                                        std::uint64_t seed) {
    FractureNetwork net;
    const double size[3] = {double(dims.nx), double(dims.ny), double(dims.nz)};
    for (std::size_t fi = 0; fi < families.size(); ++fi) {
        const FractureFamily& f = families[fi];
        const double count = fractureCount(f, dims);
        CAVESIM_CHECK(count >= 1 && count <= 1e6, "generateFractureNetwork: a family of an unchecked size");
        Rng rng(familySeed(seed, fi));
        const Vec3d mean = poleFromOrientation(f.dipDirection, f.dip);
        const double grow = drawMargin(f);
        FractureFamilyStats st;
        std::vector<Vec3d> poles;
        double lengthSum = 0, areaSum = 0;
        for (long n = 0; n < long(count); ++n) {
            FractureDisc d;
            d.family = int(fi);
            if (!drawDisc(f, mean, grow, size, rng, d)) continue;
            ++st.count;
            lengthSum += 2 * d.radius;  // the diameter drawn (halving and doubling are exact)
            areaSum += kPi * d.radius * d.radius;
            poles.push_back(d.normal);
            net.discs.push_back(d);
        }
        if (st.count > 0) {
            Vec3d resultant{0, 0, 0};
            for (const Vec3d& p : poles)
                for (int ax = 0; ax < 3; ++ax) resultant[ax] += p[ax];
            orientationFromPole(resultant, st.meanDipDirection, st.meanDip);
            st.kappaEstimate = estimateKappa(poles);
            st.meanLength = lengthSum / double(st.count);
        }
        st.p32Nominal = areaSum / (size[0] * size[1] * size[2]);
        net.families.push_back(st);
    }
    return net;
}

long rasteriseDisc(const FractureDisc& disc, double thickness, float porosity, Grid3<float>& porosityGrid,
                   Grid3<std::uint8_t>& flags) {
    return rasteriseSlab(disc, thickness, porosity, porosityGrid, flags, nullptr);
}

void measureFractureNetwork(FractureNetwork& net, const std::vector<FractureFamily>& families, const Dims& dims) {
    const double volume = double(dims.nx) * double(dims.ny) * double(dims.nz);
    std::vector<long> midPlane(net.families.size(), 0);
    for (FractureFamilyStats& st : net.families) st.voxels = 0;
    for (const FractureDisc& d : net.discs) {
        const double t = families[std::size_t(d.family)].aperture;
        FractureFamilyStats& st = net.families[std::size_t(d.family)];
        forEachDiscVoxel(d, t, dims, [&](int, int, int, double h, bool inDisc) {
            if (!inDisc) return;
            if (std::abs(h) <= 0.5) ++midPlane[std::size_t(d.family)];
            if (std::abs(h) <= 0.5 * t) ++st.voxels;
        });
    }
    for (std::size_t f = 0; f < net.families.size(); ++f) net.families[f].p32 = double(midPlane[f]) / volume;
}

void applyFractureNetwork(Domain& dom, const FractureNetwork& net, const std::vector<FractureFamily>& families) {
    // A fracture is an early-flow path like an inception horizon: mark its slab for stage 2.
    Grid3<std::uint8_t>* early = dom.inception.data.empty() ? nullptr : &dom.inception;
    for (const FractureDisc& d : net.discs) {
        const FractureFamily& f = families[std::size_t(d.family)];
        rasteriseSlab(d, f.aperture, float(f.porosity), dom.porosity, dom.flags, early);
    }
}

}  // namespace cavesim

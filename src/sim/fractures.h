/// @file fractures.h
/// @brief Fracture families (`[[rock.fracture_family]]`): a discrete fracture network (DFN) of
/// discs drawn from the scenario's seed, rasterised into the porosity grid, and measured back.
///
/// Not in Pytel & Mann (2015), whose fractures are planes drawn by hand; this is the usual
/// stochastic DFN of fractured-rock hydrogeology as KarstNSim (Gouy et al. 2024) takes it as input:
/// Fisher-distributed poles about a family's mean pole, power-law disc diameters, centres uniform
/// in the block. docs/geology.md, "Fracture families", states the rules.
///
/// Every length and position is in voxel (index) units: voxel (i, j, k) sits at (i, j, k). Each
/// family draws from its own engine, seeded by `familySeed(seed, family)`, and every variate is
/// made by hand from the engine's 64-bit integers (std:: distributions differ between standard
/// libraries), so the same scenario gives the same discs everywhere; the main `Rng` of a run is
/// not touched (a scenario without fracture families draws exactly what it drew before).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/grid.h"
#include "sim/domain.h"
#include "sim/scenario.h"

namespace cavesim {

/// One fracture: a disc of raised porosity.
struct FractureDisc {
    Vec3d centre{0, 0, 0};  ///< voxels
    Vec3d normal{0, 0, 1};  ///< unit pole (either sense)
    double radius = 1.0;    ///< voxels: half the diameter drawn from the length law
    int family = 0;         ///< index into the scenario's fracture families
};

/// One family's discs as drawn and as measured back.
struct FractureFamilyStats {
    long count = 0;               ///< discs that reach the block
    double meanDipDirection = 0;  ///< degrees, of the mean resultant of the poles
    double meanDip = 0;           ///< degrees
    double kappaEstimate = 0;     ///< Fisher's estimate (N − 1) / (N − |Σ n|); 0 below 2 discs
    double meanLength = 0;        ///< voxels: mean disc diameter
    double p32Nominal = 0;        ///< 1/voxel: total disc area / block volume
    double p32 = 0;               ///< 1/voxel: disc area inside the block / block volume (mid-plane voxel count)
    long voxels = 0;              ///< voxels inside the family's slabs (a voxel in two discs counts twice)
};

/// The discs of every family, family by family.
struct FractureNetwork {
    std::vector<FractureDisc> discs;
    std::vector<FractureFamilyStats> families;  ///< counts, orientations and lengths (p32 and voxels: measure)
};

/// The unit upward pole (z ≥ 0) of a plane dipping `dip` degrees toward azimuth `dipDirection`
/// degrees (clockwise from +y): (sin θ sin δ, cos θ sin δ, cos δ).
Vec3d poleFromOrientation(double dipDirection, double dip);

/// The dip direction and dip (degrees) of the plane with pole `pole` (any length and sense; the
/// upward sense is used). A horizontal plane has dip direction 0.
void orientationFromPole(const Vec3d& pole, double& dipDirection, double& dip);

/// The seed of family `family`'s engine: a SplitMix64 mix of the scenario seed and the index.
std::uint64_t familySeed(std::uint64_t seed, std::size_t family);

/// A uniform variate in (0, 1]: (top 53 bits of one draw + 1) · 2⁻⁵³.
double uniformOpen01(Rng& rng);

/// A unit vector from the Fisher distribution of concentration `kappa` (> 0) about the unit
/// vector `mean`: cos θ = 1 + ln(u + (1 − u) e^(−2κ)) / κ, azimuth 2πv, rotated from +z onto
/// `mean` (Eigen). Two draws.
Vec3d sampleFisher(const Vec3d& mean, double kappa, Rng& rng);

/// A length from p(l) ∝ l^(−a) on [lo, hi] (0 < lo ≤ hi) by inversion of its CDF (a = 1: log-uniform). One draw.
double samplePowerLaw(double exponent, double lo, double hi, Rng& rng);

/// E[π l² / 4] under that law: the mean disc area, voxels².
double meanDiscArea(double exponent, double lo, double hi);

/// Whether family `family` of `families`, drawn as generateFractureNetwork draws it from `seed`,
/// keeps at least one disc that reaches the block (it stops at the first).
bool fractureFamilyReachesBlock(const std::vector<FractureFamily>& families, std::size_t family, const Dims& dims,
                                std::uint64_t seed);

/// Fisher's estimate of kappa from unit vectors: (N − 1) / (N − |Σ n|) (0 for fewer than 2).
double estimateKappa(const std::vector<Vec3d>& unitVectors);

/// The block's box [−0.5, n − 0.5] grown by max_length / 2 on every side: every disc that can reach
/// the block has its centre in it. Its volume, voxels³.
double fractureDrawVolume(const FractureFamily& family, const Dims& dims);

/// The number of disc centres drawn for `family` in the grown box of `fractureDrawVolume` (V_D):
/// round(density · V_D), or round(V_D / (spacing · meanDiscArea)). Centres uniform in all of space
/// at that intensity give P32 = 1 / spacing inside any block, whatever the discs' size: counting in
/// the block alone loses the area of the discs cut by its faces (a thin block kept well under half
/// of it). Not checked against limits (validateScenario does that).
double fractureCount(const FractureFamily& family, const Dims& dims);

/// Draws the discs of every family (validated: every count in 1..10⁶). Centres uniform in the
/// grown box of `fractureDrawVolume`; per candidate three draws for the centre, two for the pole,
/// one for the diameter, in that order; a candidate is kept when its axis-aligned extent
/// (centre ± radius · √(1 − n_a²) per axis) overlaps the block.
FractureNetwork generateFractureNetwork(const std::vector<FractureFamily>& families, const Dims& dims,
                                        std::uint64_t seed);

/// Calls `visit(i, j, k, h, inDisc)` for every voxel of `dims` within distance max(thickness, 1) / 2
/// of the disc's plane (h = signed distance along the pole), `inDisc` = its in-plane distance from the
/// centre is at most the radius. Candidates are found column by column along the pole's largest
/// axis: the work is proportional to the disc's area, not its bounding box.
template <typename Visit>
void forEachDiscVoxel(const FractureDisc& disc, double thickness, const Dims& dims, Visit&& visit);

/// Raises porosity to `porosity` (max with what is there) and sets kFracture on the voxels of the
/// disc's slab: |h| ≤ thickness / 2 and in-plane distance ≤ radius. Returns the voxels in the unit
/// slab |h| ≤ 1/2 inside the disc (its area inside the block, in voxels², to about a voxel).
long rasteriseDisc(const FractureDisc& disc, double thickness, float porosity, Grid3<float>& porosityGrid,
                   Grid3<std::uint8_t>& flags);

/// Fills `p32` and `voxels` of `network.families` without touching a grid (what rasterising into
/// a block of `dims` would count).
void measureFractureNetwork(FractureNetwork& network, const std::vector<FractureFamily>& families, const Dims& dims);

/// Rasterises every disc of `network` into `domain` (rasteriseDisc) with its family's aperture and
/// porosity, in disc order (the result does not depend on it: max and or). When `domain.inception`
/// is allocated, the same slab voxels are set to 1 there: a fracture of a family is an early-flow
/// path, like an inception horizon (stage 2 reads their rate from porosity against the rock's).
void applyFractureNetwork(Domain& domain, const FractureNetwork& network, const std::vector<FractureFamily>& families);

// ---------------------------------------------------------------------------------------------

template <typename Visit>
void forEachDiscVoxel(const FractureDisc& disc, double thickness, const Dims& dims, Visit&& visit) {
    const Vec3d& c = disc.centre;
    const Vec3d& n = disc.normal;
    const int size[3] = {dims.nx, dims.ny, dims.nz};
    int a = 0;
    for (int ax = 1; ax < 3; ++ax)
        if (std::abs(n[ax]) > std::abs(n[a])) a = ax;
    const int b = (a + 1) % 3, e = (a + 2) % 3;
    const double half = 0.5 * std::max(thickness, 1.0);
    const double r2 = disc.radius * disc.radius;
    int lo[3], hi[3];
    for (int ax = 0; ax < 3; ++ax) {
        const double reach = disc.radius * std::sqrt(std::max(0.0, 1.0 - n[ax] * n[ax])) + half * std::abs(n[ax]);
        lo[ax] = std::max(0, int(std::ceil(c[ax] - reach)) - 1);
        hi[ax] = std::min(size[ax] - 1, int(std::floor(c[ax] + reach)) + 1);
    }
    int p[3];
    for (p[e] = lo[e]; p[e] <= hi[e]; ++p[e])
        for (p[b] = lo[b]; p[b] <= hi[b]; ++p[b]) {
            const double rest = n[b] * (p[b] - c[b]) + n[e] * (p[e] - c[e]);
            // h = n_a (x_a − c_a) + rest lies in [−half, half] for x_a between these.
            double t0 = c[a] + (-half - rest) / n[a], t1 = c[a] + (half - rest) / n[a];
            if (t0 > t1) std::swap(t0, t1);
            const int from = std::max(lo[a], int(std::floor(t0)) - 1);
            const int to = std::min(hi[a], int(std::ceil(t1)) + 1);
            for (p[a] = from; p[a] <= to; ++p[a]) {
                const Vec3d rel{p[0] - c[0], p[1] - c[1], p[2] - c[2]};
                const double h = rel[0] * n[0] + rel[1] * n[1] + rel[2] * n[2];
                if (std::abs(h) > half) continue;
                const double inPlane2 = rel[0] * rel[0] + rel[1] * rel[1] + rel[2] * rel[2] - h * h;
                visit(p[0], p[1], p[2], h, inPlane2 <= r2);
            }
        }
}

}  // namespace cavesim

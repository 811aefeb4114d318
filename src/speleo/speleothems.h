/// @file speleothems.h
/// @brief Stalactites grown on a cave's ceiling in 3D by Short's law, stalagmites below their
/// drip points (Amorós-Tur & García-Fernández 2024, §3, read in 3D; Short et al. 2005).
///
/// The cave surface is held as a narrow-band signed-distance level set (`DecorationField`,
/// negative in the cave's air, positive in rock) on a grid much finer than the simulation's
/// (speleothems are centimetres, cave voxels about a metre). Each step:
///  1. **Where** (§3.1): level-set voxels within two voxels of the surface whose rock faces down
///     (the normal out of the rock has n_z < 0) and is convex (mean curvature of the rock surface
///     > `convexity`) are stalactite points; 26-connected groups of them are candidate
///     stalactites. A group grows when its lowest surface point (the tip) faces down (within 45°
///     of vertical) and its points reach at least `minSize` horizontally from the tip.
///  2. **Growth** (§3.2): every point of a stalactite moves into the cave along its normal at
///     Short's speed v = α·l_Q·(l_Q/(r·sin θ))^(1/3): r the horizontal distance of its surface
///     point from the vertical axis through the tip, θ the wall's angle to the horizontal
///     (sin θ = horizontal part of the unit normal), α scaled per drip site by
///     exp(dripVariability·g), g a smooth seeded noise of the tip's position in [-1, 1].
///     r·sin θ is floored at the tip radius ε (`tipRadius`, default two voxels).
///  3. **Tip** (§3.3): within ε of the axis the law is singular; the tip translates down at
///     Short's tip speed c = α·l_Q (the lengthening rate of his platonic stalactite), normal
///     speed c·cos θ, fixed rather than interpolated from its neighbours. The shape then tends to
///     the profile translating at c: r·sin θ·cos³θ = l_Q where r·sin θ ≥ ε, and walls at
///     cos θ = (l_Q/ε)^(1/3) between the tip and there (when ε ≤ l_Q: Short's platonic profile,
///     flat within 16/(3√3)·l_Q of the axis).
///  4. **Stalagmites**: below each tip the drip falls to the first rock straight down; upward
///     facing rock near that point rises at W·exp(-d²/(2R²)) (d the horizontal distance from
///     the drip axis, R `stalagmiteRadius`, W = stalagmiteRate × the tip speed of the stalactite
///     above: the drip feeds both), a Gaussian reading of the equilibrium-radius profile of
///     Kaufmann (2003).
///  5. The level set is advected by that normal speed: OpenVDB `LevelSetAdvection`'s update
///     (fifth-order upwind WENO, TVD Runge-Kutta 2, its CFL sub-steps) on the moving voxels only
///     (elsewhere the update is the identity), then the band is dilated, renormalised and
///     trimmed within 10 voxels of them; speeds are recomputed every step.
/// Stable step: the fastest point moves at most half a level-set voxel per speed update,
/// Δt = 0.5·h / v_max (capped by `timeStep` when it is set).
///
/// Space: world space, metres, z up. No OpenVDB type appears in this header.
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/progress.h"
#include "mesh/cave_mesh.h"
#include "sim/options.h"

namespace cavesim::speleo {

/// The cave surface being decorated: a narrow-band level set (OpenVDB inside the .cpp).
class DecorationField {
public:
    DecorationField();
    ~DecorationField();
    DecorationField(DecorationField&&) noexcept;
    DecorationField& operator=(DecorationField&&) noexcept;
    DecorationField(const DecorationField& other);  ///< deep copy

    double voxelSize() const;  ///< metres
    /// Signed distance to the surface at world point `p` (metres; < 0 in the cave's air),
    /// trilinear; far from the surface it is ± the band's half width.
    double distance(const Vec3d& p) const;
    /// Active voxels of the band.
    long activeVoxels() const;

    struct Impl;
    std::unique_ptr<Impl> impl;
};

/// A closed cave mesh (triangles wound outward, out of the cave) resampled to a level set of
/// voxel edge `voxelSize` metres.
/// @throw InternalError on an empty mesh or a non-positive voxel size
DecorationField fieldFromMesh(const mesh::TriangleMesh& caveMesh, double voxelSize);

/// A level set sampled from `caveDistance` (signed distance in metres, < 0 in air) on the box
/// [lo, hi] (metres) at voxel edge `voxelSize`: tests and small set-ups.
DecorationField fieldFromFunction(const Vec3d& lo, const Vec3d& hi, double voxelSize,
                                  const std::function<double(const Vec3d&)>& caveDistance);

/// Adds seeded relief of amplitude `amplitude` and feature size `scale` (metres) to the rock
/// facing down (weighted by the downward part of its normal), then rebuilds the distance field.
void addCeilingRoughness(DecorationField& field, double amplitude, double scale, std::uint64_t seed);

/// One speleothem found in a step.
struct Stalactite {
    Vec3d tip{0, 0, 0};         ///< lowest surface point, metres
    double length = 0;          ///< tip to the highest point of its convex patch, metres
    double grownLength = 0;     ///< original ceiling straight above the tip down to the tip, metres (measureGrowth)
    double radius = 0;          ///< largest horizontal distance of its patch from the axis, metres
    double tipSpeed = 0;        ///< downward speed of the tip, α·l_Q at its drip site, m/yr
    double dripFactor = 1;      ///< α multiplier of its drip site
    long points = 0;            ///< level-set voxels in its patch
    bool dripsOnFloor = false;  ///< a floor below its tip was found
    Vec3d dripPoint{0, 0, 0};   ///< where the drip lands, metres
};

/// The stalactites of `field` as step 1 finds them (largest first: by length, then position).
std::vector<Stalactite> findStalactites(const DecorationField& field, const SpeleothemOptions& options);

/// One growth step of `years` years at the speeds of the current surface (steps 1–5).
/// @return the stalactites that grew and the largest normal speed (m/yr)
struct StepResult {
    std::vector<Stalactite> stalactites;
    double maxSpeed = 0;  ///< m/yr
};
StepResult growStep(DecorationField& field, const SpeleothemOptions& options, double years);

/// The stable step of the current speeds: 0.5·h / v_max, years (infinity when nothing moves).
double stableStep(const DecorationField& field, const SpeleothemOptions& options);

/// Progress of `grow`: years done, the field, the stalactites of the last step.
using GrowthCallback = std::function<void(double years, const DecorationField&, const std::vector<Stalactite>&)>;

/// Summary of a whole growth.
struct GrowthResult {
    std::vector<Stalactite> stalactites;  ///< found on the final surface
    int steps = 0;
    double years = 0;
    double maxSpeed = 0;  ///< m/yr over the run
};

/// Grows `options.years` years in stable steps (or `options.timeStep`), calling `atFrame` at
/// year 0 and after the steps that cross each of `frameYears` (ascending).
/// @throw InputError-free: options are validated by the registry; InternalError on a bad field
/// `progress` ("speleothems", whole years grown, years asked) is called after every step and once
/// at the end: a safe point where it may throw `Cancelled`.
GrowthResult grow(DecorationField& field, const SpeleothemOptions& options, const std::vector<double>& frameYears = {},
                  const GrowthCallback& atFrame = {}, const ProgressFn& progress = {});

/// Sets `grownLength` of each stalactite: the vertical distance from its tip up to the surface of
/// `original` (the field before growth) on the same vertical, i.e. the length of grown material
/// below the original ceiling; 0 when the tip lies in original rock (nothing grew there). Then
/// orders them by it (longest first, then by the previous order).
void measureGrowth(const DecorationField& original, std::vector<Stalactite>& stalactites);

/// The surface as a closed triangle mesh (wound outward, out of the cave), optionally only the
/// part inside the box [lo, hi] (metres; the cut is closed by the box faces).
mesh::TriangleMesh meshField(const DecorationField& field);
mesh::TriangleMesh meshField(const DecorationField& field, const Vec3d& lo, const Vec3d& hi);

}  // namespace cavesim::speleo

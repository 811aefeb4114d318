#include "speleo/speleothems.h"

#include <openvdb/math/Operators.h>
#include <openvdb/math/Stencils.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Clip.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/LevelSetRebuild.h>
#include <openvdb/tools/LevelSetTracker.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/Morphology.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "core/check.h"
#include "mesh/level_set_mesh.h"
#include "sim/noise.h"

namespace cavesim::speleo {

struct DecorationField::Impl {
    openvdb::FloatGrid::Ptr grid;  // signed distance, metres, < 0 in the cave's air
};

namespace {

using openvdb::Coord;
using openvdb::FloatGrid;
using openvdb::Vec3d;

constexpr int kHalfWidth = 3;            // band half width, voxels
constexpr int kTrackReach = 10;          // the band is renormalised within this many voxels of a moving one
constexpr double kShell = 2.0;           // stalactite points lie within this many voxels of the surface
constexpr double kTipFacing = 0.7071;    // a tip faces down within 45° of vertical
constexpr double kDripNoiseScale = 1.0;  // metres, feature size of the drip variability
constexpr std::uint64_t kDripSalt = 0x9e3779b97f4a7c15ull;

void initVdb() {
    static const bool once = [] {
        openvdb::initialize();
        return true;
    }();
    (void)once;
}

FloatGrid::Ptr emptyGrid(double h, int halfWidth) {
    FloatGrid::Ptr g = FloatGrid::create(float(halfWidth * h));
    g->setTransform(openvdb::math::Transform::createLinearTransform(h));
    g->setGridClass(openvdb::GRID_LEVEL_SET);
    g->setName("decoration");
    return g;
}

/// One voxel near the surface with its geometry.
struct Sample {
    Coord c;
    float phi = 0;
    openvdb::Vec3f nAir{0, 0, 0};  // unit normal out of the rock, into the cave
    float kappa = 0;               // mean curvature of the rock surface (div nAir), 1/m
    openvdb::Vec3f cp{0, 0, 0};    // closest surface point, world
};

std::vector<Sample> surfaceSamples(const FloatGrid& grid, double shellVoxels, bool wantCurvature) {
    const double h = grid.voxelSize()[0];
    // The voxels within the shell, in the grid's own order (leaf by leaf), gathered per leaf in
    // parallel.
    std::vector<const FloatGrid::TreeType::LeafNodeType*> leaves;
    grid.tree().getNodes(leaves);
    std::vector<std::vector<Coord>> perLeaf(leaves.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 64), [&](const auto& range) {
        for (std::size_t l = range.begin(); l < range.end(); ++l)
            for (auto it = leaves[l]->cbeginValueOn(); it; ++it)
                if (std::abs(*it) < shellVoxels * h) perLeaf[l].push_back(it.getCoord());
    });
    std::vector<Coord> coords;
    for (const auto& c : perLeaf) coords.insert(coords.end(), c.begin(), c.end());
    std::vector<Sample> out(coords.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, coords.size(), 4096), [&](const auto& range) {
        auto acc = grid.getConstAccessor();
        for (std::size_t n = range.begin(); n < range.end(); ++n) {
            const Coord c = coords[n];
            auto v = [&](int dx, int dy, int dz) { return double(acc.getValue(c.offsetBy(dx, dy, dz))); };
            const double f = v(0, 0, 0);
            const double fx = (v(1, 0, 0) - v(-1, 0, 0)) / (2 * h), fy = (v(0, 1, 0) - v(0, -1, 0)) / (2 * h),
                         fz = (v(0, 0, 1) - v(0, 0, -1)) / (2 * h);
            const double g2 = fx * fx + fy * fy + fz * fz;
            Sample& s = out[n];
            s.c = c;
            s.phi = float(f);
            if (!(g2 > 1e-12)) continue;
            const double g = std::sqrt(g2);
            s.nAir = openvdb::Vec3f(float(-fx / g), float(-fy / g), float(-fz / g));
            const Vec3d x = grid.indexToWorld(c);
            // Closest point along the unit normal (|∇φ| drifts from 1 near sharp tips).
            s.cp = openvdb::Vec3f(float(x[0] - f * fx / g), float(x[1] - f * fy / g), float(x[2] - f * fz / g));
            if (!wantCurvature || s.nAir[2] >= 0.f) continue;
            const double h2 = h * h;
            const double fxx = (v(1, 0, 0) - 2 * f + v(-1, 0, 0)) / h2, fyy = (v(0, 1, 0) - 2 * f + v(0, -1, 0)) / h2,
                         fzz = (v(0, 0, 1) - 2 * f + v(0, 0, -1)) / h2;
            const double fxy = (v(1, 1, 0) - v(1, -1, 0) - v(-1, 1, 0) + v(-1, -1, 0)) / (4 * h2);
            const double fxz = (v(1, 0, 1) - v(1, 0, -1) - v(-1, 0, 1) + v(-1, 0, -1)) / (4 * h2);
            const double fyz = (v(0, 1, 1) - v(0, 1, -1) - v(0, -1, 1) + v(0, -1, -1)) / (4 * h2);
            const double divN = (fxx * (fy * fy + fz * fz) + fyy * (fx * fx + fz * fz) + fzz * (fx * fx + fy * fy) -
                                 2 * fx * fy * fxy - 2 * fx * fz * fxz - 2 * fy * fz * fyz) /
                                (g2 * g);
            s.kappa = float(-divN);  // the rock's normal is −∇φ/|∇φ|
        }
    });
    return out;
}

double tipRadiusOf(const SpeleothemOptions& o, double h) {
    return o.tipRadius > 0 ? o.tipRadius : 2.0 * h;
}

double shortSpeed(double alpha, double lQ, double rSinTheta) {
    return alpha * lQ * std::cbrt(lQ / std::max(rSinTheta, lQ));
}

struct Analysis {
    std::vector<Sample> samples;
    std::vector<double> speed;  // normal speed per sample, m/yr
    std::vector<Stalactite> stalactites;
};

Analysis analyse(const FloatGrid& grid, const SpeleothemOptions& o) {
    const double h = grid.voxelSize()[0];
    Analysis a;
    a.samples = surfaceSamples(grid, kShell, true);
    const std::vector<Sample>& s = a.samples;
    a.speed.assign(s.size(), 0.0);
    if (!o.drained) return a;

    // Step 1: stalactite points, 26-connected groups in a fixed order.
    openvdb::Int32Grid::Ptr label = openvdb::Int32Grid::create(-1);
    auto lab = label->getAccessor();
    for (std::size_t n = 0; n < s.size(); ++n)
        if (s[n].nAir[2] < 0.f && s[n].kappa > o.convexity) lab.setValue(s[n].c, int(n));
    std::vector<int> group(s.size(), -1);
    std::vector<std::vector<int>> groups;
    for (std::size_t n = 0; n < s.size(); ++n) {
        if (group[n] >= 0 || lab.getValue(s[n].c) < 0) continue;
        const int g = int(groups.size());
        groups.emplace_back();
        std::vector<int> stack{int(n)};
        group[n] = g;
        while (!stack.empty()) {
            const int m = stack.back();
            stack.pop_back();
            groups[g].push_back(m);
            for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int q = lab.getValue(s[m].c.offsetBy(dx, dy, dz));
                        if (q >= 0 && group[q] < 0) {
                            group[q] = g;
                            stack.push_back(q);
                        }
                    }
        }
        std::sort(groups[g].begin(), groups[g].end());
    }

    std::mt19937_64 rng(o.seed ^ kDripSalt);
    const GradientNoise dripNoise(rng);
    const double rTip = tipRadiusOf(o, h);
    // GridSampler keeps a reference to the accessor: it must outlive the sampler.
    const FloatGrid::ConstAccessor sampleAccessor = grid.getConstAccessor();
    openvdb::tools::GridSampler<FloatGrid::ConstAccessor, openvdb::tools::BoxSampler> sampler(sampleAccessor,
                                                                                              grid.transform());

    for (const std::vector<int>& members : groups) {
        // The tip: the lowest surface point among the points facing down (a needle's lowest
        // voxels may see its side).
        int tip = -1;
        for (int m : members)
            if (-s[m].nAir[2] >= kTipFacing && (tip < 0 || s[m].cp[2] < s[tip].cp[2])) tip = m;
        if (tip < 0) continue;
        const double tx = s[tip].cp[0], ty = s[tip].cp[1], tz = s[tip].cp[2];
        double radius = 0, top = tz;
        std::vector<double> r(members.size());
        for (std::size_t k = 0; k < members.size(); ++k) {
            const Sample& p = s[members[k]];
            r[k] = std::hypot(p.cp[0] - tx, p.cp[1] - ty);
            radius = std::max(radius, r[k]);
            top = std::max(top, double(p.cp[2]));
        }
        if (radius < o.minSize || top - tz < h) continue;
        Stalactite st;
        st.tip = {tx, ty, tz};
        st.length = top - tz;
        st.radius = radius;
        st.points = long(members.size());
        st.dripFactor = std::exp(o.dripVariability * dripNoise.sample(tx / kDripNoiseScale, ty / kDripNoiseScale,
                                                                      0.5 + tz / kDripNoiseScale));
        const double alpha = o.alpha * st.dripFactor;
        // Steps 2 and 3. Within the tip radius ε of the axis the tip translates down at Short's
        // tip speed c = α·l_Q (normal speed c·cos θ), fixed, never slaved to its neighbours (a tip
        // that follows its ring has no speed of its own and runs away). Outside, Short's law with
        // r·sin θ floored at ε, so no wall point is faster than the law's value at ε. The shape
        // tends to the profile translating at c: r·sin θ·cos³θ = l_Q where r·sin θ ≥ ε (Short's
        // platonic profile), cos θ = (l_Q/ε)^(1/3) below (docs/speleothems.md).
        for (std::size_t k = 0; k < members.size(); ++k) {
            const Sample& p = s[members[k]];
            const double sinT = std::hypot(double(p.nAir[0]), double(p.nAir[1]));
            a.speed[members[k]] = r[k] <= rTip ? alpha * o.lQ * std::max(0.0, double(-p.nAir[2]))
                                               : shortSpeed(alpha, o.lQ, std::max(r[k] * sinT, rTip));
        }
        st.tipSpeed = alpha * o.lQ;

        // Step 4: the drip falls to the first rock below the tip.
        for (double z = tz - h; z > tz - 1000.0; z -= 0.5 * h) {
            const double d = sampler.wsSample(Vec3d(tx, ty, z));
            if (d > 0) {
                st.dripsOnFloor = true;
                st.dripPoint = {tx, ty, z};
                break;
            }
            if (d <= -kHalfWidth * h * 0.999) {  // deep in the air: leap by the background distance
                z -= kHalfWidth * h - h;
            }
        }
        a.stalactites.push_back(st);
    }

    if (o.stalagmites && o.stalagmiteRate > 0) {
        // Upward-facing rock near each drip point rises at W·exp(−d²/(2R²)).
        std::vector<int> index;
        openvdb::Int32Grid::Ptr at = openvdb::Int32Grid::create(-1);
        auto acc = at->getAccessor();
        for (std::size_t n = 0; n < s.size(); ++n)
            if (s[n].nAir[2] > 0.3f) acc.setValue(s[n].c, int(n));
        const double R = o.stalagmiteRadius;
        for (const Stalactite& st : a.stalactites) {
            if (!st.dripsOnFloor) continue;
            const double W = o.stalagmiteRate * st.tipSpeed;
            const double zHi = st.dripPoint[2] + 0.5 * (st.tip[2] - st.dripPoint[2]);
            const Coord lo = Coord::round(
                grid.worldToIndex(Vec3d(st.dripPoint[0] - 3 * R, st.dripPoint[1] - 3 * R, st.dripPoint[2] - 3 * R)));
            const Coord hi =
                Coord::round(grid.worldToIndex(Vec3d(st.dripPoint[0] + 3 * R, st.dripPoint[1] + 3 * R, zHi)));
            for (int k = lo.z(); k <= hi.z(); ++k)
                for (int j = lo.y(); j <= hi.y(); ++j)
                    for (int i = lo.x(); i <= hi.x(); ++i) {
                        const int n = acc.getValue(Coord(i, j, k));
                        if (n < 0) continue;
                        const double d = std::hypot(s[n].cp[0] - st.dripPoint[0], s[n].cp[1] - st.dripPoint[1]);
                        if (d > 3 * R || s[n].cp[2] > zHi) continue;
                        a.speed[n] = std::max(a.speed[n], W * std::exp(-d * d / (2 * R * R)));
                    }
        }
    }
    // Merging: a still point squeezed between growing walls (growing neighbours on both sides
    // along an axis) moves with them, so a gap of a voxel or two between neighbours closes.
    {
        openvdb::FloatGrid::Ptr sp = openvdb::FloatGrid::create(0.f);
        auto acc = sp->getAccessor();
        for (std::size_t n = 0; n < s.size(); ++n)
            if (a.speed[n] > 0) acc.setValue(s[n].c, float(a.speed[n]));
        // Only a voxel within two voxels (along an axis) of a growing one can be squeezed.
        using MaskTree = FloatGrid::TreeType::ValueConverter<openvdb::ValueMask>::Type;
        MaskTree near(sp->tree(), false, openvdb::TopologyCopy());
        openvdb::tools::dilateActiveValues(near, 2, openvdb::tools::NN_FACE, openvdb::tools::IGNORE_TILES);
        std::vector<double> extra(s.size(), 0.0);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, s.size(), 4096), [&](const auto& range) {
            const auto speedAt = sp->getConstAccessor();
            const openvdb::tree::ValueAccessor<const MaskTree> nearAt(near);
            for (std::size_t n = range.begin(); n < range.end(); ++n) {
                if (a.speed[n] > 0 || !nearAt.isValueOn(s[n].c)) continue;
                for (int axis = 0; axis < 3; ++axis) {
                    for (int reach = 1; reach <= 2; ++reach) {
                        Coord d(0, 0, 0);
                        d[axis] = reach;
                        const float lo = speedAt.getValue(s[n].c - d), hi = speedAt.getValue(s[n].c + d);
                        if (lo > 0 && hi > 0) extra[n] = std::max(extra[n], double(std::min(lo, hi)));
                    }
                }
            }
        });
        for (std::size_t n = 0; n < s.size(); ++n) a.speed[n] = std::max(a.speed[n], extra[n]);
    }
    std::sort(a.stalactites.begin(), a.stalactites.end(), [](const Stalactite& x, const Stalactite& y) {
        if (x.length != y.length) return x.length > y.length;
        return x.tip < y.tip;
    });
    return a;
}

double maxSpeed(const Analysis& a) {
    double m = 0;
    for (double v : a.speed) m = std::max(m, v);
    return m;
}

/// Two RK2 stages of OpenVDB's `LevelSetAdvection` (fifth-order upwind WENO, TVD Runge-Kutta),
/// on the moving voxels only: the update φ − dt·V·∇φ is φ itself where V = 0, so the still
/// voxels need no work. The same arithmetic as OpenVDB's, voxel by voxel.
template <typename MapT>
void advectStages(FloatGrid& grid, const MapT& map, const std::vector<Coord>& at,
                  const std::vector<openvdb::Vec3f>& vel, float dt) {
    using Stencil = openvdb::math::BIAS_SCHEME<openvdb::math::HJWENO5_BIAS>::ISStencil<FloatGrid>::StencilType;
    using Grad = openvdb::math::GradientBiased<MapT, openvdb::math::HJWENO5_BIAS>;
    const std::size_t n = at.size();
    std::vector<float> phi0(n), next(n);
    const auto stage = [&](bool second) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const auto& range) {
            Stencil st(grid);
            for (std::size_t i = range.begin(); i < range.end(); ++i) {
                st.moveTo(at[i]);
                if (!second) phi0[i] = st.getValue();
                const float v = st.getValue() - dt * vel[i].dot(Grad::result(map, st, vel[i]));
                next[i] = second ? 0.5f * phi0[i] + 0.5f * v : v;
            }
        });
        auto acc = grid.getAccessor();
        for (std::size_t i = 0; i < n; ++i) acc.setValueOnly(at[i], next[i]);
    };
    stage(false);
    stage(true);
}

using MaskTree = FloatGrid::TreeType::ValueConverter<openvdb::ValueMask>::Type;

/// Motion of the level set not yet followed by a renormalisation, and the union of the tracking
/// regions it happened in (`grow` keeps it from one step to the next).
struct Unsettled {
    double voxels = 0;          ///< the fastest point's motion since, in voxels
    MaskTree reach, reachPlus;  ///< within kTrackReach − 1 voxels of what moved, and one voxel more
    bool any() const { return !reach.empty(); }
};

/// The band is renormalised once the fastest point has moved this many voxels since the last time.
/// A step of the stable size (half a voxel) or a CFL sub-step is renormalised at once, as always;
/// smaller steps (a `time_step` below the stable one) wait and add up. Renormalising after every
/// tiny step rounded the convex tips a little each time, more than they grew, and with
/// `time_step` = 10 (500 steps of 0.02 voxel) no stalactite was left of those the stable step grows.
constexpr double kSettleVoxels = 0.25;

/// Dilates the band by one voxel (faces) within the pending reach, renormalises it there (three
/// TVD-RK1 iterations, `LevelSetTracker`) and trims it; then nothing is pending.
void settle(FloatGrid::Ptr& grid, Unsettled& u) {
    if (!u.any()) return;
    MaskTree grow(u.reach), region(u.reachPlus);
    grow.topologyIntersection(grid->tree());
    openvdb::tools::dilateActiveValues(grow, 1, openvdb::tools::NN_FACE, openvdb::tools::IGNORE_TILES);
    grid->tree().topologyUnion(grow);
    region.topologyIntersection(grid->tree());
    openvdb::tools::LevelSetTracker<FloatGrid> tracker(*grid);
    tracker.setSpatialScheme(openvdb::math::HJWENO5_BIAS);
    tracker.setTemporalScheme(openvdb::math::TVD_RK1);
    tracker.normalize(&region);
    tracker.prune();
    u.voxels = 0;
    u.reach.clear();
    u.reachPlus.clear();
}

/// Advects the level set by the analysis' normal speeds (the largest `vmax`, `maxSpeed`) for
/// `years` years. The moving voxels
/// take OpenVDB's `LevelSetAdvection` step (HJWENO5, TVD-RK2, CFL sub-steps); the band is then
/// dilated, renormalised and trimmed (`settle`) only within `kTrackReach` voxels of a moving voxel,
/// once the motion since the last time reaches `kSettleVoxels`: the still surface far from any
/// growth keeps its distances as they are (a whole-band renormalisation would cost a pass over
/// every voxel each step and slowly round the still relief).
void advect(FloatGrid::Ptr& grid, const Analysis& a, double vmax, double years, Unsettled& pending) {
    if (!(vmax > 0) || !(years > 0)) return;
    std::vector<Coord> at;
    std::vector<openvdb::Vec3f> vel;
    for (std::size_t n = 0; n < a.samples.size(); ++n)
        if (a.speed[n] > 0) {
            // Speeds are scaled by the largest, and time by it in turn (as OpenVDB's advection
            // wants: it treats speeds below ~3e-3 per unit time as zero; ours are ~1e-4 m/yr).
            const openvdb::Vec3f v = a.samples[n].nAir * float(a.speed[n] / vmax);
            if (v != openvdb::Vec3f(0.f)) {
                at.push_back(a.samples[n].c);
                vel.push_back(v);
            }
        }
    if (at.empty()) return;
    // The tracking region, from where the voxels move at first (fixed for the sub-steps): within
    // kTrackReach − 1 voxels of them, and one voxel more.
    MaskTree reach;
    for (const Coord& c : at) reach.setValueOn(c);
    openvdb::tools::dilateActiveValues(reach, kTrackReach - 1, openvdb::tools::NN_FACE_EDGE_VERTEX,
                                       openvdb::tools::IGNORE_TILES);
    MaskTree reachPlus(reach);
    openvdb::tools::dilateActiveValues(reachPlus, 1, openvdb::tools::NN_FACE_EDGE_VERTEX, openvdb::tools::IGNORE_TILES);
    pending.reach.topologyUnion(reach);
    pending.reachPlus.topologyUnion(reachPlus);
    const auto* map = grid->transform().constMap<openvdb::math::UniformScaleMap>().get();
    CAVESIM_CHECK(map != nullptr, "the decoration level set needs a uniform scale transform");
    const float h = float(grid->voxelSize()[0]);
    // OpenVDB's CFL number for TVD-RK2 and its sub-steps, in its float arithmetic.
    const float cfl = 0.9f / std::sqrt(3.0f);
    float time0 = 0.f;
    const float time1 = float(years * vmax);
    while (time0 < time1 && !at.empty()) {
        float maxAbsV = 0;
        for (const openvdb::Vec3f& v : vel) maxAbsV = std::max(maxAbsV, v.lengthSqr());
        if (openvdb::math::isApproxZero(maxAbsV, openvdb::math::Delta<float>::value())) break;
        const float dt = std::min(std::abs(time1 - time0), cfl * h / std::sqrt(maxAbsV));
        if (openvdb::math::isZero(dt)) break;
        advectStages(*grid, *map, at, vel, dt);
        time0 += dt;
        pending.voxels += double(dt) * std::sqrt(double(maxAbsV)) / double(h);
        if (pending.voxels < kSettleVoxels) continue;
        settle(grid, pending);
        // Voxels trimmed out of the band take no further sub-step; the next sub-step tracks
        // the same region.
        std::size_t k = 0;
        const auto acc = grid->getConstAccessor();
        for (std::size_t i = 0; i < at.size(); ++i)
            if (acc.isValueOn(at[i])) {
                at[k] = at[i];
                vel[k++] = vel[i];
            }
        at.resize(k);
        vel.resize(k);
        if (time0 < time1) {
            pending.reach.topologyUnion(reach);
            pending.reachPlus.topologyUnion(reachPlus);
        }
    }
}

}  // namespace

DecorationField::DecorationField() : impl(std::make_unique<Impl>()) {}
DecorationField::~DecorationField() = default;
DecorationField::DecorationField(DecorationField&&) noexcept = default;
DecorationField& DecorationField::operator=(DecorationField&&) noexcept = default;
DecorationField::DecorationField(const DecorationField& other) : impl(std::make_unique<Impl>()) {
    if (other.impl && other.impl->grid) impl->grid = other.impl->grid->deepCopy();
}

double DecorationField::voxelSize() const {
    CAVESIM_CHECK(impl && impl->grid, "an empty decoration field");
    return impl->grid->voxelSize()[0];
}

double DecorationField::distance(const cavesim::Vec3d& p) const {
    CAVESIM_CHECK(impl && impl->grid, "an empty decoration field");
    openvdb::tools::GridSampler<FloatGrid, openvdb::tools::BoxSampler> sampler(*impl->grid);
    return sampler.wsSample(Vec3d(p[0], p[1], p[2]));
}

long DecorationField::activeVoxels() const {
    return impl && impl->grid ? long(impl->grid->activeVoxelCount()) : 0;
}

DecorationField fieldFromMesh(const mesh::TriangleMesh& caveMesh, double voxelSize) {
    initVdb();
    CAVESIM_CHECK(voxelSize > 0, "voxel size must be positive");
    CAVESIM_CHECK(!caveMesh.triangles.empty(), "an empty cave mesh");
    std::vector<openvdb::Vec3s> points;
    points.reserve(caveMesh.vertices.size());
    for (const auto& v : caveMesh.vertices) points.emplace_back(float(v[0]), float(v[1]), float(v[2]));
    std::vector<openvdb::Vec3I> tris;
    tris.reserve(caveMesh.triangles.size());
    for (const auto& t : caveMesh.triangles) tris.emplace_back(t[0], t[1], t[2]);
    const auto xform = openvdb::math::Transform::createLinearTransform(voxelSize);
    DecorationField f;
    f.impl->grid = openvdb::tools::meshToLevelSet<FloatGrid>(*xform, points, tris, float(kHalfWidth));
    f.impl->grid->setName("decoration");
    return f;
}

DecorationField fieldFromFunction(const cavesim::Vec3d& lo, const cavesim::Vec3d& hi, double voxelSize,
                                  const std::function<double(const cavesim::Vec3d&)>& caveDistance) {
    initVdb();
    CAVESIM_CHECK(voxelSize > 0, "voxel size must be positive");
    FloatGrid::Ptr g = emptyGrid(voxelSize, kHalfWidth);
    const float band = float(kHalfWidth * voxelSize);
    const Coord a = Coord::round(g->worldToIndex(Vec3d(lo[0], lo[1], lo[2])));
    const Coord b = Coord::round(g->worldToIndex(Vec3d(hi[0], hi[1], hi[2])));
    auto acc = g->getAccessor();
    for (int k = a.z(); k <= b.z(); ++k)
        for (int j = a.y(); j <= b.y(); ++j)
            for (int i = a.x(); i <= b.x(); ++i) {
                const Vec3d x = g->indexToWorld(Coord(i, j, k));
                const double d = caveDistance({x[0], x[1], x[2]});
                if (std::abs(d) < band)
                    acc.setValue(Coord(i, j, k), float(d));
                else if (d < 0)
                    acc.setValueOff(Coord(i, j, k), -band);
            }
    openvdb::tools::signedFloodFill(g->tree());
    DecorationField f;
    f.impl->grid = g;
    return f;
}

void addCeilingRoughness(DecorationField& field, double amplitude, double scale, std::uint64_t seed) {
    CAVESIM_CHECK(field.impl && field.impl->grid, "an empty decoration field");
    if (!(amplitude > 0)) return;
    FloatGrid::Ptr& g = field.impl->grid;
    const double h = g->voxelSize()[0];
    // Widen the band so the displaced surface stays inside it, then displace and rebuild.
    const int extra = int(std::ceil(amplitude / h)) + 1;
    FloatGrid::Ptr wide =
        openvdb::tools::levelSetRebuild(*g, 0.f, float(kHalfWidth + extra), float(kHalfWidth + extra));
    const std::vector<Sample> s = surfaceSamples(*wide, kHalfWidth + extra, false);
    std::mt19937_64 rng(seed);
    const GradientNoise noise(rng);
    auto acc = wide->getAccessor();
    for (const Sample& p : s) {
        const double wgt = std::max(0.0, double(-p.nAir[2]));
        if (wgt <= 0) continue;
        const Vec3d x = wide->indexToWorld(p.c);
        const double n = noise.fractal(x[0] / scale, x[1] / scale, x[2] / scale, 2);
        acc.setValue(p.c, float(p.phi + amplitude * wgt * n));
    }
    g = openvdb::tools::levelSetRebuild(*wide, 0.f, float(kHalfWidth), float(kHalfWidth));
    g->setName("decoration");
}

std::vector<Stalactite> findStalactites(const DecorationField& field, const SpeleothemOptions& options) {
    CAVESIM_CHECK(field.impl && field.impl->grid, "an empty decoration field");
    return analyse(*field.impl->grid, options).stalactites;
}

double stableStep(const DecorationField& field, const SpeleothemOptions& options) {
    CAVESIM_CHECK(field.impl && field.impl->grid, "an empty decoration field");
    const double v = maxSpeed(analyse(*field.impl->grid, options));
    return v > 0 ? 0.5 * field.voxelSize() / v : std::numeric_limits<double>::infinity();
}

StepResult growStep(DecorationField& field, const SpeleothemOptions& options, double years) {
    CAVESIM_CHECK(field.impl && field.impl->grid, "an empty decoration field");
    initVdb();
    Analysis a = analyse(*field.impl->grid, options);
    const double vmax = maxSpeed(a);
    Unsettled pending;
    advect(field.impl->grid, a, vmax, years, pending);
    settle(field.impl->grid, pending);
    return StepResult{std::move(a.stalactites), vmax};
}

GrowthResult grow(DecorationField& field, const SpeleothemOptions& o, const std::vector<double>& frameYears,
                  const GrowthCallback& atFrame, const ProgressFn& progress) {
    CAVESIM_CHECK(field.impl && field.impl->grid, "an empty decoration field");
    initVdb();
    GrowthResult res;
    const double h = field.voxelSize();
    std::size_t nextFrame = 0, crossed = 0;  // frames shown; frames the steps so far have reached
    double t = 0;
    bool first = true;
    Unsettled pending;
    while (true) {
        // A surface that is shown (a frame) or ends the growth is renormalised first.
        if (t >= o.years - 1e-9 || nextFrame < crossed) settle(field.impl->grid, pending);
        Analysis a = analyse(*field.impl->grid, o);
        const double vmax = maxSpeed(a);
        if (!(vmax > 0) && pending.any()) {  // nothing moves: settle, and look again at the settled surface
            settle(field.impl->grid, pending);
            continue;
        }
        res.maxSpeed = std::max(res.maxSpeed, vmax);
        if (first && atFrame) atFrame(0.0, field, a.stalactites);
        first = false;
        // The frames the last step crossed show the surface it left, analysed just now.
        for (; nextFrame < crossed; ++nextFrame)
            if (atFrame && frameYears[nextFrame] > 0) atFrame(t, field, a.stalactites);
        if (t >= o.years - 1e-9 || vmax <= 0) {
            res.stalactites = std::move(a.stalactites);
            // Frames not reached because nothing moves show the final state.
            while (atFrame && nextFrame < frameYears.size()) {
                if (frameYears[nextFrame] > 0) atFrame(frameYears[nextFrame], field, res.stalactites);
                ++nextFrame;
            }
            break;
        }
        const double dt = std::min(speleothemStep(o, h, vmax), o.years - t);
        advect(field.impl->grid, a, vmax, dt, pending);
        t += dt;
        ++res.steps;
        while (crossed < frameYears.size() && frameYears[crossed] <= t + 1e-9) ++crossed;
        reportProgress(progress, "speleothems", long(std::floor(t)), long(std::ceil(o.years)));
    }
    reportProgress(progress, "speleothems", long(std::ceil(o.years)), long(std::ceil(o.years)));
    res.years = t;
    return res;
}

void measureGrowth(const DecorationField& original, std::vector<Stalactite>& stalactites) {
    CAVESIM_CHECK(original.impl && original.impl->grid, "an empty decoration field");
    const FloatGrid& g = *original.impl->grid;
    const double h = g.voxelSize()[0];
    const double band = kHalfWidth * h;
    openvdb::tools::GridSampler<FloatGrid, openvdb::tools::BoxSampler> sampler(g);
    const auto d = [&](const Stalactite& st, double z) { return sampler.wsSample(Vec3d(st.tip[0], st.tip[1], z)); };
    for (Stalactite& st : stalactites) {
        st.grownLength = 0;
        double lo = st.tip[2];
        if (d(st, lo) >= 0) continue;  // the tip is original rock
        // Up to the first original rock, leaping through deep air by the band's width.
        double hi = lo;
        bool found = false;
        for (int k = 0; k < 1000000 && !found; ++k) {
            const double v = d(st, hi);
            if (v >= 0) {
                found = true;
                break;
            }
            lo = hi;
            hi += v <= -0.999 * band ? band - h : 0.5 * h;
        }
        if (!found) continue;
        for (int i = 0; i < 40; ++i) {
            const double m = 0.5 * (lo + hi);
            (d(st, m) >= 0 ? hi : lo) = m;
        }
        st.grownLength = 0.5 * (lo + hi) - st.tip[2];
    }
    std::stable_sort(stalactites.begin(), stalactites.end(),
                     [](const Stalactite& x, const Stalactite& y) { return x.grownLength > y.grownLength; });
}

mesh::TriangleMesh meshField(const DecorationField& field) {
    CAVESIM_CHECK(field.impl && field.impl->grid, "an empty decoration field");
    return mesh::detail::meshLevelSet(*field.impl->grid, 0.0, 0.0);
}

mesh::TriangleMesh meshField(const DecorationField& field, const cavesim::Vec3d& lo, const cavesim::Vec3d& hi) {
    CAVESIM_CHECK(field.impl && field.impl->grid, "an empty decoration field");
    const openvdb::BBoxd box(Vec3d(lo[0], lo[1], lo[2]), Vec3d(hi[0], hi[1], hi[2]));
    FloatGrid::Ptr clipped = openvdb::tools::clip(*field.impl->grid, box);
    return mesh::detail::meshLevelSet(*clipped, 0.0, 0.0);
}

}  // namespace cavesim::speleo

// The cave's level set: cubes ∪ link capsules, constrained mean-curvature flow, volume offset.
#include "mesh/cave_level_set.h"

#include <openvdb/tools/Composite.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/LevelSetFilter.h>
#include <openvdb/tools/LevelSetMeasure.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <openvdb/tools/TopologyToLevelSet.h>
#include <openvdb/tree/LeafManager.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include "core/check.h"
#include "core/timer.h"

namespace cavesim::mesh::detail {
namespace {

using openvdb::Coord;
using openvdb::FloatGrid;

openvdb::math::Transform::Ptr fineTransform(double fineVoxel) {
    auto xf = openvdb::math::Transform::createLinearTransform(fineVoxel);
    xf->postTranslate(openvdb::Vec3d(0.5 * fineVoxel));  // index m is centred at (m + 0.5)·s
    return xf;
}

struct Segment {
    openvdb::Vec3d p, q;  // fine index space
};

// Squared Euclidean distance (voxel units²) from each voxel centre to the nearest rock voxel
// centre, the outside of the block counting as rock; 0 on rock. Separable exact transform
// (Felzenszwalb & Huttenlocher 2012), one axis after the other.
std::vector<float> squaredDepth(const Grid3<std::uint8_t>& mask) {
    const Dims& d = mask.dims;
    // Padded by one rock layer on every side.
    const int px = d.nx + 2, py = d.ny + 2, pz = d.nz + 2;
    const float inf = 1e20f;
    std::vector<float> f(std::size_t(px) * py * pz, 0.f);
    auto at = [&](int i, int j, int k) -> float& {
        return f[std::size_t(i) + std::size_t(px) * (std::size_t(j) + std::size_t(py) * k)];
    };
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i)
                if (mask.at(i, j, k)) at(i + 1, j + 1, k + 1) = inf;
    // One 1D pass: the lower envelope of the parabolas (q − r)² + g(r) over the finite samples.
    auto pass = [inf](float* base, int n, std::size_t stride, std::vector<double>& g, std::vector<int>& v,
                      std::vector<double>& z) {
        for (int q = 0; q < n; ++q) g[q] = base[q * stride];
        int kk = -1;
        for (int q = 0; q < n; ++q) {
            if (g[q] >= inf) continue;
            if (kk < 0) {
                kk = 0;
                v[0] = q;
                z[0] = -1e300;
                z[1] = 1e300;
                continue;
            }
            double sPos = 0.0;
            while (true) {
                const int r = v[kk];
                sPos = ((g[q] + double(q) * q) - (g[r] + double(r) * r)) / (2.0 * (q - r));
                if (kk > 0 && sPos <= z[kk])
                    --kk;
                else
                    break;
            }
            ++kk;
            v[kk] = q;
            z[kk] = sPos;
            z[kk + 1] = 1e300;
        }
        if (kk < 0) return;  // no rock on this line (cannot happen: the padding is rock)
        kk = 0;
        for (int q = 0; q < n; ++q) {
            while (z[kk + 1] < double(q)) ++kk;
            const double dq = double(q - v[kk]);
            base[q * stride] = float(dq * dq + g[v[kk]]);
        }
    };
    const int longest = std::max({px, py, pz});
    auto lines = [&](int axis) {
        const int n = axis == 0 ? px : (axis == 1 ? py : pz);
        const std::size_t stride = axis == 0 ? 1 : (axis == 1 ? std::size_t(px) : std::size_t(px) * py);
        const int na = axis == 0 ? py : px, nb = axis == 2 ? py : pz;
        tbb::parallel_for(tbb::blocked_range<int>(0, nb), [&](const tbb::blocked_range<int>& r) {
            std::vector<double> g(static_cast<std::size_t>(longest)), z(static_cast<std::size_t>(longest) + 1);
            std::vector<int> v(static_cast<std::size_t>(longest));
            for (int b = r.begin(); b < r.end(); ++b)
                for (int a = 0; a < na; ++a) {
                    float* base = axis == 0 ? &at(0, a, b) : (axis == 1 ? &at(a, 0, b) : &at(a, b, 0));
                    pass(base, n, stride, g, v, z);
                }
        });
    };
    lines(0);
    lines(1);
    lines(2);
    std::vector<float> out(mask.size(), 0.f);
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) out[d.index(i, j, k)] = at(i + 1, j + 1, k + 1);
    return out;
}

// The net: capsules that keep every channel a tube and every 26-connected piece of the cave one
// piece, whatever the smoothing does. It is the maximum spanning forest of the 26-neighbour
// graph of cave voxels weighted by depth (the bottleneck-widest paths: through the middle of
// wide passages, along thin ones), with shallow leaves pruned away (a leaf shallower than its
// neighbour is surface, not passage) so the net lies deep inside wide passages. Each remaining
// link is a segment; a piece pruned to a single voxel (or a lone voxel) is a ball.
std::vector<Segment> netSegments(const Grid3<std::uint8_t>& mask, int subdivision) {
    const Dims& d = mask.dims;
    const std::vector<float> depth2 = squaredDepth(mask);
    std::vector<std::size_t> voxels;
    std::vector<int> id(mask.size(), -1);
    for (std::size_t n = 0; n < mask.size(); ++n)
        if (mask[n]) {
            id[n] = int(voxels.size());
            voxels.push_back(n);
        }
    struct Link {
        float shallow, deep;  // squared depth of the shallower and the deeper end
        int length2, a, b;
    };
    std::vector<Link> links;
    for (std::size_t v = 0; v < voxels.size(); ++v) {
        const Index3 p = d.coord(voxels[v]);
        for (const NeighbourOffset& o : allNeighbours()) {
            const Index3 q{p.i + o.di, p.j + o.dj, p.k + o.dk};
            if (!d.contains(q) || !mask.at(q)) continue;
            const int w = id[d.index(q)];
            if (w < int(v)) continue;  // each link once
            const float da = depth2[voxels[v]], db = depth2[voxels[std::size_t(w)]];
            links.push_back({std::min(da, db), std::max(da, db), o.di * o.di + o.dj * o.dj + o.dk * o.dk, int(v), w});
        }
    }
    // Deepest first (by the shallower end, then the deeper: a voxel joins the tree through its
    // deepest neighbour, so only ridges of the depth keep shallow-to-deep branches that the
    // pruning below removes); among equals the shorter link, then by voxel order.
    std::sort(links.begin(), links.end(), [](const Link& x, const Link& y) {
        if (x.shallow != y.shallow) return x.shallow > y.shallow;
        if (x.deep != y.deep) return x.deep > y.deep;
        if (x.length2 != y.length2) return x.length2 < y.length2;
        return x.a != y.a ? x.a < y.a : x.b < y.b;
    });
    std::vector<int> parent(voxels.size());
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&parent](int x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    std::vector<std::vector<int>> adjacency(voxels.size());
    for (const Link& l : links) {
        const int ra = find(l.a), rb = find(l.b);
        if (ra == rb) continue;
        parent[std::max(ra, rb)] = std::min(ra, rb);
        adjacency[l.a].push_back(l.b);
        adjacency[l.b].push_back(l.a);
    }
    // Prune shallow leaves.
    std::vector<int> degree(voxels.size());
    std::vector<char> removed(voxels.size(), 0);
    for (std::size_t v = 0; v < voxels.size(); ++v) degree[v] = int(adjacency[v].size());
    auto liveNeighbour = [&](int v) {
        for (int w : adjacency[v])
            if (!removed[w]) return w;
        return -1;
    };
    std::vector<int> queue;
    auto consider = [&](int v) {
        if (removed[v] || degree[v] != 1) return;
        const int w = liveNeighbour(v);
        if (depth2[voxels[v]] < depth2[voxels[w]]) queue.push_back(v);
    };
    for (std::size_t v = 0; v < voxels.size(); ++v) consider(int(v));
    for (std::size_t head = 0; head < queue.size(); ++head) {
        const int v = queue[head];
        if (removed[v] || degree[v] != 1) continue;
        const int w = liveNeighbour(v);
        removed[v] = 1;
        degree[v] = 0;
        --degree[w];
        consider(w);
    }
    auto centre = [subdivision, &d, &voxels](int v) {
        const Index3 p = d.coord(voxels[std::size_t(v)]);
        const double s = double(subdivision);
        return openvdb::Vec3d((p.i + 0.5) * s - 0.5, (p.j + 0.5) * s - 0.5, (p.k + 0.5) * s - 0.5);
    };
    std::vector<Segment> segments;
    for (std::size_t v = 0; v < voxels.size(); ++v) {
        if (removed[v]) continue;
        if (degree[v] == 0) segments.push_back({centre(int(v)), centre(int(v))});
        for (int w : adjacency[v])
            if (w > int(v) && !removed[w]) segments.push_back({centre(int(v)), centre(w)});
    }
    return segments;
}

double distanceToSegment(const openvdb::Vec3d& x, const Segment& s) {
    const openvdb::Vec3d ab = s.q - s.p;
    const double len2 = ab.lengthSqr();
    double t = len2 > 0.0 ? (x - s.p).dot(ab) / len2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    return (x - (s.p + t * ab)).length();
}

// Signed distance (metres) to the union of capsules of radius `radius` (fine voxels) around the
// segments, stored within `reach` fine voxels of their surface (enough for the union and the
// blending steps); elsewhere the background +halfWidth (outside).
FloatGrid::Ptr capsuleLevelSet(const std::vector<Segment>& segments, double radius, int halfWidth, double fineVoxel) {
    constexpr double reach = 3.0;
    const float background = float(halfWidth * fineVoxel);
    FloatGrid::Ptr grid = FloatGrid::create(background);
    grid->setTransform(fineTransform(fineVoxel));
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    auto acc = grid->getAccessor();
    const double extent = radius + reach;
    for (const Segment& s : segments) {
        const openvdb::Vec3d lo = openvdb::math::minComponent(s.p, s.q) - openvdb::Vec3d(extent);
        const openvdb::Vec3d hi = openvdb::math::maxComponent(s.p, s.q) + openvdb::Vec3d(extent);
        const Coord a(int(std::ceil(lo[0])), int(std::ceil(lo[1])), int(std::ceil(lo[2])));
        const Coord b(int(std::floor(hi[0])), int(std::floor(hi[1])), int(std::floor(hi[2])));
        for (int z = a.z(); z <= b.z(); ++z)
            for (int y = a.y(); y <= b.y(); ++y)
                for (int x = a.x(); x <= b.x(); ++x) {
                    const double dist = distanceToSegment(openvdb::Vec3d(x, y, z), s) - radius;
                    if (dist >= reach) continue;
                    const float v = float(dist * fineVoxel);
                    const Coord c(x, y, z);
                    float cur;
                    if (!acc.probeValue(c, cur) || v < cur) acc.setValue(c, v);
                }
    }
    return grid;
}

// phi = min(phi, capsules) on phi's active voxels: the flow may not enter the capsules.
void unionInPlace(FloatGrid& phi, const FloatGrid& capsules) {
    openvdb::tree::LeafManager<openvdb::FloatTree> leaves(phi.tree());
    leaves.foreach ([&capsules](openvdb::FloatTree::LeafNodeType& leaf, std::size_t) {
        auto acc = capsules.getConstAccessor();
        const auto* other = acc.probeConstLeaf(leaf.origin());
        if (!other) return;
        for (auto it = leaf.beginValueOn(); it; ++it) {
            const float c = other->getValue(it.pos());
            if (c < *it) it.setValue(c);
        }
    });
}

// Samples `coarse` trilinearly at the centres of a grid `sub` times finer, over the children of
// its active voxels; the background (and so the band's half width in metres) is kept.
FloatGrid::Ptr refine(const FloatGrid& coarse, int sub, double fineVoxel, float background) {
    FloatGrid::Ptr fine = FloatGrid::create(background);
    fine->setTransform(fineTransform(fineVoxel));
    fine->setGridClass(openvdb::GRID_LEVEL_SET);
    using LeafT = openvdb::FloatTree::LeafNodeType;
    std::vector<const LeafT*> leaves;
    coarse.tree().getNodes(leaves);
    // Each coarse leaf (8³) maps onto sub³ whole fine leaves: build them in parallel, add serially.
    std::vector<std::vector<std::unique_ptr<LeafT>>> built(leaves.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size()), [&](const tbb::blocked_range<std::size_t>& r) {
        auto acc = coarse.getConstAccessor();
        for (std::size_t n = r.begin(); n < r.end(); ++n) {
            const LeafT& leaf = *leaves[n];
            const Coord origin = leaf.origin();
            for (int b = 0; b < sub * sub * sub; ++b) {
                const Coord fo(origin.x() * sub + 8 * (b % sub), origin.y() * sub + 8 * ((b / sub) % sub),
                               origin.z() * sub + 8 * (b / (sub * sub)));
                auto out = std::make_unique<LeafT>(fo, background, false);
                bool any = false;
                for (auto it = out->beginValueAll(); it; ++it) {
                    const Coord m = it.getCoord();
                    const Coord parent(openvdb::math::Floor(double(m.x()) / sub),
                                       openvdb::math::Floor(double(m.y()) / sub),
                                       openvdb::math::Floor(double(m.z()) / sub));
                    if (!leaf.isValueOn(parent)) continue;
                    const openvdb::Vec3d q((m.x() + 0.5) / sub - 0.5, (m.y() + 0.5) / sub - 0.5,
                                           (m.z() + 0.5) / sub - 0.5);
                    const float v = openvdb::tools::BoxSampler::sample(acc, q);
                    if (std::abs(v) >= background) continue;
                    it.setValue(v);
                    it.setValueOn();
                    any = true;
                }
                if (any) built[n].push_back(std::move(out));
            }
        }
    });
    for (auto& list : built)
        for (auto& leaf : list) fine->tree().addLeaf(leaf.release());
    // Interior tiles and voxels of the coarse grid far inside the cave stay inside.
    openvdb::tools::signedFloodFill(fine->tree());
    return fine;
}

// The outward offset (metres, in [0, maxOffset]) that brings the level set's volume to `target`:
// (target − volume) / area, to first order.
double volumeOffset(const FloatGrid& phi, double target, double maxOffset) {
    const double volume = openvdb::tools::levelSetVolume(phi);
    const double area = openvdb::tools::levelSetArea(phi);
    if (!(area > 0.0) || !std::isfinite(volume)) return 0.0;
    return std::clamp((target - volume) / area, 0.0, maxOffset);
}

}  // namespace

void validateMeshOptions(const MeshOptions& o, double voxelSize) {
    CAVESIM_CHECK(voxelSize > 0.0 && std::isfinite(voxelSize),
                  "mesh option voxel size must be a positive number of metres, got " + std::to_string(voxelSize));
    CAVESIM_CHECK(o.subdivision >= 1 && o.subdivision <= 4,
                  "mesh option subdivision must be in [1, 4], got " + std::to_string(o.subdivision));
    CAVESIM_CHECK(o.halfWidth >= 3 && o.halfWidth <= 8,
                  "mesh option half width must be in [3, 8], got " + std::to_string(o.halfWidth));
    CAVESIM_CHECK(o.tubeRadius >= 0.25 && o.tubeRadius <= 0.85,
                  "mesh option tube radius must be in [0.25, 0.85] voxels, got " + std::to_string(o.tubeRadius));
    CAVESIM_CHECK(o.smoothingIterations >= 0 && o.smoothingIterations <= 100,
                  "mesh option smoothing iterations must be in [0, 100], got " + std::to_string(o.smoothingIterations));
    CAVESIM_CHECK(o.maxVolumeOffset >= 0.0 && o.maxVolumeOffset <= 1.0,
                  "mesh option max volume offset must be in [0, 1] voxels, got " + std::to_string(o.maxVolumeOffset));
    CAVESIM_CHECK(o.adaptivity >= 0.0 && o.adaptivity <= 1.0,
                  "mesh option adaptivity must be in [0, 1], got " + std::to_string(o.adaptivity));
}

CaveLevelSet buildCaveLevelSet(const Grid3<std::uint8_t>& mask, double voxelSize, const MeshOptions& options) {
    validateMeshOptions(options, voxelSize);
    CaveLevelSet out;
    const Dims& d = mask.dims;
    long caveVoxels = 0;
    for (std::uint8_t v : mask.data) caveVoxels += v ? 1 : 0;
    if (caveVoxels == 0) return out;
    openvdb::initialize();

    const int sub = options.subdivision;
    const double fine = voxelSize / sub;
    const int fineHalfWidth = options.halfWidth;
    out.voxelVolume = double(caveVoxels) * voxelSize * voxelSize * voxelSize;
    Stopwatch watch;

    // 1. The cubes: the signed distance to the cave voxels' faces at the simulation resolution,
    //    refined `sub` times by trilinear interpolation.
    openvdb::MaskGrid maskGrid(false);
    maskGrid.setTransform(fineTransform(voxelSize));
    {
        auto acc = maskGrid.getAccessor();
        for (int k = 0; k < d.nz; ++k)
            for (int j = 0; j < d.ny; ++j)
                for (int i = 0; i < d.nx; ++i)
                    if (mask.at(i, j, k)) acc.setValueOn(Coord(i, j, k));
    }
    FloatGrid::Ptr coarse = openvdb::tools::topologyToLevelSet(maskGrid, (fineHalfWidth + sub - 1) / sub + 1, 0, 0, 0);
    coarse->setTransform(fineTransform(voxelSize));
    FloatGrid::Ptr phi = refine(*coarse, sub, fine, float(fineHalfWidth * fine));
    coarse.reset();
    out.secondsCubes = watch.lap();

    // 2. United with the net (capsules of radius tubeRadius, at least 0.9 level-set voxels so
    //    that the level-set samples inside a capsule are always face-connected).
    const std::vector<Segment> segments = netSegments(mask, sub);
    FloatGrid::Ptr capsules = capsuleLevelSet(segments, std::max(options.tubeRadius * sub, 0.9), fineHalfWidth, fine);
    {
        FloatGrid::Ptr copy = capsules->deepCopy();
        openvdb::tools::csgUnion(*phi, *copy);
    }
    out.secondsCapsules = watch.lap();

    // 3. Mean-curvature flow rounds the voxel staircase; the net is unioned back after every
    //    step, so the flow cannot thin a channel below the net or pinch the cave apart.
    if (options.smoothingIterations > 0) {
        openvdb::tools::LevelSetFilter<FloatGrid> filter(*phi);
        filter.setSpatialScheme(openvdb::math::FIRST_BIAS);
        filter.setTemporalScheme(openvdb::math::TVD_RK1);
        filter.setNormCount(1);
        for (int n = 0; n < options.smoothingIterations; ++n) {
            filter.meanCurvature();
            unionInPlace(*phi, *capsules);
        }
    }
    out.secondsSmoothing = watch.lap();

    // 4. Volume-preserving outward offset, applied as the iso value (keeping it well inside the
    //    narrow band: meshing needs a voxel to spare).
    out.maxIsoValue = std::min(options.maxVolumeOffset * voxelSize, (fineHalfWidth - 2) * fine);
    if (options.preserveVolume) out.isoValue = volumeOffset(*phi, out.voxelVolume, out.maxIsoValue);
    out.secondsVolume = watch.lap();
    out.grid = phi;
    return out;
}

}  // namespace cavesim::mesh::detail

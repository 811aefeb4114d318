#include "sim/domain.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/vec3.h"
#include "sim/fractures.h"
#include "sim/noise.h"
#include "sim/recharge.h"

namespace cavesim {
namespace {

/// Distance from p to the segment ab (index units).
double segmentDistance(const Vec3d& p, const Vec3d& a, const Vec3d& b) {
    const Vec3d ab = sub(b, a), ap = sub(p, a);
    const double len2 = dot(ab, ab);
    double t = len2 > 0 ? dot(ap, ab) / len2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    const Vec3d q{a[0] + t * ab[0] - p[0], a[1] + t * ab[1] - p[1], a[2] + t * ab[2] - p[2]};
    return norm(q);
}

std::vector<std::size_t> boxVoxels(const Dims& d, const VoxelBox& b) {
    std::vector<std::size_t> out;
    for (int k = b.lo[2]; k <= b.hi[2]; ++k)
        for (int j = b.lo[1]; j <= b.hi[1]; ++j)
            for (int i = b.lo[0]; i <= b.hi[0]; ++i) out.push_back(d.index(i, j, k));
    return out;
}

/// The site's surfaces on the grid: inception horizons raise porosity, air above the land surface
/// and insoluble rock below the base of the limestone become inert (porosity 0).
void applySite(Domain& dom, const Scenario& s, const SiteData& site) {
    const Dims& d = dom.dims;
    if (site.nx != d.nx || site.ny != d.ny) throw InputError(s.path + ": the site data is not on the block's columns");
    const double h = s.voxelSize, z0 = s.site.origin[2];
    // World elevation → index units: voxel k's centre is at z0 + (k + 0.5) · h.
    dom.siteWaterTable.clear();
    for (double z : site.waterTable) dom.siteWaterTable.push_back((z - z0) / h - 0.5);
    for (int j = 0; j < d.ny; ++j)
        for (int i = 0; i < d.nx; ++i) {
            const std::size_t col = std::size_t(i) + std::size_t(d.nx) * std::size_t(j);
            for (int k = 0; k < d.nz; ++k) {
                const double z = z0 + (k + 0.5) * h;
                float& R = dom.porosity.at(i, j, k);
                for (std::size_t n = 0; n < site.horizons.size() && n < s.siteHorizons.size(); ++n) {
                    if (std::abs(z - site.horizons[n][col]) > 0.5 * s.siteHorizons[n].thickness * h) continue;
                    R = std::max(R, float(s.siteHorizons[n].porosity));
                    dom.flags.at(i, j, k) |= kFracture;
                }
                const bool air = !site.landSurface.empty() && z > site.landSurface[col];
                const bool insoluble = !site.baseOfLimestone.empty() && z < site.baseOfLimestone[col];
                if (air || insoluble) {
                    R = 0.f;
                    dom.flags.at(i, j, k) |= kInert;
                }
            }
        }
}

}  // namespace

Domain emptyDomain(const Dims& dims, double voxelSize, float porosity) {
    Domain dom;
    dom.dims = dims;
    dom.voxelSize = voxelSize;
    dom.porosity = Grid3<float>(dims, porosity);
    dom.porosity0 = dom.porosity;
    dom.rockPorosity = porosity;
    dom.flags = Grid3<std::uint8_t>(dims, 0);
    dom.zone = Grid3<std::int32_t>(dims, -1);
    dom.pressure = Grid3<float>(dims, 0.f);
    dom.water = Grid3<float>(dims, 0.f);
    dom.flow = Grid3<float>(dims, 0.f);
    return dom;
}

void placeTerminals(Domain& dom, const Scenario& s) {
    const Dims& d = dom.dims;
    for (const SourceSpec& src : allSources(s)) {
        dom.sourceVoxels.push_back(boxVoxels(d, src.box));
        dom.sourcePressure.push_back(src.pressure);
        for (std::size_t v : dom.sourceVoxels.back()) dom.flags[v] |= kSource;
    }
    // The scenario's sinks, then the site's springs.
    const auto placeSinks = [&](const std::vector<SinkSpec>& sinks) {
        for (const SinkSpec& snk : sinks) {
            dom.sinkVoxels.push_back(boxVoxels(d, snk.box));
            for (std::size_t v : dom.sinkVoxels.back()) dom.flags[v] |= kSink;
        }
    };
    placeSinks(s.sinks);
    if (s.siteData) placeSinks(s.siteData->sinks);
}

Domain buildDomain(const Scenario& s, Rng& rng) {
    Domain dom = emptyDomain(Dims{s.size[0], s.size[1], s.size[2]}, s.voxelSize, float(s.rockPorosity));
    const Dims& d = dom.dims;

    // Noise: always drawn from the engine (so later draws do not depend on whether noise is on).
    const GradientNoise noise(rng);
    if (s.noise.amplitude > 0) {
        const double inv = 1.0 / s.noise.scale;
        for (int k = 0; k < d.nz; ++k)
            for (int j = 0; j < d.ny; ++j)
                for (int i = 0; i < d.nx; ++i) {
                    const double n = noise.fractal(i * inv + 0.37, j * inv + 0.61, k * inv + 0.13, s.noise.octaves);
                    dom.porosity.at(i, j, k) = float(s.rockPorosity + s.noise.amplitude * n);
                }
    }

    for (const SphereObstacle& o : s.spheres) {
        const int r = int(std::ceil(o.radius));
        for (int k = std::max(0, int(o.center[2]) - r - 1); k <= std::min(d.nz - 1, int(o.center[2]) + r + 1); ++k)
            for (int j = std::max(0, int(o.center[1]) - r - 1); j <= std::min(d.ny - 1, int(o.center[1]) + r + 1); ++j)
                for (int i = std::max(0, int(o.center[0]) - r - 1); i <= std::min(d.nx - 1, int(o.center[0]) + r + 1);
                     ++i) {
                    const double dist = distance(o.center, {double(i), double(j), double(k)});
                    if (dist >= o.radius) continue;
                    // Porosity falls quadratically from the surrounding rock at the rim to the core value.
                    const double t = dist / o.radius;
                    float& R = dom.porosity.at(i, j, k);
                    R = float(o.corePorosity + (R - o.corePorosity) * t * t);
                    dom.flags.at(i, j, k) |= kObstacle;
                }
    }

    // Bedding planes and fractures, then inception horizons: the same slabs; a horizon's voxels are
    // also marked for stage 2's early-flow rate.
    if (!s.inceptionHorizons.empty() || !s.fractureFamilies.empty()) dom.inception = Grid3<std::uint8_t>(d, 0);
    std::vector<const PlaneFeature*> slabs;
    for (const PlaneFeature& p : s.planes) slabs.push_back(&p);
    for (const PlaneFeature& p : s.inceptionHorizons) slabs.push_back(&p);
    for (std::size_t slab = 0; slab < slabs.size(); ++slab) {
        const PlaneFeature& p = *slabs[slab];
        const bool inception = slab >= s.planes.size();
        const double nlen = norm(p.normal);
        const Vec3d n{p.normal[0] / nlen, p.normal[1] / nlen, p.normal[2] / nlen};
        for (int k = 0; k < d.nz; ++k)
            for (int j = 0; j < d.ny; ++j)
                for (int i = 0; i < d.nx; ++i) {
                    const Vec3d rel = sub({double(i), double(j), double(k)}, p.point);
                    const double h = dot(rel, n);
                    if (std::abs(h) > 0.5 * p.thickness) continue;
                    if (p.extent > 0) {
                        const Vec3d inplane{rel[0] - h * n[0], rel[1] - h * n[1], rel[2] - h * n[2]};
                        if (dot(inplane, inplane) > p.extent * p.extent) continue;
                    }
                    float& R = dom.porosity.at(i, j, k);
                    R = std::max(R, float(p.porosity));
                    dom.flags.at(i, j, k) |= kFracture;
                    if (inception) dom.inception.at(i, j, k) = 1;
                }
    }

    // Fracture families: discs from their own seeded streams (the run's engine is not drawn from);
    // their slabs are early-flow paths like inception horizons (marked in `dom.inception`).
    if (!s.fractureFamilies.empty())
        applyFractureNetwork(dom, generateFractureNetwork(s.fractureFamilies, d, s.seed), s.fractureFamilies);

    for (const ChannelFeature& c : s.channels) {
        // A polyline of at least the voxels it passes through (radius 0.5 catches the centre line).
        const double rad = std::max(c.radius, 0.5);
        for (std::size_t seg = 0; seg + 1 < c.points.size(); ++seg) {
            const Vec3d& a = c.points[seg];
            const Vec3d& b = c.points[seg + 1];
            int lo[3], hi[3];
            for (int ax = 0; ax < 3; ++ax) {
                lo[ax] = std::max(0, int(std::floor(std::min(a[ax], b[ax]) - rad)));
                hi[ax] = std::min((ax == 0   ? d.nx
                                   : ax == 1 ? d.ny
                                             : d.nz) -
                                      1,
                                  int(std::ceil(std::max(a[ax], b[ax]) + rad)));
            }
            for (int k = lo[2]; k <= hi[2]; ++k)
                for (int j = lo[1]; j <= hi[1]; ++j)
                    for (int i = lo[0]; i <= hi[0]; ++i) {
                        if (segmentDistance({double(i), double(j), double(k)}, a, b) > rad) continue;
                        float& R = dom.porosity.at(i, j, k);
                        R = std::max(R, float(c.porosity));
                        dom.flags.at(i, j, k) |= kFeatureChannel;
                        if (c.protochannel) dom.flags.at(i, j, k) |= kProtochannel;
                    }
        }
    }

    if (s.siteData) applySite(dom, s, *s.siteData);
    for (auto& R : dom.porosity.data) R = std::clamp(R, 0.f, 1.f);

    dom.origin = {s.site.origin[0], s.site.origin[1], s.site.origin[2]};
    placeTerminals(dom, s);
    dom.porosity0 = dom.porosity;
    return dom;
}

}  // namespace cavesim

/// @file protosinks.cpp
/// @brief Zone boundaries, cluster centres and clustered protosinks.
#include "flownet/protosinks.h"

#include <algorithm>
#include <limits>
#include <string>

#include "core/check.h"

namespace cavesim::flownet {
namespace {

double distance2(const Index3& a, const Index3& b) {
    const double di = a.i - b.i, dj = a.j - b.j, dk = a.k - b.k;
    return di * di + dj * dj + dk * dk;
}

/// Uniform index in [0, n) from one 64-bit draw (Lemire's multiply-shift, no rejection: the bias
/// is below n / 2^64, immaterial here, and the mapping is the same on every standard library).
std::size_t drawIndex(std::mt19937_64& rng, std::size_t n) {
    const unsigned __int128 r = static_cast<unsigned __int128>(rng()) * static_cast<unsigned __int128>(n);
    return std::size_t(r >> 64);
}

}  // namespace

std::vector<std::size_t> zoneBoundary(const Grid3<std::int32_t>& labels, const std::vector<std::size_t>& zoneVoxels,
                                      int zone, const GridFaces& faces) {
    const Dims& d = labels.dims;
    const int extent[3] = {d.nx, d.ny, d.nz};
    std::vector<std::size_t> out;
    for (std::size_t v : zoneVoxels) {
        CAVESIM_CHECK(
            v < labels.size() && labels[v] == zone,
            "zoneBoundary: voxel " + std::to_string(v) + " does not carry the label of zone " + std::to_string(zone));
        const Index3 p = d.coord(v);
        bool boundary = false;
        for (int f = 0; f < 6 && !boundary; ++f) {
            const NeighbourOffset& o = faceNeighbours()[f];
            const int i = p.i + o.di, j = p.j + o.dj, k = p.k + o.dk;
            if (!d.contains(i, j, k)) {
                boundary = faces[f] && extent[f / 2] > 1;
            } else {
                const std::int32_t l = labels.at(i, j, k);
                boundary = l >= 0 && l != zone;
            }
        }
        if (boundary) out.push_back(v);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

std::vector<std::size_t> chooseClusterCentres(const Dims& dims, const std::vector<std::size_t>& candidates, int count,
                                              const std::vector<Vec3d>& aim, std::mt19937_64& rng) {
    CAVESIM_CHECK(count >= 1, "chooseClusterCentres: count must be at least 1, got " + std::to_string(count));
    std::vector<std::size_t> centres;
    if (candidates.empty()) return centres;
    if (!aim.empty()) {
        for (const auto& a : aim) {
            std::size_t best = candidates.front();
            double bestD = std::numeric_limits<double>::infinity();
            for (std::size_t c : candidates) {  // increasing: the first minimum is the lower index
                const Index3 p = dims.coord(c);
                const double dx = p.i - a[0], dy = p.j - a[1], dz = p.k - a[2];
                const double dd = dx * dx + dy * dy + dz * dz;
                if (dd < bestD) {
                    bestD = dd;
                    best = c;
                }
            }
            if (std::find(centres.begin(), centres.end(), best) == centres.end()) centres.push_back(best);
        }
        return centres;
    }
    if (candidates.size() <= std::size_t(count)) return candidates;

    constexpr int kDraws = 16;
    std::vector<std::uint8_t> taken(candidates.size(), 0);
    for (int c = 0; c < count; ++c) {
        std::size_t best = 0;
        double bestD = -1;
        const int draws = centres.empty() ? 1 : kDraws;
        for (int t = 0; t < draws; ++t) {
            std::size_t pick = drawIndex(rng, candidates.size());
            while (taken[pick]) pick = (pick + 1) % candidates.size();  // distinct centres
            const Index3 p = dims.coord(candidates[pick]);
            double dmin = std::numeric_limits<double>::infinity();
            for (std::size_t q : centres) dmin = std::min(dmin, distance2(p, dims.coord(q)));
            if (dmin > bestD) {
                bestD = dmin;
                best = pick;
            }
        }
        taken[best] = 1;
        centres.push_back(candidates[best]);
    }
    return centres;
}

std::vector<std::size_t> clusterProtosinks(const Dims& dims, const std::vector<std::size_t>& candidates,
                                           const std::vector<std::size_t>& centres, double radius) {
    CAVESIM_CHECK(radius >= 0, "clusterProtosinks: radius must be >= 0, got " + std::to_string(radius));
    std::vector<Index3> c;
    for (std::size_t v : centres) c.push_back(dims.coord(v));
    const double r2 = radius * radius;
    std::vector<std::size_t> out;
    for (std::size_t v : candidates) {
        const Index3 p = dims.coord(v);
        for (const Index3& q : c)
            if (distance2(p, q) <= r2) {
                out.push_back(v);
                break;
            }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

}  // namespace cavesim::flownet

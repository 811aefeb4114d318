#include "formats/passages.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace cavesim::formats {

double distanceToWall(const Grid3<std::uint8_t>& cave, double voxelSize, const std::array<double, 3>& origin,
                      const std::array<double, 3>& direction) {
    const Dims& d = cave.dims;
    const int n[3] = {d.nx, d.ny, d.nz};
    double u[3];
    int cell[3], step[3];
    double tMax[3], tDelta[3];
    constexpr double kInf = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        u[a] = origin[a] / voxelSize;  // index-space coordinate; voxel c spans [c, c+1]
        cell[a] = int(std::floor(u[a]));
        if (!(u[a] >= 0.0) || cell[a] >= n[a]) return 0.0;
        if (direction[a] > 0) {
            step[a] = 1;
            tDelta[a] = 1.0 / direction[a];
            tMax[a] = (cell[a] + 1 - u[a]) * tDelta[a];
        } else if (direction[a] < 0) {
            step[a] = -1;
            tDelta[a] = -1.0 / direction[a];
            tMax[a] = (u[a] - cell[a]) * tDelta[a];
        } else {
            step[a] = 0;
            tDelta[a] = kInf;
            tMax[a] = kInf;
        }
    }
    if (!cave.at(cell[0], cell[1], cell[2])) return 0.0;
    for (;;) {
        int a = 0;
        if (tMax[1] < tMax[a]) a = 1;
        if (tMax[2] < tMax[a]) a = 2;
        if (tMax[a] == kInf) return 0.0;  // zero direction
        const double t = tMax[a];
        cell[a] += step[a];
        if (cell[a] < 0 || cell[a] >= n[a] || !cave.at(cell[0], cell[1], cell[2])) return t * voxelSize;
        tMax[a] += tDelta[a];
    }
}

Lrud measureLrud(const Grid3<std::uint8_t>& cave, double voxelSize, const std::array<double, 3>& position,
                 const std::array<double, 3>& heading) {
    double hx = heading[0], hy = heading[1];
    const double len = std::hypot(hx, hy);
    const double full = std::sqrt(hx * hx + hy * hy + heading[2] * heading[2]);
    if (!(len > 1e-9 * full) || !(len > 0)) {
        hx = 0;
        hy = 1;
    } else {
        hx /= len;
        hy /= len;
    }
    Lrud r;
    r.left = distanceToWall(cave, voxelSize, position, {-hy, hx, 0});
    r.right = distanceToWall(cave, voxelSize, position, {hy, -hx, 0});
    r.up = distanceToWall(cave, voxelSize, position, {0, 0, 1});
    r.down = distanceToWall(cave, voxelSize, position, {0, 0, -1});
    return r;
}

std::vector<morpho::Branch> findPassages(const morpho::Skeleton& skeleton) {
    return morpho::findBranches(skeleton);
}

std::vector<std::string> stationNames(const morpho::Skeleton& skeleton, const std::vector<morpho::Branch>& passages,
                                      const std::string& prefix, const std::string& separator) {
    std::vector<std::string> names(skeleton.nodes.size());
    for (std::size_t p = 0; p < passages.size(); ++p) {
        const auto& nodes = passages[p].nodes;
        for (std::size_t s = 0; s < nodes.size(); ++s) {
            std::string& name = names[std::size_t(nodes[s])];
            if (name.empty()) name = prefix + std::to_string(p) + separator + std::to_string(s);
        }
    }
    return names;
}

std::vector<int> passageOfNodes(const morpho::Skeleton& skeleton, const std::vector<morpho::Branch>& passages) {
    std::vector<int> passageOf(skeleton.nodes.size(), -1);
    for (std::size_t p = passages.size(); p-- > 0;)
        for (int v : passages[p].nodes) passageOf[std::size_t(v)] = int(p);
    return passageOf;
}

std::vector<int> pieceOfNodes(const morpho::Skeleton& skeleton) {
    // Union-find whose roots are the lowest index of their set: the smaller root always wins.
    std::vector<int> parent(skeleton.nodes.size());
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&parent](int v) {
        while (parent[std::size_t(v)] != v) v = parent[std::size_t(v)] = parent[std::size_t(parent[std::size_t(v)])];
        return v;
    };
    for (const auto& e : skeleton.edges) {
        const int a = find(e[0]), b = find(e[1]);
        if (a != b) parent[std::size_t(std::max(a, b))] = std::min(a, b);
    }
    for (std::size_t v = 0; v < parent.size(); ++v) parent[v] = find(int(v));
    return parent;
}

std::array<double, 3> passageHeading(const morpho::Skeleton& skeleton, const morpho::Branch& passage, std::size_t s) {
    std::array<double, 3> h{0, 0, 0};
    auto addLeg = [&](std::size_t from, std::size_t to) {
        const auto& a = skeleton.nodes[std::size_t(passage.nodes[from])].position;
        const auto& b = skeleton.nodes[std::size_t(passage.nodes[to])].position;
        const double v[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (len > 0)
            for (int c = 0; c < 3; ++c) h[c] += v[c] / len;
    };
    if (s > 0) addLeg(s - 1, s);
    if (s + 1 < passage.nodes.size()) addLeg(s, s + 1);
    return h;
}

LegReading legReading(const std::array<double, 3>& a, const std::array<double, 3>& b) {
    constexpr double kDeg = 180.0 / 3.14159265358979323846;
    const double dx = b[0] - a[0], dy = b[1] - a[1], dz = b[2] - a[2];
    LegReading r;
    const double horizontal = std::hypot(dx, dy);
    r.tape = std::sqrt(dx * dx + dy * dy + dz * dz);
    r.plumbed = !(horizontal > 1e-9 * r.tape);
    r.clino = r.tape > 0 ? std::atan2(dz, horizontal) * kDeg : 0.0;
    double c = r.plumbed ? 0.0 : std::atan2(dx, dy) * kDeg;
    if (c < 0) c += 360.0;
    if (c >= 360.0) c -= 360.0;
    r.compass = c;
    return r;
}

}  // namespace cavesim::formats

// The cave skeleton (issue 6): thinning keeps topology, the graph has the right shape,
// lengths and radii, and the files read back.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "morpho/skeleton.h"
#include "morpho/skeleton_io.h"

namespace {

using namespace cavesim;
using namespace cavesim::morpho;
using Mask = Grid3<std::uint8_t>;
using Vec3 = std::array<double, 3>;

constexpr double kPi = 3.14159265358979323846;

// ---- shapes (index space: voxel (i, j, k) has its centre at (i, j, k)) ---------------------------

/// Distance from p to the segment a–b; with `flat`, +∞ where p projects outside the segment (so a
/// tube ends in flat faces through a and b instead of half-balls).
double distanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b, bool flat = false) {
    Vec3 ab{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, ap{p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    const double l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    double t = l2 > 0 ? (ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / l2 : 0.0;
    if (flat && (t < -1e-9 || t > 1 + 1e-9)) return std::numeric_limits<double>::infinity();
    t = std::clamp(t, 0.0, 1.0);
    const double dx = ap[0] - t * ab[0], dy = ap[1] - t * ab[1], dz = ap[2] - t * ab[2];
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

/// Sets the voxels whose centres lie within `rho` voxels of the segment a–b; `rho = r + 0.5` is a
/// passage "of radius r voxels" (r voxels around its axis voxel). Rounded ends, or flat ones.
void addTube(Mask& m, const Vec3& a, const Vec3& b, double rho, bool flat = false) {
    const Dims& d = m.dims;
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i)
                if (distanceToSegment({double(i), double(j), double(k)}, a, b, flat) <= rho + 1e-9) m.at(i, j, k) = 1;
}

/// A torus around the z axis through `centre`: voxels within `rho` of the circle of radius R.
void addTorus(Mask& m, const Vec3& centre, double R, double rho) {
    const Dims& d = m.dims;
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                const double x = i - centre[0], y = j - centre[1], z = k - centre[2];
                const double q = std::sqrt(x * x + y * y) - R;
                if (std::sqrt(q * q + z * z) <= rho + 1e-9) m.at(i, j, k) = 1;
            }
}

int count(const Mask& m) {
    return int(std::count_if(m.data.begin(), m.data.end(), [](auto v) { return v != 0; }));
}

// ---- graph analysis -------------------------------------------------------------------------------

struct Topology {
    int nodes = 0, edges = 0, components = 0, ends = 0, junctions = 0, isolated = 0, branches = 0;
    int cycleRank = 0;  // E − V + C: independent loops
    std::vector<int> degree;
    std::vector<int> component;
};

Topology analyse(const Skeleton& s) {
    Topology t;
    t.nodes = int(s.nodes.size());
    t.edges = int(s.edges.size());
    t.degree.assign(s.nodes.size(), 0);
    std::vector<std::vector<int>> adj(s.nodes.size());
    for (const auto& e : s.edges) {
        ++t.degree[std::size_t(e[0])];
        ++t.degree[std::size_t(e[1])];
        adj[std::size_t(e[0])].push_back(e[1]);
        adj[std::size_t(e[1])].push_back(e[0]);
    }
    t.component.assign(s.nodes.size(), -1);
    std::vector<bool> allDegreeTwo;
    for (int sN = 0; sN < t.nodes; ++sN) {
        if (t.component[std::size_t(sN)] >= 0) continue;
        const int c = t.components++;
        bool allTwo = true;
        std::vector<int> stack{sN};
        t.component[std::size_t(sN)] = c;
        while (!stack.empty()) {
            const int u = stack.back();
            stack.pop_back();
            allTwo = allTwo && t.degree[std::size_t(u)] == 2;
            for (const int w : adj[std::size_t(u)])
                if (t.component[std::size_t(w)] < 0) {
                    t.component[std::size_t(w)] = c;
                    stack.push_back(w);
                }
        }
        allDegreeTwo.push_back(allTwo);
    }
    int endSum = 0;
    for (const int d : t.degree) {
        if (d == 0) ++t.isolated;
        if (d == 1) ++t.ends;
        if (d >= 3) ++t.junctions;
        if (d != 2) endSum += d;
    }
    t.branches = endSum / 2 + int(std::count(allDegreeTwo.begin(), allDegreeTwo.end(), true));
    t.cycleRank = t.edges - t.nodes + t.components;
    return t;
}

double edgeLength(const Skeleton& s, const std::array<int, 2>& e) {
    const auto& a = s.nodes[std::size_t(e[0])].position;
    const auto& b = s.nodes[std::size_t(e[1])].position;
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

double totalLength(const Skeleton& s) {
    double l = 0;
    for (const auto& e : s.edges) l += edgeLength(s, e);
    return l;
}

/// The data-structure contract of skeleton_graph.h, and every node on a cave voxel.
void expectWellFormed(const Skeleton& s, const Mask& mask, double h) {
    std::set<std::array<int, 2>> seen;
    for (const auto& e : s.edges) {
        ASSERT_GE(e[0], 0);
        ASSERT_LT(e[0], e[1]);
        ASSERT_LT(std::size_t(e[1]), s.nodes.size());
        EXPECT_TRUE(seen.insert(e).second) << "duplicate edge " << e[0] << "-" << e[1];
    }
    std::set<std::size_t> voxels;
    for (const SkeletonNode& n : s.nodes) {
        ASSERT_LT(n.voxel, mask.dims.count());
        EXPECT_NE(mask[n.voxel], 0) << "node on a non-cave voxel";
        EXPECT_TRUE(voxels.insert(n.voxel).second) << "two nodes on one voxel";
        EXPECT_GE(n.radius, 0.5 * h - 1e-12);
        for (const double c : n.position) EXPECT_TRUE(std::isfinite(c));
    }
}

// ---- independent topology of a voxel set: (26, 6) Euler characteristic of the closed unit cubes --

struct VoxelTopology {
    int components = 0;  // 26-connected cave components
    int cavities = 0;    // 6-connected background components not reaching the outside
    int tunnels = 0;     // first Betti number: b0 + b2 − χ
};

VoxelTopology voxelTopology(const Mask& m) {
    const Dims& d = m.dims;
    const int X = d.nx + 2, Y = d.ny + 2, Z = d.nz + 2;  // padded
    auto pad = [&](int i, int j, int k) {
        return std::size_t(i + 1) + std::size_t(X) * (std::size_t(j + 1) + std::size_t(Y) * std::size_t(k + 1));
    };
    std::vector<std::uint8_t> v(std::size_t(X) * std::size_t(Y) * std::size_t(Z), 0);
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) v[pad(i, j, k)] = m.at(i, j, k) != 0;
    auto decode = [&](std::size_t n) {
        return std::array<int, 3>{int(n % std::size_t(X)) - 1, int((n / std::size_t(X)) % std::size_t(Y)) - 1,
                                  int(n / (std::size_t(X) * std::size_t(Y))) - 1};
    };
    VoxelTopology t;
    std::vector<int> label(v.size(), -1);
    // Components, 26 (cave) and 6 (background).
    int bgComponents = 0;
    for (std::size_t s = 0; s < v.size(); ++s) {
        if (label[s] >= 0) continue;
        const bool fg = v[s] != 0;
        std::vector<std::size_t> stack{s};
        label[s] = 1;
        while (!stack.empty()) {
            const auto c = decode(stack.back());
            stack.pop_back();
            for (int dk = -1; dk <= 1; ++dk)
                for (int dj = -1; dj <= 1; ++dj)
                    for (int di = -1; di <= 1; ++di) {
                        const int l1 = std::abs(di) + std::abs(dj) + std::abs(dk);
                        if (l1 == 0 || (!fg && l1 != 1)) continue;
                        const int i = c[0] + di, j = c[1] + dj, k = c[2] + dk;
                        if (i < -1 || j < -1 || k < -1 || i > d.nx || j > d.ny || k > d.nz) continue;
                        const std::size_t n = pad(i, j, k);
                        if (label[n] < 0 && (v[n] != 0) == fg) {
                            label[n] = 1;
                            stack.push_back(n);
                        }
                    }
        }
        if (fg) {
            ++t.components;
        } else {
            ++bgComponents;
        }
    }
    t.cavities = bgComponents - 1;
    // χ of the union of closed cubes: vertices − edges + faces − cubes on the (n+1)³ lattice.
    std::set<std::array<int, 4>> verts, edges, faces;
    long cubes = 0;
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                if (!m.at(i, j, k)) continue;
                ++cubes;
                for (int a = 0; a < 2; ++a)
                    for (int b = 0; b < 2; ++b) {
                        for (int c = 0; c < 2; ++c) verts.insert({i + a, j + b, k + c, 0});
                        edges.insert({i, j + a, k + b, 0});
                        edges.insert({i + a, j, k + b, 1});
                        edges.insert({i + a, j + b, k, 2});
                    }
                for (int a = 0; a < 2; ++a) {
                    faces.insert({i + a, j, k, 0});
                    faces.insert({i, j + a, k, 1});
                    faces.insert({i, j, k + a, 2});
                }
            }
    const long chi = long(verts.size()) - long(edges.size()) + long(faces.size()) - cubes;
    t.tunnels = int(t.components + t.cavities - chi);
    return t;
}

// A seeded network of random tubes, some crossing (loops, junctions, thick clusters).
Mask randomNetwork(std::uint32_t seed, const Dims& d, int tubes) {
    std::mt19937 rng(seed);
    auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * (double(rng()) / 4294967296.0); };
    Mask m(d, 0);
    for (int t = 0; t < tubes; ++t) {
        const Vec3 a{uniform(0, d.nx - 1), uniform(0, d.ny - 1), uniform(0, d.nz - 1)};
        const Vec3 b{uniform(0, d.nx - 1), uniform(0, d.ny - 1), uniform(0, d.nz - 1)};
        addTube(m, a, b, uniform(0.5, 2.6));
    }
    return m;
}

/// Voxels within `rho` of the chain of segments through `points` (rounded joints).
void addPolyline(Mask& m, const std::vector<Vec3>& points, double rho) {
    for (std::size_t i = 1; i < points.size(); ++i) addTube(m, points[i - 1], points[i], rho);
}

/// Whether the world position `p` (metres) lies in a cave voxel or on its boundary.
bool insideCave(const Mask& m, const std::array<double, 3>& p, double h) {
    for (int a = 0; a < 8; ++a) {
        const int i = int(std::floor(p[0] / h + ((a & 1) ? 1e-9 : -1e-9)));
        const int j = int(std::floor(p[1] / h + ((a & 2) ? 1e-9 : -1e-9)));
        const int k = int(std::floor(p[2] / h + ((a & 4) ? 1e-9 : -1e-9)));
        if (m.dims.contains(i, j, k) && m.at(i, j, k) != 0) return true;
    }
    return false;
}

/// Every node lies in the cave, and a chain node (degree 2) stays within its radius of its voxel.
void expectNodesInPassage(const Skeleton& s, const Mask& m, double h) {
    const Topology t = analyse(s);
    for (std::size_t n = 0; n < s.nodes.size(); ++n) {
        const SkeletonNode& node = s.nodes[n];
        EXPECT_TRUE(insideCave(m, node.position, h)) << "node " << n << " outside the cave";
        if (t.degree[n] != 2) continue;
        const Index3 c = m.dims.coord(node.voxel);
        const double ox = node.position[0] / h - 0.5 - c.i, oy = node.position[1] / h - 0.5 - c.j,
                     oz = node.position[2] / h - 0.5 - c.k;
        EXPECT_LE(std::sqrt(ox * ox + oy * oy + oz * oz), node.radius / h + 1e-9) << "node " << n << " left its voxel";
    }
}

// ---- straight tubes -------------------------------------------------------------------------------

class StraightTube : public ::testing::TestWithParam<int> {};

// A tube of r voxels around its axis, 34 voxels long (flat ends through x = 3 and x = 36): one
// branch, 34 voxels long end wall to end wall, on the axis, radius r + 1/2 voxels.
TEST_P(StraightTube, AlongXIsOneBranchOfTheTubeLengthWithItsRadius) {
    const int r = GetParam();
    const double h = 0.5;
    Mask m({40, 11, 11}, 0);
    addTube(m, {3, 5, 5}, {36, 5, 5}, r + 0.5, true);
    const Skeleton s = skeletonize(m, h);
    expectWellFormed(s, m, h);
    expectNodesInPassage(s, m, h);
    const Topology t = analyse(s);
    EXPECT_EQ(t.components, 1);
    EXPECT_EQ(t.ends, 2);
    EXPECT_EQ(t.junctions, 0);
    EXPECT_EQ(t.branches, 1);
    EXPECT_EQ(t.cycleRank, 0);
    EXPECT_NEAR(totalLength(s) / h, 34.0, 1.0);
    for (const SkeletonNode& n : s.nodes) {
        const Index3 c = m.dims.coord(n.voxel);
        EXPECT_NEAR(n.position[1] / h - 0.5, 5.0, 0.5);
        EXPECT_NEAR(n.position[2] / h - 0.5, 5.0, 0.5);
        if (c.i >= 3 + r + 1 && c.i <= 36 - r - 1) {
            EXPECT_NEAR(n.radius / h, r + 0.5, 0.5) << "node at x = " << c.i;
        }
    }
}

// Along (1, 1, 0): the voxel cubes of the tube span 26·√2 along its axis.
TEST_P(StraightTube, AlongAFaceDiagonalIsOneBranchOfTheTubeLength) {
    const int r = GetParam();
    Mask m({34, 34, 11}, 0);
    addTube(m, {4, 4, 5}, {29, 29, 5}, r + 0.5, true);
    const Skeleton s = skeletonize(m, 1.0);
    expectWellFormed(s, m, 1.0);
    expectNodesInPassage(s, m, 1.0);
    const Topology t = analyse(s);
    EXPECT_EQ(t.components, 1);
    EXPECT_EQ(t.ends, 2);
    EXPECT_EQ(t.junctions, 0);
    EXPECT_EQ(t.cycleRank, 0);
    EXPECT_NEAR(totalLength(s), 26.0 * std::sqrt(2.0), 1.0);
}

// Along (1, 1, 1): 22·√3.
TEST_P(StraightTube, AlongASpaceDiagonalIsOneBranchOfTheTubeLength) {
    const int r = GetParam();
    Mask m({30, 30, 30}, 0);
    addTube(m, {4, 4, 4}, {25, 25, 25}, r + 0.5, true);
    const Skeleton s = skeletonize(m, 1.0);
    expectWellFormed(s, m, 1.0);
    expectNodesInPassage(s, m, 1.0);
    const Topology t = analyse(s);
    EXPECT_EQ(t.components, 1);
    EXPECT_EQ(t.ends, 2);
    EXPECT_EQ(t.junctions, 0);
    EXPECT_EQ(t.cycleRank, 0);
    EXPECT_NEAR(totalLength(s), 22.0 * std::sqrt(3.0), 1.0);
}

// A passage that runs through the whole grid ends on the grid faces: length = grid extent.
TEST_P(StraightTube, ThroughTheWholeGridEndsOnItsFaces) {
    const int r = GetParam();
    Mask m({25, 9, 9}, 0);
    addTube(m, {-5, 4, 4}, {30, 4, 4}, r + 0.5);
    const Skeleton s = skeletonize(m, 2.0);
    expectWellFormed(s, m, 2.0);
    const Topology t = analyse(s);
    EXPECT_EQ(t.branches, 1);
    EXPECT_EQ(t.ends, 2);
    EXPECT_NEAR(totalLength(s), 2.0 * 25, 2.0 * 1.0);
    double xmin = 1e9, xmax = -1e9;
    for (const SkeletonNode& n : s.nodes) {
        xmin = std::min(xmin, n.position[0]);
        xmax = std::max(xmax, n.position[0]);
    }
    EXPECT_NEAR(xmin, 0.0, 1e-9);
    EXPECT_NEAR(xmax, 50.0, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Radius, StraightTube, ::testing::Values(0, 1, 2));

// A one-voxel tube of L voxels: L nodes, length L·h exactly, radius h/2 everywhere.
TEST(Skeleton, OneVoxelTubeIsExact) {
    const double h = 0.25;
    Mask m({20, 3, 3}, 0);
    for (int i = 2; i < 17; ++i) m.at(i, 1, 1) = 1;  // 15 voxels
    const Skeleton s = skeletonize(m, h);
    ASSERT_EQ(s.nodes.size(), 15u);
    ASSERT_EQ(s.edges.size(), 14u);
    EXPECT_DOUBLE_EQ(totalLength(s), 15 * h);
    for (std::size_t n = 0; n < s.nodes.size(); ++n) {
        EXPECT_EQ(s.nodes[n].voxel, m.dims.index(int(n) + 2, 1, 1));  // ordered by voxel index
        EXPECT_DOUBLE_EQ(s.nodes[n].radius, 0.5 * h);
        EXPECT_DOUBLE_EQ(s.nodes[n].position[1], 1.5 * h);
        EXPECT_DOUBLE_EQ(s.nodes[n].position[2], 1.5 * h);
    }
    EXPECT_DOUBLE_EQ(s.nodes.front().position[0], 2.0 * h);  // on the end wall
    EXPECT_DOUBLE_EQ(s.nodes.back().position[0], 17.0 * h);
    for (std::size_t e = 0; e < s.edges.size(); ++e) EXPECT_EQ(s.edges[e], (std::array<int, 2>{int(e), int(e) + 1}));
}

// ---- loops ----------------------------------------------------------------------------------------

void expectOneCycle(const Skeleton& s) {
    const Topology t = analyse(s);
    EXPECT_EQ(t.components, 1);
    EXPECT_EQ(t.nodes, t.edges);
    EXPECT_EQ(t.cycleRank, 1);
    for (const int d : t.degree) EXPECT_EQ(d, 2);
}

TEST(Skeleton, ThinRingIsOneCycle) {
    Mask m({24, 24, 3}, 0);
    addTorus(m, {11.5, 11.5, 1}, 8.0, 0.5);
    ASSERT_EQ(voxelTopology(m).tunnels, 1);
    const Skeleton s = skeletonize(m, 1.0);
    expectWellFormed(s, m, 1.0);
    expectOneCycle(s);
    EXPECT_NEAR(totalLength(s), 2 * kPi * 8.0, 0.1 * 2 * kPi * 8.0);
}

TEST(Skeleton, ThickTorusIsOneCycleOfItsCircumference) {
    Mask m({36, 36, 11}, 0);
    addTorus(m, {17.5, 17.5, 5}, 11.0, 2.5);
    ASSERT_EQ(voxelTopology(m).tunnels, 1);
    const Skeleton s = skeletonize(m, 1.0);
    expectWellFormed(s, m, 1.0);
    expectNodesInPassage(s, m, 1.0);
    expectOneCycle(s);
    EXPECT_NEAR(totalLength(s), 2 * kPi * 11.0, 0.1 * 2 * kPi * 11.0);
    for (const SkeletonNode& n : s.nodes) {  // on the core circle
        const double x = n.position[0] - 18.0, y = n.position[1] - 18.0;
        EXPECT_NEAR(std::sqrt(x * x + y * y), 11.0, 1.0);
        EXPECT_NEAR(n.position[2] - 0.5, 5.0, 1.0);
    }
}

// A figure of eight: two loops sharing a passage.
TEST(Skeleton, TwoLoopsSharingAPassage) {
    Mask m({40, 24, 5}, 0);
    addPolyline(m, {{4, 4, 2}, {35, 4, 2}, {35, 19, 2}, {4, 19, 2}, {4, 4, 2}}, 1.5);
    addTube(m, {19, 4, 2}, {19, 19, 2}, 1.5);
    ASSERT_EQ(voxelTopology(m).tunnels, 2);
    const Skeleton s = skeletonize(m, 1.0);
    expectWellFormed(s, m, 1.0);
    const Topology t = analyse(s);
    EXPECT_EQ(t.components, 1);
    EXPECT_EQ(t.cycleRank, 2);
    EXPECT_EQ(t.ends, 0);
    EXPECT_EQ(t.junctions, 2);
    EXPECT_EQ(t.branches, 3);
}

// ---- junctions ------------------------------------------------------------------------------------

class Junction : public ::testing::TestWithParam<int> {};

TEST_P(Junction, TeeIsThreeBranchesAndOneJunction) {
    const int r = GetParam();
    Mask m({41, 30, 11}, 0);
    addTube(m, {4, 6, 5}, {36, 6, 5}, r + 0.5, true);
    addTube(m, {20, 6, 5}, {20, 26, 5}, r + 0.5, true);
    const Skeleton s = skeletonize(m, 1.0);
    expectWellFormed(s, m, 1.0);
    expectNodesInPassage(s, m, 1.0);
    const Topology t = analyse(s);
    EXPECT_EQ(t.components, 1);
    EXPECT_EQ(t.ends, 3);
    EXPECT_EQ(t.junctions, 1);
    EXPECT_EQ(t.branches, 3);
    EXPECT_EQ(t.cycleRank, 0);
    // The junction sits where the axes cross; total length = 33 + 20.5 voxels of passage axis.
    for (std::size_t n = 0; n < s.nodes.size(); ++n)
        if (t.degree[n] == 3) {
            EXPECT_NEAR(s.nodes[n].position[0] - 0.5, 20.0, 1.0);
            EXPECT_NEAR(s.nodes[n].position[1] - 0.5, 6.0, 1.0);
        }
    EXPECT_NEAR(totalLength(s), 33.0 + 20.5, 2.0);
}

TEST_P(Junction, CrossIsFourBranchesAndOneJunction) {
    const int r = GetParam();
    Mask m({41, 41, 11}, 0);
    addTube(m, {4, 20, 5}, {36, 20, 5}, r + 0.5, true);
    addTube(m, {20, 4, 5}, {20, 36, 5}, r + 0.5, true);
    const Skeleton s = skeletonize(m, 1.0);
    expectWellFormed(s, m, 1.0);
    expectNodesInPassage(s, m, 1.0);
    const Topology t = analyse(s);
    EXPECT_EQ(t.components, 1);
    EXPECT_EQ(t.ends, 4);
    EXPECT_EQ(t.junctions, 1);
    EXPECT_EQ(t.branches, 4);
    EXPECT_EQ(t.cycleRank, 0);
    for (std::size_t n = 0; n < s.nodes.size(); ++n)
        if (t.degree[n] >= 3) {
            EXPECT_EQ(t.degree[n], 4);
            EXPECT_NEAR(s.nodes[n].position[0] - 0.5, 20.0, 1.0);
            EXPECT_NEAR(s.nodes[n].position[1] - 0.5, 20.0, 1.0);
        }
    EXPECT_NEAR(totalLength(s), 2 * 33.0, 2.0);
}

// A vertical shaft joining a horizontal passage from above, at an angle.
TEST_P(Junction, ObliqueSideBranchIsThreeBranches) {
    const int r = GetParam();
    Mask m({41, 20, 30}, 0);
    addTube(m, {3, 10, 6}, {37, 10, 6}, r + 0.5);
    addTube(m, {18, 10, 6}, {28, 10, 26}, r + 0.5);
    const Skeleton s = skeletonize(m, 1.0);
    expectWellFormed(s, m, 1.0);
    const Topology t = analyse(s);
    EXPECT_EQ(t.components, 1);
    EXPECT_EQ(t.ends, 3);
    EXPECT_EQ(t.junctions, 1);
    EXPECT_EQ(t.cycleRank, 0);
}

INSTANTIATE_TEST_SUITE_P(Radius, Junction, ::testing::Values(0, 1, 2));

TEST(Skeleton, TwoSeparateTubesAreTwoComponents) {
    Mask m({30, 20, 9}, 0);
    addTube(m, {3, 4, 4}, {26, 4, 4}, 1.5, true);
    addTube(m, {3, 14, 4}, {26, 16, 4}, 2.5, true);
    const Skeleton s = skeletonize(m, 1.0);
    expectWellFormed(s, m, 1.0);
    const Topology t = analyse(s);
    EXPECT_EQ(t.components, 2);
    EXPECT_EQ(t.ends, 4);
    EXPECT_EQ(t.junctions, 0);
    EXPECT_EQ(t.branches, 2);
}

// ---- degenerate input -----------------------------------------------------------------------------

TEST(Skeleton, EmptyMaskGivesEmptySkeleton) {
    EXPECT_TRUE(skeletonize(Mask({10, 10, 10}, 0), 1.0).nodes.empty());
    EXPECT_TRUE(skeletonize(Mask({10, 10, 10}, 0), 1.0).edges.empty());
    EXPECT_TRUE(skeletonize(Mask({0, 0, 0}, 0), 1.0).nodes.empty());
    EXPECT_TRUE(skeletonize(Mask({5, 0, 5}, 0), 1.0).nodes.empty());
    EXPECT_TRUE(skeletonize(Mask(), 1.0).nodes.empty());
}

TEST(Skeleton, SingleVoxelIsOneNodeWithoutEdges) {
    Mask m({5, 6, 7}, 0);
    m.at(2, 3, 4) = 1;
    const Skeleton s = skeletonize(m, 2.0);
    ASSERT_EQ(s.nodes.size(), 1u);
    EXPECT_TRUE(s.edges.empty());
    EXPECT_EQ(s.nodes[0].voxel, m.dims.index(2, 3, 4));
    EXPECT_EQ(s.nodes[0].position, (std::array<double, 3>{5.0, 7.0, 9.0}));
    EXPECT_DOUBLE_EQ(s.nodes[0].radius, 1.0);

    Mask one({1, 1, 1}, 1);  // the whole grid is one cave voxel
    const Skeleton t = skeletonize(one, 1.0);
    ASSERT_EQ(t.nodes.size(), 1u);
    EXPECT_TRUE(t.edges.empty());
}

TEST(Skeleton, SmallBlobsShrinkToAPoint) {
    Mask m({12, 12, 12}, 0);
    addTube(m, {6, 6, 6}, {6, 6, 6}, 3.5);  // a ball
    const Topology t = analyse(skeletonize(m, 1.0));
    EXPECT_EQ(t.components, 1);
    EXPECT_EQ(t.cycleRank, 0);
    EXPECT_LE(t.branches, 1);
    Mask cube({4, 4, 4}, 0);
    for (int k = 1; k < 3; ++k)
        for (int j = 1; j < 3; ++j)
            for (int i = 1; i < 3; ++i) cube.at(i, j, k) = 1;
    const Topology c = analyse(skeletonize(cube, 1.0));
    EXPECT_EQ(c.components, 1);
    EXPECT_EQ(c.cycleRank, 0);
}

// Extents of 1: a line along y in a 1×N×1 grid, and loops in 2D sections.
TEST(Skeleton, GridsWithUnitExtents) {
    Mask line({1, 30, 1}, 1);
    const Skeleton s = skeletonize(line, 1.0);
    const Topology t = analyse(s);
    EXPECT_EQ(t.nodes, 30);
    EXPECT_EQ(t.branches, 1);
    EXPECT_DOUBLE_EQ(totalLength(s), 30.0);

    Mask ring({20, 20, 1}, 0);  // nz = 1: a horizontal section with a thick ring
    addTorus(ring, {9.5, 9.5, 0}, 6.5, 2.0);
    ASSERT_EQ(voxelTopology(ring).tunnels, 1);
    expectOneCycle(skeletonize(ring, 1.0));

    Mask vring({1, 20, 20}, 0);  // nx = 1
    for (int k = 0; k < 20; ++k)
        for (int j = 0; j < 20; ++j) {
            const double q = std::hypot(j - 9.5, k - 9.5);
            vring.at(0, j, k) = q >= 4.5 && q <= 8.5;
        }
    ASSERT_EQ(voxelTopology(vring).tunnels, 1);
    expectOneCycle(skeletonize(vring, 1.0));
}

// ---- 2D sections (ny = 1) -------------------------------------------------------------------------

// A wide passage in a vertical section thins to its medial line, not a sheet; the radius is the
// distance to the passage's walls within the section.
TEST(Skeleton, WideSectionPassageThinsToItsMedialLine) {
    Mask m({40, 1, 15}, 0);
    for (int k = 4; k <= 10; ++k)
        for (int i = 2; i <= 37; ++i) m.at(i, 0, k) = 1;  // 36 × 7 voxels
    const Skeleton s = skeletonize(m, 1.0);
    expectWellFormed(s, m, 1.0);
    expectNodesInPassage(s, m, 1.0);
    const Topology t = analyse(s);
    EXPECT_EQ(t.components, 1);
    EXPECT_EQ(t.ends, 2);
    EXPECT_EQ(t.junctions, 0);
    EXPECT_NEAR(totalLength(s), 36.0, 1.0);
    for (const SkeletonNode& n : s.nodes) {
        EXPECT_NEAR(n.position[2] - 0.5, 7.0, 0.5);
        EXPECT_DOUBLE_EQ(n.position[1], 0.5);
        const Index3 c = m.dims.coord(n.voxel);
        if (c.i >= 6 && c.i <= 33) {
            EXPECT_DOUBLE_EQ(n.radius, 3.5);
        }
    }
}

// Two-voxel-wide vertical and diagonal shafts in a section, and a section loop.
TEST(Skeleton, NarrowSectionPassagesKeepTheirLength) {
    Mask m({12, 1, 30}, 0);
    for (int k = 2; k <= 27; ++k) m.at(5, 0, k) = m.at(6, 0, k) = 1;
    Skeleton s = skeletonize(m, 1.0);
    Topology t = analyse(s);
    EXPECT_EQ(t.branches, 1);
    EXPECT_EQ(t.ends, 2);
    EXPECT_NEAR(totalLength(s), 26.0, 1.0);

    Mask d({40, 1, 40}, 0);  // a staircase band two voxels wide along (1, 0, 1)
    for (int q = 3; q <= 34; ++q) d.at(q, 0, q) = d.at(q + 1, 0, q) = 1;
    s = skeletonize(d, 1.0);
    t = analyse(s);
    EXPECT_EQ(t.branches, 1);
    EXPECT_EQ(t.ends, 2);
    EXPECT_NEAR(totalLength(s), 32.0 * std::sqrt(2.0), 1.5);

    Mask loop({30, 1, 30}, 0);
    for (int k = 0; k < 30; ++k)
        for (int i = 0; i < 30; ++i) {
            const double q = std::hypot(i - 14.5, k - 14.5);
            loop.at(i, 0, k) = q >= 7 && q <= 11;
        }
    ASSERT_EQ(voxelTopology(loop).tunnels, 1);
    expectOneCycle(skeletonize(loop, 1.0));
}

// Thin bands in 3D that the sequential re-check of plain LKC thinning eats from one end.
TEST(Skeleton, TwoVoxelBandsAndShaftsKeepTheirLength) {
    Mask band({12, 12, 30}, 0);  // one voxel thick in x, two wide in y, long in z
    for (int k = 2; k <= 27; ++k) band.at(5, 5, k) = band.at(5, 6, k) = 1;
    Skeleton s = skeletonize(band, 1.0);
    EXPECT_EQ(analyse(s).branches, 1);
    EXPECT_NEAR(totalLength(s), 26.0, 1.0);

    Mask shaft({12, 12, 30}, 0);  // two voxels side by side diagonally, long in z
    for (int k = 2; k <= 27; ++k) shaft.at(5, 5, k) = shaft.at(6, 4, k) = 1;
    s = skeletonize(shaft, 1.0);
    EXPECT_EQ(analyse(s).branches, 1);
    EXPECT_NEAR(totalLength(s), 26.0, 1.0);
}

// ---- topology and determinism on random networks ---------------------------------------------------

// Thinning keeps the cave's topology: components, cavities (pockets left unfilled) and tunnels of
// the voxel set, counted independently through the Euler characteristic of its closed cubes.
TEST(Thinning, KeepsTheTopologyOfRandomNetworks) {
    for (std::uint32_t seed = 1; seed <= 12; ++seed) {
        const Mask m = randomNetwork(seed, {40, 36, 16}, 7);
        const VoxelTopology before = voxelTopology(m);
        const Mask thin = thinToCurveSkeleton(m, false);
        const VoxelTopology after = voxelTopology(thin);
        EXPECT_EQ(after.components, before.components) << "seed " << seed;
        EXPECT_EQ(after.cavities, before.cavities) << "seed " << seed;
        EXPECT_EQ(after.tunnels, before.tunnels) << "seed " << seed;
        for (std::size_t n = 0; n < m.size(); ++n) {
            if (thin[n]) {
                ASSERT_NE(m[n], 0);
            }
        }
        EXPECT_LT(count(thin), count(m) / 4) << "seed " << seed;
    }
}

// The graph has the cave's loops and components: cycle rank E − V + C = tunnels of the voxels.
TEST(Skeleton, GraphHasTheLoopsAndComponentsOfRandomNetworks) {
    int loops = 0, networks = 0;
    for (std::uint32_t seed = 1; seed <= 16; ++seed) {
        const Mask m = randomNetwork(seed, {40, 36, 16}, 7);
        const VoxelTopology vt = voxelTopology(m);
        if (vt.cavities != 0) continue;  // filled first, which may change the tunnels
        ++networks;
        const Skeleton s = skeletonize(m, 1.0);
        expectWellFormed(s, m, 1.0);
        expectNodesInPassage(s, m, 1.0);
        const Topology t = analyse(s);
        EXPECT_EQ(t.components, vt.components) << "seed " << seed;
        EXPECT_EQ(t.cycleRank, vt.tunnels) << "seed " << seed;
        loops += vt.tunnels;
    }
    EXPECT_GE(networks, 12);
    EXPECT_GT(loops, 12);  // the sample does exercise loops
}

TEST(Skeleton, IsDeterministic) {
    const Mask m = randomNetwork(99, {50, 44, 18}, 10);
    const Skeleton a = skeletonize(m, 0.7);
    const Skeleton b = skeletonize(m, 0.7);
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    ASSERT_EQ(a.edges, b.edges);
    for (std::size_t n = 0; n < a.nodes.size(); ++n) {
        EXPECT_EQ(a.nodes[n].voxel, b.nodes[n].voxel);
        EXPECT_EQ(a.nodes[n].position, b.nodes[n].position);  // bit for bit
        EXPECT_EQ(a.nodes[n].radius, b.nodes[n].radius);
    }
    for (std::size_t n = 1; n < a.nodes.size(); ++n) EXPECT_LT(a.nodes[n - 1].voxel, a.nodes[n].voxel);
}

// Moving the cave inside the grid (away from the borders) moves the skeleton and nothing else.
TEST(Skeleton, TranslationMovesTheSkeletonExactly) {
    Mask a({44, 40, 16}, 0), b({60, 52, 25}, 0);
    const int di = 9, dj = 7, dk = 5;
    const Mask net = randomNetwork(5, {40, 36, 14}, 6);
    for (int k = 0; k < 14; ++k)
        for (int j = 0; j < 36; ++j)
            for (int i = 0; i < 40; ++i) {
                a.at(i + 2, j + 2, k + 1) = net.at(i, j, k);
                b.at(i + 2 + di, j + 2 + dj, k + 1 + dk) = net.at(i, j, k);
            }
    const double h = 0.5;
    const Skeleton sa = skeletonize(a, h), sb = skeletonize(b, h);
    ASSERT_GT(sa.nodes.size(), 20u);
    ASSERT_EQ(sa.nodes.size(), sb.nodes.size());
    EXPECT_EQ(sa.edges, sb.edges);
    for (std::size_t n = 0; n < sa.nodes.size(); ++n) {
        const Index3 ca = a.dims.coord(sa.nodes[n].voxel), cb = b.dims.coord(sb.nodes[n].voxel);
        EXPECT_EQ(cb, (Index3{ca.i + di, ca.j + dj, ca.k + dk}));
        EXPECT_NEAR(sb.nodes[n].position[0] - sa.nodes[n].position[0], di * h, 1e-9);
        EXPECT_NEAR(sb.nodes[n].position[1] - sa.nodes[n].position[1], dj * h, 1e-9);
        EXPECT_NEAR(sb.nodes[n].position[2] - sa.nodes[n].position[2], dk * h, 1e-9);
        EXPECT_EQ(sb.nodes[n].radius, sa.nodes[n].radius);
    }
}

// ---- cavities, pruning, smoothing -------------------------------------------------------------------

// A rock voxel enclosed in a passage would leave a closed shell; it is filled first.
TEST(Skeleton, EnclosedRockIsFilled) {
    Mask m({30, 11, 11}, 0);
    addTube(m, {3, 5, 5}, {26, 5, 5}, 3.5, true);
    m.at(14, 5, 5) = 0;
    ASSERT_EQ(voxelTopology(m).cavities, 1);
    const Topology t = analyse(skeletonize(m, 1.0));
    EXPECT_EQ(t.branches, 1);
    EXPECT_EQ(t.ends, 2);
    EXPECT_EQ(t.cycleRank, 0);
    // Left unfilled, thinning must keep the pocket (a closed surface around it).
    EXPECT_EQ(voxelTopology(thinToCurveSkeleton(m, false)).cavities, 1);
    EXPECT_EQ(voxelTopology(thinToCurveSkeleton(m, true)).cavities, 0);
}

// A pocket holding a separate cave component is not filled: components stay components.
TEST(Skeleton, PocketAroundAnotherComponentIsKept) {
    Mask m({11, 11, 11}, 0);
    for (int k = 1; k <= 9; ++k)
        for (int j = 1; j <= 9; ++j)
            for (int i = 1; i <= 9; ++i) m.at(i, j, k) = 1;
    for (int k = 3; k <= 7; ++k)
        for (int j = 3; j <= 7; ++j)
            for (int i = 3; i <= 7; ++i) m.at(i, j, k) = 0;
    m.at(5, 5, 5) = 1;  // an island in the pocket
    ASSERT_EQ(voxelTopology(m).components, 2);
    const Mask thin = thinToCurveSkeleton(m, true);
    EXPECT_EQ(voxelTopology(thin).components, 2);
    EXPECT_EQ(voxelTopology(thin).cavities, 1);
    EXPECT_EQ(analyse(skeletonize(m, 1.0)).components, 2);
}

// Bumps and shallow alcoves on a wide passage leave no branches (pruning removes the spur
// thinning leaves in an alcove); a side passage stays.
TEST(Skeleton, PruningRemovesBumpsAndKeepsSidePassages) {
    Mask m({40, 30, 13}, 0);
    addTube(m, {3, 6, 6}, {36, 6, 6}, 3.5, true);
    for (int i = 8; i <= 9; ++i)
        for (int k = 5; k <= 7; ++k) m.at(i, 10, k) = 1;  // a one-voxel bump on the wall
    m.at(28, 6, 10) = 1;                                  // a single voxel on the roof
    addTube(m, {20, 6, 6}, {20, 10.5, 6}, 1.5);           // an alcove 2.5 voxels deep
    Topology t = analyse(skeletonize(m, 1.0));
    EXPECT_EQ(t.branches, 1);
    EXPECT_EQ(t.junctions, 0);
    SkeletonOptions raw;
    raw.pruneFactor = 0;
    raw.minSpurLength = 0;
    t = analyse(skeletonize(m, 1.0, raw));
    EXPECT_EQ(t.branches, 3);  // the alcove's spur
    EXPECT_EQ(t.junctions, 1);

    addTube(m, {30, 6, 6}, {30, 20, 6}, 1.5, true);  // a side passage 10 voxels beyond the wall
    t = analyse(skeletonize(m, 1.0));
    EXPECT_EQ(t.branches, 3);
    EXPECT_EQ(t.junctions, 1);
}

/// Fraction of the horizontal skeleton length whose azimuth (folded to [0°, 180°)) lies within
/// `tolerance` degrees of `azimuth`.
double azimuthShare(const Skeleton& s, double azimuth, double tolerance) {
    double within = 0, total = 0;
    for (const auto& e : s.edges) {
        const auto& a = s.nodes[std::size_t(e[0])].position;
        const auto& b = s.nodes[std::size_t(e[1])].position;
        const double dx = b[0] - a[0], dy = b[1] - a[1];
        const double l = std::hypot(dx, dy);
        if (l < 1e-12) continue;
        double az = std::atan2(dy, dx) * 180.0 / kPi;
        az = std::fmod(az + 360.0, 180.0);
        double diff = std::abs(az - azimuth);
        diff = std::min(diff, 180.0 - diff);
        total += l;
        if (diff <= tolerance) within += l;
    }
    return total > 0 ? within / total : 0.0;
}

// A staircase along atan(1/2) ≈ 26.6° or atan(1/3) ≈ 18.4° reads as that direction once smoothed,
// not as 0° and 45° steps.
TEST(Skeleton, SmoothingRemovesTheStaircaseOrientation) {
    for (const double slope : {0.5, 1.0 / 3.0}) {
        const double azimuth = std::atan(slope) * 180.0 / kPi;
        Mask m({64, 30, 7}, 0);
        addTube(m, {4, 5, 3}, {4 + 54, 5 + 54 * slope, 3}, 1.5);
        SkeletonOptions voxels;
        voxels.smoothingIterations = 0;
        EXPECT_LT(azimuthShare(skeletonize(m, 1.0, voxels), azimuth, 10.0), 0.5) << slope;
        EXPECT_GT(azimuthShare(skeletonize(m, 1.0), azimuth, 10.0), 0.9) << slope;
    }
}

// ---- errors -------------------------------------------------------------------------------------------

TEST(Skeleton, RejectsBadInput) {
    const Mask m({4, 4, 4}, 1);
    EXPECT_THROW(skeletonize(m, 0.0), InternalError);
    EXPECT_THROW(skeletonize(m, -1.0), InternalError);
    EXPECT_THROW(skeletonize(m, std::nan("")), InternalError);
    EXPECT_THROW(skeletonize(m, std::numeric_limits<double>::infinity()), InternalError);
    Mask bad({4, 4, 4}, 1);
    bad.data.pop_back();
    EXPECT_THROW(skeletonize(bad, 1.0), InternalError);
    EXPECT_THROW(thinToCurveSkeleton(bad), InternalError);
    Mask negative;
    negative.dims = {-1, 2, 2};
    EXPECT_THROW(skeletonize(negative, 1.0), InternalError);
    SkeletonOptions o;
    o.pruneFactor = -1;
    EXPECT_THROW(skeletonize(m, 1.0, o), InternalError);
    o = {};
    o.minSpurLength = std::nan("");
    EXPECT_THROW(skeletonize(m, 1.0, o), InternalError);
    o = {};
    o.smoothingIterations = -1;
    EXPECT_THROW(skeletonize(m, 1.0, o), InternalError);
    o = {};
    o.smoothingWeight = 0;
    EXPECT_THROW(skeletonize(m, 1.0, o), InternalError);
    o.smoothingWeight = 1.5;
    EXPECT_THROW(skeletonize(m, 1.0, o), InternalError);
}

// ---- files ----------------------------------------------------------------------------------------

namespace fs = std::filesystem;

/// A fresh empty directory under the system temporary directory, removed at scope exit.
struct TempDir {
    fs::path path;
    TempDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        path = fs::temp_directory_path() /
               (std::string("cavesim_skel_") + info->name() + "_" + std::to_string(std::random_device{}()));
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

std::vector<std::string> readLines(const fs::path& p) {
    std::ifstream in(p);
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    return lines;
}

TEST(SkeletonFiles, WritesJsonAndKarstnetFiles) {
    Mask m({41, 30, 11}, 0);
    addTube(m, {4, 6, 5}, {36, 6, 5}, 1.5, true);
    addTube(m, {20, 6, 5}, {20, 26, 5}, 1.5, true);
    const double h = 0.3;
    const Skeleton s = skeletonize(m, h);
    ASSERT_GT(s.edges.size(), 10u);
    TempDir dir;
    writeSkeletonFiles(s, dir.path.string(), h, m.dims);

    // skeleton.json
    std::ifstream in(dir.path / "skeleton.json");
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_EQ(j.at("voxel_size_m").get<double>(), h);
    EXPECT_EQ(j.at("grid"), nlohmann::json({41, 30, 11}));
    ASSERT_EQ(j.at("nodes").size(), s.nodes.size());
    ASSERT_EQ(j.at("radius").size(), s.nodes.size());
    ASSERT_EQ(j.at("voxels").size(), s.nodes.size());
    ASSERT_EQ(j.at("edges").size(), s.edges.size());
    EXPECT_EQ(j.at("node_count").get<std::size_t>(), s.nodes.size());
    EXPECT_EQ(j.at("edge_count").get<std::size_t>(), s.edges.size());
    for (std::size_t n = 0; n < s.nodes.size(); ++n) {
        for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(j["nodes"][n][c].get<double>(), s.nodes[n].position[c]);
        EXPECT_EQ(j["radius"][n].get<double>(), s.nodes[n].radius);
        const Index3 v = m.dims.coord(s.nodes[n].voxel);
        EXPECT_EQ(j["voxels"][n], nlohmann::json({v.i, v.j, v.k}));
    }
    for (std::size_t e = 0; e < s.edges.size(); ++e)
        EXPECT_EQ(j["edges"][e], nlohmann::json({s.edges[e][0], s.edges[e][1]}));

    // karstnet: x y z per line; i j per line, 1-based.
    const auto nodes = readLines(dir.path / "skeleton_nodes.dat");
    const auto links = readLines(dir.path / "skeleton_links.dat");
    ASSERT_EQ(nodes.size(), s.nodes.size());
    ASSERT_EQ(links.size(), s.edges.size());
    for (std::size_t n = 0; n < nodes.size(); ++n) {
        std::istringstream line(nodes[n]);
        double x, y, z;
        std::string rest;
        ASSERT_TRUE(line >> x >> y >> z);
        EXPECT_FALSE(line >> rest);
        EXPECT_EQ(x, s.nodes[n].position[0]);  // exact round trip
        EXPECT_EQ(y, s.nodes[n].position[1]);
        EXPECT_EQ(z, s.nodes[n].position[2]);
    }
    for (std::size_t e = 0; e < links.size(); ++e) {
        std::istringstream line(links[e]);
        int a, b;
        std::string rest;
        ASSERT_TRUE(line >> a >> b);
        EXPECT_FALSE(line >> rest);
        EXPECT_EQ(a, s.edges[e][0] + 1);
        EXPECT_EQ(b, s.edges[e][1] + 1);
    }
    // Nothing else (no temporary files) left behind.
    std::set<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir.path)) names.insert(entry.path().filename().string());
    EXPECT_EQ(names, (std::set<std::string>{"skeleton.json", "skeleton_links.dat", "skeleton_nodes.dat"}));

    // Read back exactly.
    const SkeletonFile f = readSkeletonJson((dir.path / "skeleton.json").string());
    EXPECT_EQ(f.voxelSize, h);
    EXPECT_EQ(f.grid, m.dims);
    EXPECT_EQ(f.skeleton.edges, s.edges);
    ASSERT_EQ(f.skeleton.nodes.size(), s.nodes.size());
    for (std::size_t n = 0; n < s.nodes.size(); ++n) {
        EXPECT_EQ(f.skeleton.nodes[n].position, s.nodes[n].position);
        EXPECT_EQ(f.skeleton.nodes[n].radius, s.nodes[n].radius);
        EXPECT_EQ(f.skeleton.nodes[n].voxel, s.nodes[n].voxel);
    }

    // Overwriting works (rename over an existing file).
    writeSkeletonFiles(Skeleton{}, dir.path.string(), h, m.dims);
    EXPECT_TRUE(readLines(dir.path / "skeleton_nodes.dat").empty());
    EXPECT_TRUE(readSkeletonJson((dir.path / "skeleton.json").string()).skeleton.nodes.empty());
}

TEST(SkeletonFiles, Errors) {
    TempDir dir;
    Skeleton s;
    s.nodes.resize(2);
    s.nodes[1].voxel = 1;
    s.edges.push_back({0, 1});
    const Dims grid{2, 1, 1};
    EXPECT_THROW(writeSkeletonFiles(s, (dir.path / "missing").string(), 1.0, grid), RuntimeError);
    EXPECT_THROW(writeSkeletonFiles(s, dir.path.string(), 0.0, grid), InternalError);
    EXPECT_THROW(writeSkeletonFiles(s, dir.path.string(), 1.0, Dims{1, 1, 1}), InternalError);  // voxel 1 outside
    Skeleton badEdge = s;
    badEdge.edges[0] = {1, 0};
    EXPECT_THROW(writeSkeletonFiles(badEdge, dir.path.string(), 1.0, grid), InternalError);
    badEdge.edges[0] = {0, 2};
    EXPECT_THROW(writeSkeletonFiles(badEdge, dir.path.string(), 1.0, grid), InternalError);
    Skeleton nan = s;
    nan.nodes[0].position[1] = std::nan("");
    EXPECT_THROW(writeSkeletonFiles(nan, dir.path.string(), 1.0, grid), InternalError);
    EXPECT_TRUE(fs::is_empty(dir.path));  // nothing written on error

    EXPECT_THROW(readSkeletonJson((dir.path / "none.json").string()), RuntimeError);
    auto writeText = [&](const std::string& text) {
        std::ofstream(dir.path / "bad.json") << text;
        return (dir.path / "bad.json").string();
    };
    EXPECT_THROW(readSkeletonJson(writeText("{not json")), InputError);
    EXPECT_THROW(readSkeletonJson(writeText("{}")), InputError);
    EXPECT_THROW(readSkeletonJson(writeText(R"({"voxel_size_m": 1, "grid": [2,1,1], "nodes": [[0,0,0]],
        "radius": [1], "voxels": [[0,0,0]], "edges": [[0, 1]]})")),
                 InputError);
    EXPECT_THROW(readSkeletonJson(writeText(R"({"voxel_size_m": 1, "grid": [2,1,1], "nodes": [[0,0]],
        "radius": [1], "voxels": [[0,0,0]], "edges": []})")),
                 InputError);
}

}  // namespace

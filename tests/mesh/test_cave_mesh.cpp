// The smooth cave mesh against analytic shapes: volume, genus, closedness, orientation, thin tubes.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <queue>
#include <random>

#include "core/error.h"
#include "mesh/cave_mesh.h"

namespace cavesim::mesh {
namespace {

constexpr double kPi = 3.14159265358979323846;

using Mask = Grid3<std::uint8_t>;

// Voxel (i, j, k) is cave when inside(centre in voxel units) holds.
Mask maskFrom(Dims d, const std::function<bool(double, double, double)>& inside) {
    Mask m(d, 0);
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) m.at(i, j, k) = inside(i + 0.5, j + 0.5, k + 0.5) ? 1 : 0;
    return m;
}

long countVoxels(const Mask& m) {
    long n = 0;
    for (auto v : m.data) n += v;
    return n;
}

// 26-connected components of the mask.
long components26(const Mask& m) {
    std::vector<char> seen(m.size(), 0);
    long count = 0;
    for (std::size_t s = 0; s < m.size(); ++s) {
        if (!m[s] || seen[s]) continue;
        ++count;
        std::queue<std::size_t> q;
        q.push(s);
        seen[s] = 1;
        while (!q.empty()) {
            const Index3 p = m.dims.coord(q.front());
            q.pop();
            for (const auto& o : allNeighbours()) {
                const Index3 n{p.i + o.di, p.j + o.dj, p.k + o.dk};
                if (!m.dims.contains(n)) continue;
                const std::size_t id = m.dims.index(n);
                if (m[id] && !seen[id]) {
                    seen[id] = 1;
                    q.push(id);
                }
            }
        }
    }
    return count;
}

void expectClosedManifold(const MeshStats& s) {
    EXPECT_TRUE(s.manifold);
    EXPECT_TRUE(s.closed);
    EXPECT_GT(s.volumeM3, 0.0) << "outward orientation gives a positive signed volume";
}

TEST(CaveMesh, SphereHasItsVolumeGenusZeroAndOutwardNormals) {
    const double h = 0.5, R = 10.0, c = 13.0;
    const Mask m = maskFrom({26, 26, 26}, [&](double x, double y, double z) {
        return (x - c) * (x - c) + (y - c) * (y - c) + (z - c) * (z - c) <= R * R;
    });
    const TriangleMesh mesh = buildCaveMesh(m, h);
    const MeshStats s = measureMesh(mesh);
    expectClosedManifold(s);
    EXPECT_EQ(s.components, 1);
    EXPECT_EQ(s.eulerCharacteristic, 2);  // genus 0
    const double exact = 4.0 / 3.0 * kPi * std::pow(R * h, 3);
    EXPECT_NEAR(s.volumeM3, exact, 0.05 * exact);
    EXPECT_NEAR(s.areaM2, 4 * kPi * std::pow(R * h, 2), 0.08 * 4 * kPi * std::pow(R * h, 2));
    // Every face normal points away from the centre; every vertex lies near the sphere.
    const double cw = c * h;
    for (const auto& t : mesh.triangles) {
        const auto& a = mesh.vertices[t[0]];
        const auto& b = mesh.vertices[t[1]];
        const auto& d = mesh.vertices[t[2]];
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const double v[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
        const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        const double r[3] = {a[0] - cw, a[1] - cw, a[2] - cw};
        ASSERT_GT(n[0] * r[0] + n[1] * r[1] + n[2] * r[2], 0.0);
    }
    for (const auto& p : mesh.vertices) {
        const double r = std::sqrt((p[0] - cw) * (p[0] - cw) + (p[1] - cw) * (p[1] - cw) + (p[2] - cw) * (p[2] - cw));
        ASSERT_NEAR(r, R * h, 0.8 * h);
    }
}

TEST(CaveMesh, CylinderHasItsVolume) {
    const double h = 1.0, R = 6.0;
    const Mask m = maskFrom({16, 16, 26}, [&](double x, double y, double z) {
        return (x - 8) * (x - 8) + (y - 8) * (y - 8) <= R * R && z > 3 && z < 23;
    });
    const MeshStats s = measureMesh(buildCaveMesh(m, h));
    expectClosedManifold(s);
    EXPECT_EQ(s.eulerCharacteristic, 2);
    const double exact = kPi * R * R * 20.0;
    EXPECT_NEAR(s.volumeM3, exact, 0.05 * exact);
}

TEST(CaveMesh, TorusHasGenusOne) {
    const double Rmaj = 8.0, rmin = 3.0;
    const Mask m = maskFrom({26, 26, 10}, [&](double x, double y, double z) {
        const double q = std::hypot(x - 13, y - 13) - Rmaj;
        return q * q + (z - 5) * (z - 5) <= rmin * rmin;
    });
    const MeshStats s = measureMesh(buildCaveMesh(m, 1.0));
    expectClosedManifold(s);
    EXPECT_EQ(s.components, 1);
    EXPECT_EQ(s.eulerCharacteristic, 0);  // genus 1
    const double exact = 2 * kPi * kPi * Rmaj * rmin * rmin;
    EXPECT_NEAR(s.volumeM3, exact, 0.05 * exact);
}

TEST(CaveMesh, OneVoxelStraightTubeStaysOneRoundTube) {
    Mask m({24, 5, 5}, 0);
    for (int i = 2; i < 22; ++i) m.at(i, 2, 2) = 1;
    const TriangleMesh mesh = buildCaveMesh(m, 1.0);
    const MeshStats s = measureMesh(mesh);
    expectClosedManifold(s);
    EXPECT_EQ(s.components, 1);
    EXPECT_EQ(s.eulerCharacteristic, 2);
    // The voxels' volume (20 m³), in a round tube: away from the ends every vertex lies at the
    // same distance from the axis, at least the net's radius.
    EXPECT_NEAR(s.volumeM3, 20.0, 0.05 * 20.0);
    double sum = 0, sum2 = 0;
    int n = 0;
    for (const auto& p : mesh.vertices) {
        if (p[0] < 5 || p[0] > 19) continue;
        const double r = std::hypot(p[1] - 2.5, p[2] - 2.5);
        EXPECT_GT(r, MeshOptions{}.tubeRadius - 0.05);
        sum += r, sum2 += r * r, ++n;
    }
    ASSERT_GT(n, 50);
    const double mean = sum / n, sd = std::sqrt(std::max(0.0, sum2 / n - mean * mean));
    EXPECT_LT(sd, 0.06 * mean);
}

TEST(CaveMesh, CornerAndEdgeConnectedChainsStayConnected) {
    // Voxels touching only at corners (body diagonal) and only along edges (face diagonal).
    Mask corner({12, 12, 12}, 0);
    for (int i = 1; i < 11; ++i) corner.at(i, i, i) = 1;
    Mask edge({14, 5, 14}, 0);
    for (int i = 1; i < 13; ++i) edge.at(i, 2, i) = 1;
    for (const Mask* m : {&corner, &edge}) {
        const MeshStats s = measureMesh(buildCaveMesh(*m, 1.0));
        expectClosedManifold(s);
        EXPECT_EQ(s.components, 1);
        EXPECT_EQ(s.eulerCharacteristic, 2);
    }
}

TEST(CaveMesh, OneVoxelRingHasGenusOne) {
    Mask m({12, 12, 3}, 0);
    for (int i = 2; i < 10; ++i) {
        m.at(i, 2, 1) = m.at(i, 9, 1) = 1;
        m.at(2, i, 1) = m.at(9, i, 1) = 1;
    }
    const MeshStats s = measureMesh(buildCaveMesh(m, 1.0));
    expectClosedManifold(s);
    EXPECT_EQ(s.components, 1);
    EXPECT_EQ(s.eulerCharacteristic, 0);
}

TEST(CaveMesh, RandomWalkTubesGiveOneComponentPer26Component) {
    std::mt19937 rng(5);
    for (int trial = 0; trial < 4; ++trial) {
        Mask m({30, 30, 12}, 0);
        for (int walk = 0; walk < 3; ++walk) {
            int p[3] = {int(rng() % 30), int(rng() % 30), int(rng() % 12)};
            for (int step = 0; step < 60; ++step) {
                m.at(p[0], p[1], p[2]) = 1;
                for (int a = 0; a < 3; ++a) {
                    const int lim = a == 2 ? 12 : 30;
                    p[a] = std::clamp(p[a] + int(rng() % 3) - 1, 0, lim - 1);
                }
            }
        }
        const MeshStats s = measureMesh(buildCaveMesh(m, 1.0));
        expectClosedManifold(s);
        EXPECT_EQ(s.components, components26(m)) << "trial " << trial;
    }
}

TEST(CaveMesh, SingleVoxelIsABall) {
    Mask m({1, 1, 1}, 1);
    const MeshStats s = measureMesh(buildCaveMesh(m, 2.0));
    expectClosedManifold(s);
    EXPECT_EQ(s.eulerCharacteristic, 2);
    EXPECT_EQ(s.components, 1);
}

TEST(CaveMesh, SectionMasksMeshAsThinClosedSlabs) {
    const Mask m = maskFrom(
        {30, 1, 20}, [](double x, double, double z) { return (x - 15) * (x - 15) + (z - 10) * (z - 10) <= 64.0; });
    const TriangleMesh mesh = buildCaveMesh(m, 1.0);
    const MeshStats s = measureMesh(mesh);
    expectClosedManifold(s);
    EXPECT_EQ(s.components, 1);
    EXPECT_EQ(s.eulerCharacteristic, 2);
    double ylo = 1e9, yhi = -1e9;
    for (const auto& p : mesh.vertices) {
        ylo = std::min(ylo, p[1]);
        yhi = std::max(yhi, p[1]);
    }
    EXPECT_LT(yhi - ylo, 1.5);  // about one voxel thick
    EXPECT_GT(yhi - ylo, 0.9);
    EXPECT_NEAR(s.volumeM3, double(countVoxels(m)), 0.1 * countVoxels(m));
}

TEST(CaveMesh, EmptyMaskGivesEmptyMesh) {
    const Mask m({8, 8, 8}, 0);
    const TriangleMesh mesh = buildCaveMesh(m, 1.0);
    EXPECT_TRUE(mesh.vertices.empty());
    EXPECT_TRUE(mesh.triangles.empty());
    const MeshStats s = measureMesh(mesh);
    EXPECT_EQ(s.faces, 0);
    EXPECT_EQ(s.components, 0);
    EXPECT_FALSE(s.closed);
    EXPECT_TRUE(buildCaveMesh(Mask({0, 0, 0}), 1.0).triangles.empty());
}

TEST(CaveMesh, IsTheSameForAnyThreadCount) {
    const Mask m = maskFrom({20, 20, 8}, [](double x, double y, double z) {
        return std::abs(std::sin(x * 0.4) * 5 + 10 - y) < 1.5 && z > 2 && z < 6;
    });
    const TriangleMesh a = buildCaveMesh(m, 1.0), b = buildCaveMesh(m, 1.0);
    EXPECT_EQ(a.vertices, b.vertices);
    EXPECT_EQ(a.triangles, b.triangles);
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    const TriangleMesh c = buildCaveMesh(m, 1.0);
    EXPECT_EQ(a.vertices, c.vertices);
    EXPECT_EQ(a.triangles, c.triangles);
}

TEST(CaveMesh, AdaptiveMeshIsSmallerAndStillClosed) {
    const Mask m = maskFrom({26, 26, 10}, [&](double x, double y, double z) {
        const double q = std::hypot(x - 13, y - 13) - 8;
        return q * q + (z - 5) * (z - 5) <= 9;
    });
    MeshOptions o;
    o.adaptivity = 0.3;
    const MeshStats dense = measureMesh(buildCaveMesh(m, 1.0));
    const MeshStats coarse = measureMesh(buildCaveMesh(m, 1.0, o));
    EXPECT_LT(coarse.faces, dense.faces);
    EXPECT_TRUE(coarse.closed);
    EXPECT_EQ(coarse.eulerCharacteristic, 0);
    EXPECT_NEAR(coarse.volumeM3, dense.volumeM3, 0.02 * dense.volumeM3);  // the offset matches both
}

TEST(CaveMesh, RejectsBadOptions) {
    const Mask m({2, 2, 2}, 1);
    MeshOptions o;
    o.subdivision = 9;
    EXPECT_THROW(buildCaveMesh(m, 1.0, o), InternalError);
    o = {};
    o.tubeRadius = 0.1;
    EXPECT_THROW(buildCaveMesh(m, 1.0, o), InternalError);
    o = {};
    o.halfWidth = 2;
    EXPECT_THROW(buildCaveMesh(m, 1.0, o), InternalError);
    o = {};
    o.smoothingIterations = -1;
    EXPECT_THROW(buildCaveMesh(m, 1.0, o), InternalError);
    EXPECT_THROW(buildCaveMesh(m, 0.0), InternalError);
    EXPECT_THROW(buildCaveMesh(m, std::nan("")), InternalError);
}

}  // namespace
}  // namespace cavesim::mesh

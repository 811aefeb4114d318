// Plain-array mesh measures and the blocky voxel-face mesh (no OpenVDB, no OpenMesh here).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>

#include "core/check.h"
#include "mesh/cave_mesh.h"

namespace cavesim::mesh {
namespace {

struct UnionFind {
    std::vector<int> parent;
    explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
    int find(int x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    void unite(int a, int b) {
        a = find(a);
        b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
};

}  // namespace

MeshStats measureMesh(const TriangleMesh& mesh) {
    MeshStats s;
    const long nv = long(mesh.vertices.size());
    const long nf = long(mesh.triangles.size());
    if (nf == 0) return s;
    for (const auto& t : mesh.triangles)
        for (int c = 0; c < 3; ++c)
            CAVESIM_CHECK(t[c] >= 0 && t[c] < nv, "measureMesh: a triangle refers to the missing vertex " +
                                                      std::to_string(t[c]) + " of " + std::to_string(nv));

    // Area and signed volume (sum of signed tetrahedra against the origin).
    for (const auto& t : mesh.triangles) {
        const Vec3d& a = mesh.vertices[t[0]];
        const Vec3d& b = mesh.vertices[t[1]];
        const Vec3d& c = mesh.vertices[t[2]];
        const Vec3d n = cross(sub(b, a), sub(c, a));
        s.areaM2 += 0.5 * std::sqrt(dot(n, n));
        s.volumeM3 += dot(a, cross(b, c)) / 6.0;
    }

    // Half-edges sorted by their undirected edge.
    struct HalfEdge {
        std::uint64_t key;  // min << 32 | max
        int from, face;
    };
    std::vector<HalfEdge> he;
    he.reserve(std::size_t(3 * nf));
    std::vector<char> used(std::size_t(nv), 0);
    bool degenerate = false;
    for (long f = 0; f < nf; ++f) {
        const auto& t = mesh.triangles[std::size_t(f)];
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) degenerate = true;
        for (int c = 0; c < 3; ++c) {
            const int a = t[c], b = t[(c + 1) % 3];
            used[std::size_t(a)] = 1;
            he.push_back({std::uint64_t(std::min(a, b)) << 32 | std::uint64_t(std::max(a, b)), a, int(f)});
        }
    }
    std::sort(he.begin(), he.end(), [](const HalfEdge& x, const HalfEdge& y) {
        return x.key != y.key ? x.key < y.key : (x.from != y.from ? x.from < y.from : x.face < y.face);
    });

    long edges = 0;
    bool everyEdgeTwice = true, consistent = true;
    UnionFind faces{std::size_t(nf)};
    for (std::size_t i = 0; i < he.size();) {
        const HalfEdge& first = he[i];
        std::size_t j = i + 1;
        for (; j < he.size() && he[j].key == first.key; ++j) {
            faces.unite(first.face, he[j].face);
            if (he[j].from == first.from) consistent = false;  // the same direction twice
        }
        ++edges;
        const std::size_t count = j - i;
        if (count != 2) everyEdgeTwice = false;
        if (count > 2) consistent = false;
        i = j;
    }
    const long usedVertices = long(std::count(used.begin(), used.end(), 1));
    s.vertices = usedVertices;
    s.faces = nf;
    s.eulerCharacteristic = usedVertices - edges + nf;
    for (long f = 0; f < nf; ++f)
        if (faces.find(int(f)) == int(f)) ++s.components;

    // Vertex manifoldness: the triangles around a vertex form one fan, i.e. the edges opposite
    // the vertex (its link) form one connected chain or cycle.
    bool fans = true;
    if (consistent && !degenerate) {
        std::vector<int> start(std::size_t(nv) + 1, 0);
        for (const auto& t : mesh.triangles)
            for (int c = 0; c < 3; ++c) ++start[std::size_t(t[c]) + 1];
        std::partial_sum(start.begin(), start.end(), start.begin());
        std::vector<int> incident(std::size_t(start.back()));
        std::vector<int> fill(start.begin(), start.end() - 1);
        for (long f = 0; f < nf; ++f)
            for (int c = 0; c < 3; ++c)
                incident[std::size_t(fill[std::size_t(mesh.triangles[std::size_t(f)][c])]++)] = int(f);
        std::vector<int> local;
        for (long v = 0; v < nv && fans; ++v) {
            const int b = start[std::size_t(v)], e = start[std::size_t(v) + 1];
            if (e - b <= 1) continue;
            // Link vertices of v, joined by the link edge of each incident triangle.
            local.clear();
            std::vector<std::pair<int, int>> link;
            for (int n = b; n < e; ++n) {
                const auto& t = mesh.triangles[std::size_t(incident[std::size_t(n)])];
                const int c = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
                link.push_back({t[(c + 1) % 3], t[(c + 2) % 3]});
                local.push_back(t[(c + 1) % 3]);
                local.push_back(t[(c + 2) % 3]);
            }
            std::sort(local.begin(), local.end());
            local.erase(std::unique(local.begin(), local.end()), local.end());
            UnionFind uf(local.size());
            auto id = [&local](int x) { return int(std::lower_bound(local.begin(), local.end(), x) - local.begin()); };
            for (const auto& [x, y] : link) uf.unite(id(x), id(y));
            int roots = 0;
            for (std::size_t n = 0; n < local.size(); ++n)
                if (uf.find(int(n)) == int(n)) ++roots;
            if (roots != 1) fans = false;
        }
    }
    s.manifold = consistent && fans && !degenerate;
    s.closed = s.manifold && everyEdgeTwice;
    return s;
}

TriangleMesh buildVoxelMesh(const Grid3<std::uint8_t>& mask, double voxelSize) {
    CAVESIM_CHECK(voxelSize > 0.0 && std::isfinite(voxelSize),
                  "voxel size must be a positive number of metres, got " + std::to_string(voxelSize));
    const Dims& d = mask.dims;
    TriangleMesh mesh;
    std::unordered_map<std::uint64_t, int> corner;
    auto vertex = [&](int i, int j, int k) {
        const std::uint64_t key = (std::uint64_t(i) << 42) | (std::uint64_t(j) << 21) | std::uint64_t(k);
        auto [it, inserted] = corner.emplace(key, int(mesh.vertices.size()));
        if (inserted) mesh.vertices.push_back({i * voxelSize, j * voxelSize, k * voxelSize});
        return it->second;
    };
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                if (!mask.at(i, j, k)) continue;
                const int p[3] = {i, j, k};
                for (int axis = 0; axis < 3; ++axis)
                    for (int sign = -1; sign <= 1; sign += 2) {
                        int q[3] = {i, j, k};
                        q[axis] += sign;
                        if (d.contains(q[0], q[1], q[2]) && mask.at(q[0], q[1], q[2])) continue;
                        // Face corners, counter-clockwise seen from outside: tangent axes u, v
                        // with u × v = +axis, reversed on the negative side.
                        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
                        int ids[4];
                        const int uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
                        for (int c = 0; c < 4; ++c) {
                            int r[3] = {p[0], p[1], p[2]};
                            r[axis] += sign > 0 ? 1 : 0;
                            r[u] += uv[c][0];
                            r[v] += uv[c][1];
                            ids[c] = vertex(r[0], r[1], r[2]);
                        }
                        if (sign < 0) std::swap(ids[1], ids[3]);
                        mesh.triangles.push_back({ids[0], ids[1], ids[2]});
                        mesh.triangles.push_back({ids[0], ids[2], ids[3]});
                    }
            }
    return mesh;
}

}  // namespace cavesim::mesh

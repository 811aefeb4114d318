#include "morpho/skeleton.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <iterator>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "core/check.h"

namespace cavesim::morpho {
namespace {

// ------------------------------------------------------------------------------------------------
// The cave's bounding box cut from the mask, with one voxel of background around it, so that every
// cave voxel has all 26 neighbours in memory and "outside the grid" reads as background. Nothing
// outside the box is cave, so distances to the background, thinning and rays are the same as on
// the whole grid.
// ------------------------------------------------------------------------------------------------
struct Padded {
    Dims inner;              // the box, voxels
    Index3 origin;           // grid coordinate of the box's voxel (0, 0, 0)
    int sectionNormal = -1;  // of the whole grid: see sectionNormalAxis
    int px = 0, py = 0, pz = 0;
    std::vector<std::uint8_t> v;  // 1 = cave (or skeleton), 0 = background

    explicit Padded(const Dims& d) : inner(d), px(d.nx + 2), py(d.ny + 2), pz(d.nz + 2) {
        v.assign(std::size_t(px) * std::size_t(py) * std::size_t(pz), 0);
    }
    /// Padded linear index of the inner voxel (i, j, k).
    std::size_t index(int i, int j, int k) const {
        return std::size_t(i + 1) + std::size_t(px) * (std::size_t(j + 1) + std::size_t(py) * std::size_t(k + 1));
    }
    /// Inner voxel coordinate of a padded linear index.
    Index3 innerCoord(std::size_t n) const {
        const int i = int(n % std::size_t(px));
        const std::size_t r = n / std::size_t(px);
        return {i - 1, int(r % std::size_t(py)) - 1, int(r / std::size_t(py)) - 1};
    }
    std::ptrdiff_t offset(int di, int dj, int dk) const {
        return std::ptrdiff_t(di) + std::ptrdiff_t(px) * (std::ptrdiff_t(dj) + std::ptrdiff_t(py) * std::ptrdiff_t(dk));
    }
};

/// The axis a distance is not measured along, or −1: on a 2D section (exactly one extent 1) the
/// padding beyond the section's two faces is not a wall; distances are measured within the section.
int sectionNormalAxis(const Dims& d) {
    const int ones = int(d.nx == 1) + int(d.ny == 1) + int(d.nz == 1);
    if (ones != 1) return -1;
    return d.nx == 1 ? 0 : (d.ny == 1 ? 1 : 2);
}

/// The padded bounding box of the cave voxels (an empty box when there are none).
Padded padMask(const Grid3<std::uint8_t>& mask) {
    const Dims& d = mask.dims;
    Index3 lo{d.nx, d.ny, d.nz}, hi{-1, -1, -1};
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i)
                if (mask.at(i, j, k) != 0) {
                    lo = {std::min(lo.i, i), std::min(lo.j, j), std::min(lo.k, k)};
                    hi = {std::max(hi.i, i), std::max(hi.j, j), std::max(hi.k, k)};
                }
    if (hi.i < 0) return Padded(Dims{0, 0, 0});
    Padded p(Dims{hi.i - lo.i + 1, hi.j - lo.j + 1, hi.k - lo.k + 1});
    p.origin = lo;
    p.sectionNormal = sectionNormalAxis(d);
    for (int k = lo.k; k <= hi.k; ++k)
        for (int j = lo.j; j <= hi.j; ++j)
            for (int i = lo.i; i <= hi.i; ++i)
                if (mask.at(i, j, k) != 0) p.v[p.index(i - lo.i, j - lo.j, k - lo.k)] = 1;
    return p;
}

// ------------------------------------------------------------------------------------------------
// 3×3×3 neighbourhoods as bit masks: position code c = (dx+1) + 3(dy+1) + 9(dz+1), centre 13.
// ------------------------------------------------------------------------------------------------
constexpr int kCentre = 13;

struct NeighbourhoodTables {
    std::array<std::uint32_t, 27> adj26{};  // positions 26-adjacent to c (centre excluded)
    std::array<std::uint32_t, 27> adj6{};   // positions 6-adjacent to c (centre excluded)
    std::uint32_t n18 = 0;                  // N18*(centre): faces and edges
    std::uint32_t face6 = 0;                // the 6 face neighbours of the centre
    std::array<std::uint32_t, 6> side{};    // the −x, +x, −y, +y, −z, +z thirds of the block
};

const NeighbourhoodTables& tables() {
    static const NeighbourhoodTables t = [] {
        NeighbourhoodTables r;
        auto decode = [](int c, int& x, int& y, int& z) {
            x = c % 3 - 1;
            y = (c / 3) % 3 - 1;
            z = c / 9 - 1;
        };
        for (int c = 0; c < 27; ++c) {
            if (c == kCentre) continue;
            int x, y, z;
            decode(c, x, y, z);
            const int l1 = std::abs(x) + std::abs(y) + std::abs(z);
            if (l1 <= 2) r.n18 |= 1u << c;
            if (l1 == 1) r.face6 |= 1u << c;
            const int coord[3] = {x, y, z};
            for (int a = 0; a < 3; ++a) {
                if (coord[a] < 0) r.side[std::size_t(2 * a)] |= 1u << c;
                if (coord[a] > 0) r.side[std::size_t(2 * a + 1)] |= 1u << c;
            }
            for (int q = 0; q < 27; ++q) {
                if (q == kCentre || q == c) continue;
                int a, b, e;
                decode(q, a, b, e);
                const int dx = std::abs(a - x), dy = std::abs(b - y), dz = std::abs(e - z);
                if (std::max({dx, dy, dz}) <= 1) r.adj26[c] |= 1u << q;
                if (dx + dy + dz == 1) r.adj6[c] |= 1u << q;
            }
        }
        return r;
    }();
    return t;
}

int lowestBit(std::uint32_t m) {
    return __builtin_ctz(m);
}
int popCount(std::uint32_t m) {
    return __builtin_popcount(m);
}

/// The connected part of `set` that contains the bits of `seed`, under adjacency `adj`.
std::uint32_t flood(std::uint32_t seed, std::uint32_t set, const std::array<std::uint32_t, 27>& adj) {
    std::uint32_t comp = seed, frontier = seed;
    while (frontier != 0) {
        std::uint32_t grow = 0;
        while (frontier != 0) {
            grow |= adj[lowestBit(frontier)];
            frontier &= frontier - 1;
        }
        grow &= set & ~comp;
        comp |= grow;
        frontier = grow;
    }
    return comp;
}

/// Simple-point test for (26, 6) connectivity (Bertrand & Malandain 1994): the cave in N26*(p)
/// is one 26-component and the background in N18*(p) has exactly one 6-component 6-adjacent to p.
/// `fg` holds the cave bits of the 26 neighbours.
bool isSimple(std::uint32_t fg) {
    const NeighbourhoodTables& t = tables();
    if (fg == 0) return false;  // isolated voxel: deleting it deletes a component
    if (flood(1u << lowestBit(fg), fg, t.adj26) != fg) return false;
    const std::uint32_t bg = t.n18 & ~fg;
    const std::uint32_t touching = bg & t.face6;
    if (touching == 0) return false;  // interior voxel: deleting it makes a cavity
    const std::uint32_t comp = flood(1u << lowestBit(touching), bg, t.adj6);
    return (touching & ~comp) == 0;
}

/// A tip: the cave neighbours (at least one) all lie in one 2×2×2 block with the voxel, i.e. on
/// no axis on both sides of it — the end of a curve one or two voxels thick.
bool isTip(std::uint32_t fg) {
    const NeighbourhoodTables& t = tables();
    if (fg == 0) return false;
    for (int a = 0; a < 3; ++a)
        if ((fg & t.side[std::size_t(2 * a)]) != 0 && (fg & t.side[std::size_t(2 * a + 1)]) != 0) return false;
    return true;
}

struct NeighbourOffsets {
    std::array<std::ptrdiff_t, 27> off{};
};

NeighbourOffsets neighbourOffsets(const Padded& g) {
    NeighbourOffsets o;
    for (int c = 0; c < 27; ++c) o.off[c] = g.offset(c % 3 - 1, (c / 3) % 3 - 1, c / 9 - 1);
    return o;
}

std::uint32_t neighbourhood(const std::uint8_t* v, std::size_t n, const NeighbourOffsets& o) {
    std::uint32_t m = 0;
    for (int c = 0; c < 27; ++c)
        if (c != kCentre && v[std::ptrdiff_t(n) + o.off[c]] != 0) m |= 1u << c;
    return m;
}

// ------------------------------------------------------------------------------------------------
// Step 1: enclosed background pockets.
// ------------------------------------------------------------------------------------------------
void fillEnclosedCavities(Padded& g) {
    const std::size_t count = g.v.size();
    // Background reachable from the padding (6-connected). The padding is one connected shell.
    std::vector<std::uint8_t> outside(count, 0);
    std::vector<std::size_t> queue;
    queue.reserve(1024);
    outside[0] = 1;
    queue.push_back(0);
    for (std::size_t head = 0; head < queue.size(); ++head) {
        const std::size_t n = queue[head];
        const Index3 c = g.innerCoord(n);  // inner coordinates: −1 … n
        static constexpr int kFace[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
        for (const auto& f : kFace) {
            const int i = c.i + f[0], j = c.j + f[1], k = c.k + f[2];
            if (i < -1 || j < -1 || k < -1 || i > g.inner.nx || j > g.inner.ny || k > g.inner.nz) continue;
            const std::size_t m = g.index(i, j, k);
            if (g.v[m] == 0 && outside[m] == 0) {
                outside[m] = 1;
                queue.push_back(m);
            }
        }
    }
    bool anyPocket = false;
    for (std::size_t n = 0; n < count && !anyPocket; ++n) anyPocket = g.v[n] == 0 && outside[n] == 0;
    if (!anyPocket) return;

    // Label the cave's 26-components (cave voxels are never in the padding, so all 26
    // neighbours are in memory).
    const NeighbourOffsets o = neighbourOffsets(g);
    std::vector<int> label(count, -1);
    int labels = 0;
    for (std::size_t s = 0; s < count; ++s) {
        if (g.v[s] == 0 || label[s] >= 0) continue;
        queue.clear();
        queue.push_back(s);
        label[s] = labels;
        for (std::size_t head = 0; head < queue.size(); ++head) {
            const std::size_t n = queue[head];
            for (int c = 0; c < 27; ++c) {
                if (c == kCentre) continue;
                const std::size_t m = std::size_t(std::ptrdiff_t(n) + o.off[c]);
                if (g.v[m] != 0 && label[m] < 0) {
                    label[m] = labels;
                    queue.push_back(m);
                }
            }
        }
        ++labels;
    }
    // Each pocket (a 6-component of enclosed background) is filled when every cave voxel around
    // it belongs to one component.
    const std::array<std::ptrdiff_t, 6> face = {o.off[12], o.off[14], o.off[10], o.off[16], o.off[4], o.off[22]};
    std::vector<std::uint8_t> seen(count, 0);
    for (std::size_t s = 0; s < count; ++s) {
        if (g.v[s] != 0 || outside[s] != 0 || seen[s] != 0) continue;
        queue.clear();
        queue.push_back(s);
        seen[s] = 1;
        int owner = -1;
        bool single = true;
        for (std::size_t head = 0; head < queue.size(); ++head) {
            const std::size_t n = queue[head];
            for (const std::ptrdiff_t f : face) {
                const std::size_t m = std::size_t(std::ptrdiff_t(n) + f);
                if (g.v[m] != 0) {
                    if (owner < 0)
                        owner = label[m];
                    else if (owner != label[m])
                        single = false;
                } else if (seen[m] == 0) {
                    seen[m] = 1;
                    queue.push_back(m);
                }
            }
        }
        if (single)
            for (const std::size_t n : queue) g.v[n] = 1;
    }
}

// ------------------------------------------------------------------------------------------------
// Step 2: directional thinning (Lee, Kashyap & Chu 1994) with an exact simple-point test.
// ------------------------------------------------------------------------------------------------
void thin(Padded& g) {
    const NeighbourOffsets o = neighbourOffsets(g);
    const int sectionNormal = g.sectionNormal;
    std::uint8_t* v = g.v.data();
    std::vector<std::size_t> fg;
    for (std::size_t n = 0; n < g.v.size(); ++n)
        if (v[n] != 0) fg.push_back(n);
    // Border directions: −x, +x, −y, +y, −z, +z.
    const std::array<std::ptrdiff_t, 6> border = {o.off[12], o.off[14], o.off[10], o.off[16], o.off[4], o.off[22]};
    // Candidate voxel, and whether it may be deleted even if it has become a tip meanwhile.
    std::vector<std::pair<std::size_t, bool>> candidates;
    for (;;) {
        bool deletedInPass = false;
        for (int b = 0; b < 6; ++b) {
            if (b / 2 == sectionNormal) continue;  // a 2D section: every voxel borders its faces
            const std::ptrdiff_t dir = border[std::size_t(b)];
            candidates.clear();
            for (const std::size_t n : fg) {
                if (v[std::ptrdiff_t(n) + dir] != 0) continue;
                const std::uint32_t m = neighbourhood(v, n, o);
                if (popCount(m) > 1 && isSimple(m))
                    candidates.emplace_back(n, v[std::ptrdiff_t(n) - dir] != 0 || isTip(m));
            }
            bool deleted = false;
            for (const auto& [n, tipMayGo] : candidates) {
                const std::uint32_t m = neighbourhood(v, n, o);
                if (popCount(m) > 1 && (tipMayGo || !isTip(m)) && isSimple(m)) {
                    v[n] = 0;
                    deleted = true;
                }
            }
            if (deleted) {
                deletedInPass = true;
                fg.erase(std::remove_if(fg.begin(), fg.end(), [v](std::size_t n) { return v[n] == 0; }), fg.end());
            }
        }
        if (!deletedInPass) break;
    }
}

/// Squared distances on the padded grid (0 on background), voxel units, to the nearest background
/// voxel centre, ignoring axis `skipAxis` (−1: none). Stored as float: squared distances are
/// integers, exact in float up to 2^24.
std::vector<float> squaredDistanceToBackground(const Padded& g, int skipAxis) {
    const int px = g.px, py = g.py, pz = g.pz;
    constexpr double kFar = 1e18;
    std::vector<float> d(g.v.size(), 0.0f);
    std::vector<double> line, out;
    std::vector<int> vtx;
    std::vector<double> z;
    // x: distance along the row to the nearest background voxel (every row has padding at both ends).
    line.resize(std::size_t(px));
    for (int k = 0; k < pz; ++k)
        for (int j = 0; j < py; ++j) {
            const std::size_t base = std::size_t(px) * (std::size_t(j) + std::size_t(py) * std::size_t(k));
            if (skipAxis == 0) {
                for (int i = 0; i < px; ++i)
                    d[base + std::size_t(i)] = g.v[base + std::size_t(i)] != 0 ? float(kFar) : 0.0f;
                continue;
            }
            double last = -kFar;
            for (int i = 0; i < px; ++i) {
                if (g.v[base + std::size_t(i)] == 0) last = i;
                line[std::size_t(i)] = i - last;
            }
            last = kFar;
            for (int i = px - 1; i >= 0; --i) {
                if (g.v[base + std::size_t(i)] == 0) last = i;
                const double a = std::min(line[std::size_t(i)], last - i);
                d[base + std::size_t(i)] = float(a * a);
            }
        }
    // y and z: lower envelopes of parabolas over the previous pass.
    auto pass = [&](int n, std::size_t stride, auto&& lineStarts) {
        line.resize(std::size_t(n));
        out.resize(std::size_t(n));
        lineStarts([&](std::size_t base) {
            for (int q = 0; q < n; ++q) line[std::size_t(q)] = d[base + std::size_t(q) * stride];
            envelope1d(line.data(), n, out.data(), vtx, z);
            for (int q = 0; q < n; ++q) d[base + std::size_t(q) * stride] = float(out[std::size_t(q)]);
        });
    };
    if (skipAxis != 1)
        pass(py, std::size_t(px), [&](auto&& f) {
            for (int k = 0; k < pz; ++k)
                for (int i = 0; i < px; ++i) f(std::size_t(i) + std::size_t(px) * std::size_t(py) * std::size_t(k));
        });
    if (skipAxis != 2)
        pass(pz, std::size_t(px) * std::size_t(py), [&](auto&& f) {
            for (int j = 0; j < py; ++j)
                for (int i = 0; i < px; ++i) f(std::size_t(i) + std::size_t(px) * std::size_t(j));
        });
    return d;
}

// ------------------------------------------------------------------------------------------------
// Steps 3–5 on a small adjacency-list graph of voxels.
// ------------------------------------------------------------------------------------------------
struct WorkGraph {
    std::vector<std::size_t> pad;  // padded linear index of the node's voxel
    std::vector<Index3> ijk;       // inner voxel coordinate
    std::vector<double> dist;      // distance (voxels) from the voxel centre to the nearest background centre
    std::vector<Vec3d> pos;        // position, voxel units (index space)
    std::vector<std::vector<int>> adj;
    std::vector<char> alive;
    const std::vector<float>* dist2 = nullptr;  // squared distance per padded voxel

    float dist2Of(std::size_t paddedIndex) const { return (*dist2)[paddedIndex]; }
    int size() const { return int(pad.size()); }
    int degree(int u) const { return int(adj[std::size_t(u)].size()); }
    int addNode(std::size_t p, const Index3& c, double distance) {
        pad.push_back(p);
        ijk.push_back(c);
        dist.push_back(distance);
        pos.push_back({double(c.i), double(c.j), double(c.k)});
        adj.emplace_back();
        alive.push_back(1);
        return size() - 1;
    }
    bool hasEdge(int a, int b) const {
        const auto& l = adj[std::size_t(a)];
        return std::binary_search(l.begin(), l.end(), b);
    }
    void addEdge(int a, int b) {
        auto ins = [](std::vector<int>& l, int x) {
            const auto it = std::lower_bound(l.begin(), l.end(), x);
            if (it == l.end() || *it != x) l.insert(it, x);
        };
        ins(adj[std::size_t(a)], b);
        ins(adj[std::size_t(b)], a);
    }
    void removeEdge(int a, int b) {
        auto del = [](std::vector<int>& l, int x) {
            const auto it = std::lower_bound(l.begin(), l.end(), x);
            if (it != l.end() && *it == x) l.erase(it);
        };
        del(adj[std::size_t(a)], b);
        del(adj[std::size_t(b)], a);
    }
    void removeNode(int u) {
        const std::vector<int> nb = adj[std::size_t(u)];
        for (const int w : nb) removeEdge(u, w);
        alive[std::size_t(u)] = 0;
    }
    int squaredLength(int a, int b) const {
        const Index3& p = ijk[std::size_t(a)];
        const Index3& q = ijk[std::size_t(b)];
        const int dx = p.i - q.i, dy = p.j - q.j, dz = p.k - q.k;
        return dx * dx + dy * dy + dz * dz;
    }
    double length(int a, int b) const { return std::sqrt(double(squaredLength(a, b))); }
    /// Wall distance in voxels: distance to the nearest background centre minus half a voxel.
    double radius(int u) const { return std::max(0.5, dist[std::size_t(u)] - 0.5); }
};

/// Nodes for the skeleton voxels, edges for 26-adjacency.
WorkGraph buildVoxelGraph(const Padded& skel, const std::vector<float>& dist2) {
    WorkGraph g;
    g.dist2 = &dist2;
    for (std::size_t n = 0; n < skel.v.size(); ++n)
        if (skel.v[n] != 0) g.addNode(n, skel.innerCoord(n), std::sqrt(double(dist2[n])));
    const NeighbourOffsets o = neighbourOffsets(skel);
    for (int u = 0; u < g.size(); ++u) {
        for (int c = kCentre + 1; c < 27; ++c) {  // forward half: positive offsets
            const std::size_t m = std::size_t(std::ptrdiff_t(g.pad[std::size_t(u)]) + o.off[c]);
            if (skel.v[m] == 0) continue;
            const int w = int(std::lower_bound(g.pad.begin(), g.pad.end(), m) - g.pad.begin());
            g.adj[std::size_t(u)].push_back(w);
            g.adj[std::size_t(w)].push_back(u);
        }
    }
    for (auto& l : g.adj) std::sort(l.begin(), l.end());
    return g;
}

/// Step 3a: the edges that stay. A spanning forest of shortest edges first (Kruskal; ties by node
/// ids), plus, of the other edges (shortest first), those whose cycle is a loop of the voxel set:
/// independent, over GF(2), of the cycles already kept and of the triangles of the 26-adjacency
/// graph. (The triangles fill the clique complex of 26-adjacency, which by the nerve theorem has
/// the topology of the union of the closed voxel cubes, i.e. (26, 6) digital topology.) So the
/// graph keeps the connectivity, has exactly one independent cycle per tunnel of the skeleton
/// voxels, and a staircase corner or a junction blob reads as a chain or a tree, never a triangle
/// or a square.
void keepTreeAndLoops(WorkGraph& g) {
    struct E {
        int len2, a, b;
    };
    std::vector<E> edges;
    for (int a = 0; a < g.size(); ++a)
        for (const int b : g.adj[std::size_t(a)])
            if (a < b) edges.push_back({g.squaredLength(a, b), a, b});
    std::sort(edges.begin(), edges.end(), [](const E& x, const E& y) {
        if (x.len2 != y.len2) return x.len2 < y.len2;
        if (x.a != y.a) return x.a < y.a;
        return x.b < y.b;
    });
    // Spanning forest; the other edges get a column each, in order of preference.
    std::vector<int> parent(std::size_t(g.size()));
    for (int u = 0; u < g.size(); ++u) parent[std::size_t(u)] = u;
    auto find = [&](int u) {
        while (parent[std::size_t(u)] != u) {
            parent[std::size_t(u)] = parent[std::size_t(parent[std::size_t(u)])];
            u = parent[std::size_t(u)];
        }
        return u;
    };
    std::vector<E> extra;
    for (const E& e : edges) {
        const int ra = find(e.a), rb = find(e.b);
        if (ra != rb)
            parent[std::size_t(ra)] = rb;
        else
            extra.push_back(e);
    }
    if (extra.empty()) return;
    const std::size_t columns = extra.size();
    auto column = [&](int a, int b) -> int {  // column of a non-tree edge, −1 for a tree edge
        if (a > b) std::swap(a, b);
        const E key{g.squaredLength(a, b), a, b};
        const auto it = std::lower_bound(extra.begin(), extra.end(), key, [](const E& x, const E& y) {
            if (x.len2 != y.len2) return x.len2 < y.len2;
            if (x.a != y.a) return x.a < y.a;
            return x.b < y.b;
        });
        return it != extra.end() && it->a == a && it->b == b ? int(it - extra.begin()) : -1;
    };
    // GF(2) elimination on sparse vectors (sorted column lists, pivot = largest column); a cycle
    // is written in the basis of the fundamental cycles, i.e. by its non-tree edges.
    std::vector<std::vector<int>> basis(columns);
    std::vector<int> sum;
    auto insert = [&](std::vector<int> v) {
        while (!v.empty()) {
            const int pivot = v.back();
            std::vector<int>& b = basis[std::size_t(pivot)];
            if (b.empty()) {
                b = std::move(v);
                return true;
            }
            sum.clear();
            std::set_symmetric_difference(v.begin(), v.end(), b.begin(), b.end(), std::back_inserter(sum));
            v.swap(sum);
        }
        return false;
    };
    std::vector<int> v;
    for (int a = 0; a < g.size(); ++a)
        for (const int b : g.adj[std::size_t(a)]) {
            if (b <= a) continue;
            for (const int c : g.adj[std::size_t(b)]) {
                if (c <= b || !g.hasEdge(a, c)) continue;
                v.clear();
                for (const int col : {column(a, b), column(b, c), column(a, c)})
                    if (col >= 0) v.push_back(col);
                std::sort(v.begin(), v.end());
                insert(v);
            }
        }
    for (std::size_t col = 0; col < columns; ++col) {
        v.assign(1, int(col));
        if (!insert(v)) g.removeEdge(extra[col].a, extra[col].b);
    }
}

/// Step 3b: each cluster of adjacent degree-≥3 nodes becomes one node — unless that would erase a
/// cycle (a loop of the cave through the junction); such a cluster is left as it is.
void collapseJunctionClusters(WorkGraph& g) {
    const int n = g.size();
    std::vector<int> cluster(std::size_t(n), -1);
    std::vector<int> rep;  // per cluster: the node that stays
    std::vector<int> members, stack;
    for (int s = 0; s < n; ++s) {
        if (!g.alive[std::size_t(s)] || g.degree(s) < 3 || cluster[std::size_t(s)] >= 0) continue;
        const int id = int(rep.size());
        members.clear();
        stack.assign(1, s);
        cluster[std::size_t(s)] = id;
        while (!stack.empty()) {
            const int u = stack.back();
            stack.pop_back();
            members.push_back(u);
            for (const int w : g.adj[std::size_t(u)])
                if (g.degree(w) >= 3 && cluster[std::size_t(w)] < 0) {
                    cluster[std::size_t(w)] = id;
                    stack.push_back(w);
                }
        }
        std::sort(members.begin(), members.end());
        // Collapsing must not lose a cycle (every cycle left is a loop of the cave): count the
        // cluster's inner edges and the edges that would merge (a neighbour joined to two members).
        std::vector<int> outer;
        int inner = 0;
        for (const int u : members)
            for (const int w : g.adj[std::size_t(u)]) {
                if (cluster[std::size_t(w)] == id)
                    ++inner;
                else
                    outer.push_back(w);
            }
        inner /= 2;
        std::sort(outer.begin(), outer.end());
        const std::size_t distinctOuter = std::size_t(std::unique(outer.begin(), outer.end()) - outer.begin());
        const std::size_t lost = std::size_t(inner) + (outer.size() - distinctOuter);
        if (lost != members.size() - 1) {
            rep.push_back(-1);
            continue;
        }
        double cx = 0, cy = 0, cz = 0;
        for (const int u : members) {
            cx += g.ijk[std::size_t(u)].i;
            cy += g.ijk[std::size_t(u)].j;
            cz += g.ijk[std::size_t(u)].k;
        }
        const double inv = 1.0 / double(members.size());
        cx *= inv;
        cy *= inv;
        cz *= inv;
        // Farthest from the wall, then nearest the centroid, then the lowest id (members ascend).
        int best = -1;
        double bestDist = 0, bestCentroid = 0;
        for (const int u : members) {
            const Index3& c = g.ijk[std::size_t(u)];
            const double dc = (c.i - cx) * (c.i - cx) + (c.j - cy) * (c.j - cy) + (c.k - cz) * (c.k - cz);
            const double du = g.dist[std::size_t(u)];
            if (best < 0 || du > bestDist || (du == bestDist && dc < bestCentroid)) {
                best = u;
                bestDist = du;
                bestCentroid = dc;
            }
        }
        rep.push_back(best);
    }
    if (rep.empty()) return;
    auto mapped = [&](int u) {
        const int c = cluster[std::size_t(u)];
        return c >= 0 && rep[std::size_t(c)] >= 0 ? rep[std::size_t(c)] : u;
    };
    std::vector<std::pair<int, int>> edges;
    for (int a = 0; a < n; ++a)
        for (const int b : g.adj[std::size_t(a)]) {
            if (a >= b) continue;
            const int ma = mapped(a), mb = mapped(b);
            if (ma != mb) edges.emplace_back(std::min(ma, mb), std::max(ma, mb));
        }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    for (auto& l : g.adj) l.clear();
    for (int u = 0; u < n; ++u)
        if (mapped(u) != u) g.alive[std::size_t(u)] = 0;
    for (const auto& e : edges) {
        g.adj[std::size_t(e.first)].push_back(e.second);
        g.adj[std::size_t(e.second)].push_back(e.first);
    }
    for (auto& l : g.adj) std::sort(l.begin(), l.end());
}

/// Step 4: spur pruning, in rounds until stable.
void pruneSpurs(WorkGraph& g, const SkeletonOptions& opt) {
    struct Spur {
        int junction = -1;
        double length = 0;
        int end = -1;
        std::vector<int> path;  // end … last node before the junction
    };
    std::vector<Spur> spurs;
    for (bool changed = true; changed;) {
        changed = false;
        spurs.clear();
        for (int e = 0; e < g.size(); ++e) {
            if (!g.alive[std::size_t(e)] || g.degree(e) != 1) continue;
            Spur s;
            s.end = e;
            s.path.push_back(e);
            int prev = e, cur = g.adj[std::size_t(e)][0];
            s.length = g.length(prev, cur);
            while (g.degree(cur) == 2) {
                const auto& l = g.adj[std::size_t(cur)];
                const int next = l[0] == prev ? l[1] : l[0];
                s.path.push_back(cur);
                s.length += g.length(cur, next);
                prev = cur;
                cur = next;
            }
            if (g.degree(cur) < 3) continue;  // a plain chain: the component's only branch
            s.junction = cur;
            spurs.push_back(std::move(s));
        }
        std::sort(spurs.begin(), spurs.end(), [](const Spur& a, const Spur& b) {
            if (a.junction != b.junction) return a.junction < b.junction;
            if (a.length != b.length) return a.length < b.length;
            return a.end < b.end;
        });
        for (std::size_t first = 0; first < spurs.size();) {
            std::size_t last = first;
            while (last < spurs.size() && spurs[last].junction == spurs[first].junction) ++last;
            const int j = spurs[first].junction;
            const double threshold = std::max(opt.pruneFactor * g.radius(j), opt.minSpurLength);
            std::size_t shortCount = 0;
            while (first + shortCount < last && spurs[first + shortCount].length < threshold) ++shortCount;
            const std::size_t degree = std::size_t(g.degree(j));
            std::size_t remove = shortCount;
            if (shortCount >= degree) remove = degree - 2;  // a star: the two longest stay as one branch
            for (std::size_t s = first; s < first + remove; ++s) {
                for (const int u : spurs[s].path) g.removeNode(u);
                changed = true;
            }
            first = last;
        }
    }
}

/// The passage direction at end `e`: principal axis of the last few chain nodes (at most
/// `kEndNodes`, not past a junction), pointing out of the chain. Zero if the chain has one node.
Vec3d endDirection(const WorkGraph& g, int e) {
    constexpr int kEndNodes = 8;
    std::vector<int> chain{e};
    if (g.degree(e) == 1) {
        int prev = e, cur = g.adj[std::size_t(e)][0];
        chain.push_back(cur);
        while (int(chain.size()) < kEndNodes && g.degree(cur) == 2) {
            const auto& l = g.adj[std::size_t(cur)];
            const int next = l[0] == prev ? l[1] : l[0];
            prev = cur;
            cur = next;
            chain.push_back(cur);
        }
    }
    if (chain.size() < 2) return {0, 0, 0};
    Vec3d c{0, 0, 0};
    for (const int u : chain) c = add(c, g.pos[std::size_t(u)]);
    for (double& x : c) x /= double(chain.size());
    std::array<Vec3d, 3> cov{};  // scatter matrix, row by row (symmetric)
    for (const int u : chain) {
        const Vec3d d = sub(g.pos[std::size_t(u)], c);
        for (std::size_t r = 0; r < 3; ++r) cov[r] = add(cov[r], scale(d, d[r]));
    }
    // Power iteration from the chord end → far end (deterministic; the chain is elongated).
    const Vec3d chord = sub(g.pos[std::size_t(e)], g.pos[std::size_t(chain.back())]);
    Vec3d v = chord;
    for (int it = 0; it < 64; ++it) {
        const Vec3d w{dot(cov[0], v), dot(cov[1], v), dot(cov[2], v)};
        const double n = norm(w);
        if (!(n > 0)) break;
        for (std::size_t r = 0; r < 3; ++r) v[r] = w[r] / n;
    }
    const double n = norm(v);
    if (!(n > 0)) return {0, 0, 0};
    for (double& x : v) x /= n;
    // Point away from the chain: along end − far end.
    if (dot(v, chord) < 0)
        for (double& x : v) x = -x;
    return v;
}

/// Distance (voxels) from the centre of voxel `c` along the unit direction `u` to where the ray
/// leaves the cave (enters a background voxel or leaves the grid), at most `maxDistance`. Voxel
/// traversal of Amanatides & Woo (1987); a ray through an edge or corner steps diagonally.
double exitDistance(const Padded& cave, const Index3& c, const Vec3d& u, double maxDistance) {
    int step[3];
    double tMax[3], tDelta[3];
    for (int a = 0; a < 3; ++a) {
        const double ua = u[std::size_t(a)];
        if (std::abs(ua) < 1e-12) {
            step[a] = 0;
            tMax[a] = tDelta[a] = std::numeric_limits<double>::infinity();
        } else {
            step[a] = ua > 0 ? 1 : -1;
            tDelta[a] = 1.0 / std::abs(ua);
            tMax[a] = 0.5 * tDelta[a];
        }
    }
    int p[3] = {c.i, c.j, c.k};
    for (;;) {
        const double t = std::min({tMax[0], tMax[1], tMax[2]});
        if (!(t < maxDistance)) return maxDistance;
        for (int a = 0; a < 3; ++a)
            if (tMax[a] <= t + 1e-9) {
                p[a] += step[a];
                tMax[a] += tDelta[a];
            }
        if (!cave.inner.contains(p[0], p[1], p[2]) || cave.v[cave.index(p[0], p[1], p[2])] == 0) return t;
    }
}

/// Step 5a: passage ends. Thinning bends the last voxels of a blunt passage end toward a corner
/// of its end wall; so each end chain is first cut back to its deepest node (farthest from the
/// wall) among those no farther from the end than twice their wall distance — the cap zone. Then
/// the end is
/// extended voxel by voxel along the passage direction while it stays in the cave, and the end
/// node is placed where that direction meets the end wall.
void extendEnds(WorkGraph& g, const Padded& cave) {
    std::vector<std::uint8_t> isNode(cave.v.size(), 0);
    std::vector<int> ends;
    for (int u = 0; u < g.size(); ++u) {
        if (!g.alive[std::size_t(u)]) continue;
        isNode[g.pad[std::size_t(u)]] = 1;
        if (g.degree(u) == 1) ends.push_back(u);
    }
    for (const int end : ends) {
        if (!g.alive[std::size_t(end)] || g.degree(end) != 1) continue;
        // The cap zone: the new end is the node farthest from the wall among those whose wall
        // distance reaches back to the end within a factor 2 (ties: nearest the end); never past
        // a junction or the chain's other end.
        std::vector<int> path{end};
        std::vector<double> walkedTo{0.0};
        int prev = end, cur = g.adj[std::size_t(end)][0];
        double walked = g.length(end, cur);
        std::size_t best = 0;
        double deepest = g.dist[std::size_t(end)];
        while (g.degree(cur) == 2 && walked <= 2.0 * deepest + 2.0) {
            path.push_back(cur);
            walkedTo.push_back(walked);
            const double d = g.dist[std::size_t(cur)];
            deepest = std::max(deepest, d);
            if (walked <= 2.0 * d && d > g.dist[std::size_t(path[best])]) best = path.size() - 1;
            const auto& l = g.adj[std::size_t(cur)];
            const int next = l[0] == prev ? l[1] : l[0];
            walked += g.length(cur, next);
            prev = cur;
            cur = next;
        }
        // Keep at least two nodes behind the new end to tell the passage direction.
        if (path.size() - 1 - best + 1 < 2) best = 0;
        for (std::size_t i = 0; i < best; ++i) {
            isNode[g.pad[std::size_t(path[i])]] = 0;
            g.removeNode(path[i]);
        }
        const int e = path[best];
        const double trimmed = walkedTo[best];

        const Vec3d dir = endDirection(g, e);
        const double big = std::max({std::abs(dir[0]), std::abs(dir[1]), std::abs(dir[2])});
        if (!(big > 0)) continue;
        const Index3 a = g.ijk[std::size_t(e)];
        const int maxSteps = int(std::ceil(trimmed + g.dist[std::size_t(e)])) + 1;
        int last = e;
        for (int t = 1; t <= maxSteps; ++t) {
            const Index3 p{a.i + int(std::lround(t * dir[0] / big)), a.j + int(std::lround(t * dir[1] / big)),
                           a.k + int(std::lround(t * dir[2] / big))};
            if (!cave.inner.contains(p)) break;
            const std::size_t m = cave.index(p.i, p.j, p.k);
            if (cave.v[m] == 0 || isNode[m] != 0) break;
            isNode[m] = 1;
            const int u = g.addNode(m, p, std::sqrt(double(g.dist2Of(m))));
            g.addEdge(last, u);
            last = u;
        }
        const Index3& c = g.ijk[std::size_t(last)];
        const double s = exitDistance(cave, c, dir, g.dist[std::size_t(last)]);
        g.pos[std::size_t(last)] = {c.i + s * dir[0], c.j + s * dir[1], c.k + s * dir[2]};
    }
}

/// Step 5b: Laplacian smoothing of chain nodes (voxel units, relative to the voxel centres).
std::vector<Vec3d> smoothPositions(const WorkGraph& g, const Padded& cave, const SkeletonOptions& opt) {
    const int n = g.size();
    std::vector<Vec3d> p = g.pos, next;
    std::vector<int> movable;
    for (int u = 0; u < n; ++u)
        if (g.alive[std::size_t(u)] && g.degree(u) == 2) movable.push_back(u);
    const double w = opt.smoothingWeight;
    for (int it = 0; it < opt.smoothingIterations; ++it) {
        next = p;
        for (const int u : movable) {
            const auto& l = g.adj[std::size_t(u)];
            const auto& a = p[std::size_t(l[0])];
            const auto& b = p[std::size_t(l[1])];
            const auto& x = p[std::size_t(u)];
            Vec3d y;
            for (int d = 0; d < 3; ++d)
                y[std::size_t(d)] =
                    x[std::size_t(d)] + w * (0.5 * (a[std::size_t(d)] + b[std::size_t(d)]) - x[std::size_t(d)]);
            // Stay within the node's radius of its voxel centre (inside the passage).
            const Index3& c = g.ijk[std::size_t(u)];
            const double ox = y[0] - c.i, oy = y[1] - c.j, oz = y[2] - c.k;
            const double off = std::sqrt(ox * ox + oy * oy + oz * oz);
            const double limit = g.radius(u);
            if (off > limit) {
                const double s = limit / off;
                y = {c.i + ox * s, c.j + oy * s, c.k + oz * s};
            }
            // ... and inside a cave voxel (a ball of that radius may graze a wall corner).
            const Index3 q{int(std::floor(y[0] + 0.5)), int(std::floor(y[1] + 0.5)), int(std::floor(y[2] + 0.5))};
            if (cave.inner.contains(q) && cave.v[cave.index(q.i, q.j, q.k)] != 0) next[std::size_t(u)] = y;
        }
        std::swap(p, next);
    }
    return p;
}

void validate(const Grid3<std::uint8_t>& mask) {
    const Dims& d = mask.dims;
    CAVESIM_CHECK(d.nx >= 0 && d.ny >= 0 && d.nz >= 0, "skeleton: negative grid extent " + std::to_string(d.nx) + "×" +
                                                           std::to_string(d.ny) + "×" + std::to_string(d.nz));
    CAVESIM_CHECK(mask.data.size() == d.count(), "skeleton: the mask holds " + std::to_string(mask.data.size()) +
                                                     " values for a " + std::to_string(d.nx) + "×" +
                                                     std::to_string(d.ny) + "×" + std::to_string(d.nz) + " grid (" +
                                                     std::to_string(d.count()) + " expected)");
}

}  // namespace

void envelope1d(const double* f, int n, double* out, std::vector<int>& vtx, std::vector<double>& z) {
    vtx.resize(std::size_t(n));
    z.resize(std::size_t(n) + 1);
    int k = 0;
    vtx[0] = 0;
    z[0] = -std::numeric_limits<double>::infinity();
    z[1] = std::numeric_limits<double>::infinity();
    auto meet = [&](int q, int p) {  // abscissa where the parabolas rooted at q and p intersect
        return ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * (q - p));
    };
    for (int q = 1; q < n; ++q) {
        double s = meet(q, vtx[std::size_t(k)]);
        while (s <= z[std::size_t(k)]) {  // z[0] = −∞ stops this at k = 0
            --k;
            s = meet(q, vtx[std::size_t(k)]);
        }
        ++k;
        vtx[std::size_t(k)] = q;
        z[std::size_t(k)] = s;
        z[std::size_t(k) + 1] = std::numeric_limits<double>::infinity();
    }
    k = 0;
    for (int q = 0; q < n; ++q) {
        while (z[std::size_t(k) + 1] < q) ++k;
        const int p = vtx[std::size_t(k)];
        out[q] = double(q - p) * double(q - p) + f[p];
    }
}

Grid3<std::uint8_t> thinToCurveSkeleton(const Grid3<std::uint8_t>& mask, bool fillCavities) {
    validate(mask);
    Grid3<std::uint8_t> out(mask.dims, 0);
    Padded g = padMask(mask);
    if (g.inner.count() == 0) return out;
    if (fillCavities) fillEnclosedCavities(g);
    thin(g);
    for (std::size_t n = 0; n < g.v.size(); ++n)
        if (g.v[n] != 0) {
            const Index3 c = g.innerCoord(n);
            out.at(c.i + g.origin.i, c.j + g.origin.j, c.k + g.origin.k) = 1;
        }
    return out;
}

Skeleton skeletonize(const Grid3<std::uint8_t>& mask, double voxelSize, const SkeletonOptions& options) {
    validate(mask);
    CAVESIM_CHECK(std::isfinite(voxelSize) && voxelSize > 0,
                  "skeleton: voxel size must be a finite positive length in metres, got " + std::to_string(voxelSize));
    CAVESIM_CHECK(std::isfinite(options.pruneFactor) && options.pruneFactor >= 0,
                  "skeleton: pruneFactor must be finite and ≥ 0, got " + std::to_string(options.pruneFactor));
    CAVESIM_CHECK(
        std::isfinite(options.minSpurLength) && options.minSpurLength >= 0,
        "skeleton: minSpurLength must be finite and ≥ 0 voxels, got " + std::to_string(options.minSpurLength));
    CAVESIM_CHECK(options.smoothingIterations >= 0,
                  "skeleton: smoothingIterations must be ≥ 0, got " + std::to_string(options.smoothingIterations));
    CAVESIM_CHECK(options.smoothingWeight > 0 && options.smoothingWeight <= 1,
                  "skeleton: smoothingWeight must lie in (0, 1], got " + std::to_string(options.smoothingWeight));

    Skeleton result;
    Padded cave = padMask(mask);
    if (cave.inner.count() == 0) return result;
    if (options.fillCavities) fillEnclosedCavities(cave);
    Padded skel = cave;
    const std::vector<float> dist2 = squaredDistanceToBackground(cave, cave.sectionNormal);
    thin(skel);

    WorkGraph g = buildVoxelGraph(skel, dist2);
    if (g.size() == 0) return result;
    keepTreeAndLoops(g);
    collapseJunctionClusters(g);
    pruneSpurs(g, options);
    if (options.extendEnds) extendEnds(g, cave);
    const std::vector<Vec3d> pos = smoothPositions(g, cave, options);

    // Output: alive nodes by voxel index (the padded order is the inner order).
    std::vector<int> order;
    for (int u = 0; u < g.size(); ++u)
        if (g.alive[std::size_t(u)]) order.push_back(u);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return g.pad[std::size_t(a)] < g.pad[std::size_t(b)]; });
    std::vector<int> id(std::size_t(g.size()), -1);
    result.nodes.reserve(order.size());
    for (const int u : order) {
        id[std::size_t(u)] = int(result.nodes.size());
        SkeletonNode node;
        const auto& p = pos[std::size_t(u)];
        const Index3& o = cave.origin;
        node.position = {(p[0] + o.i + 0.5) * voxelSize, (p[1] + o.j + 0.5) * voxelSize,
                         (p[2] + o.k + 0.5) * voxelSize};
        node.radius = g.radius(u) * voxelSize;
        const Index3& c = g.ijk[std::size_t(u)];
        node.voxel = mask.dims.index(c.i + o.i, c.j + o.j, c.k + o.k);
        result.nodes.push_back(node);
    }
    for (const int u : order)
        for (const int w : g.adj[std::size_t(u)]) {
            const int a = id[std::size_t(u)], b = id[std::size_t(w)];
            if (a < b) result.edges.push_back({a, b});
        }
    std::sort(result.edges.begin(), result.edges.end());
    return result;
}

}  // namespace cavesim::morpho

/// @file grid.h
/// @brief Dense voxel grids in index space: the layout every hot loop of cavesim uses.
///
/// A grid has `nx × ny × nz` voxels, z up, stored x-fastest (`index = i + nx·(j + ny·k)`).
/// Positions here are integer voxel indices; world positions in metres are
/// `worldFromIndex(ijk) = (ijk + 0.5) · voxelSize` (voxel centres), see `worldFromIndex`.
/// Any extent may be 1 (`ny = 1` is a 2D vertical section); nothing here assumes otherwise.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace cavesim {

/// Integer voxel coordinate (i, j, k) = (x, y, z), z up.
struct Index3 {
    int i = 0, j = 0, k = 0;
    friend bool operator==(const Index3& a, const Index3& b) { return a.i == b.i && a.j == b.j && a.k == b.k; }
    friend bool operator!=(const Index3& a, const Index3& b) { return !(a == b); }
};

/// Grid extents in voxels.
struct Dims {
    int nx = 0, ny = 0, nz = 0;

    std::size_t count() const { return std::size_t(nx) * std::size_t(ny) * std::size_t(nz); }
    bool contains(int i, int j, int k) const {
        return i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz;
    }
    bool contains(const Index3& p) const { return contains(p.i, p.j, p.k); }
    /// Linear index of voxel (i, j, k); the voxel must be inside.
    std::size_t index(int i, int j, int k) const {
        return std::size_t(i) + std::size_t(nx) * (std::size_t(j) + std::size_t(ny) * std::size_t(k));
    }
    std::size_t index(const Index3& p) const { return index(p.i, p.j, p.k); }
    /// Voxel coordinate of a linear index.
    Index3 coord(std::size_t n) const {
        const int i = int(n % std::size_t(nx));
        const std::size_t r = n / std::size_t(nx);
        return {i, int(r % std::size_t(ny)), int(r / std::size_t(ny))};
    }
    friend bool operator==(const Dims& a, const Dims& b) { return a.nx == b.nx && a.ny == b.ny && a.nz == b.nz; }
};

/// A dense scalar field over a `Dims` box.
template <typename T>
struct Grid3 {
    Dims dims;
    std::vector<T> data;

    Grid3() = default;
    explicit Grid3(const Dims& d, T fill = T{}) : dims(d), data(d.count(), fill) {}

    std::size_t size() const { return data.size(); }
    T& operator[](std::size_t n) { return data[n]; }
    const T& operator[](std::size_t n) const { return data[n]; }
    T& at(int i, int j, int k) { return data[dims.index(i, j, k)]; }
    const T& at(int i, int j, int k) const { return data[dims.index(i, j, k)]; }
    T& at(const Index3& p) { return data[dims.index(p)]; }
    const T& at(const Index3& p) const { return data[dims.index(p)]; }
};

/// One neighbour offset with its Euclidean length in voxel units.
struct NeighbourOffset {
    int di, dj, dk;
    double length;
};

/// The 6 face neighbours.
inline const std::array<NeighbourOffset, 6>& faceNeighbours() {
    static const std::array<NeighbourOffset, 6> n{{{-1, 0, 0, 1.0}, {1, 0, 0, 1.0}, {0, -1, 0, 1.0},
                                                  {0, 1, 0, 1.0},  {0, 0, -1, 1.0}, {0, 0, 1, 1.0}}};
    return n;
}

/// The 26 neighbours (faces, edges, corners), ordered by (dk, dj, di) lexicographically.
inline const std::array<NeighbourOffset, 26>& allNeighbours() {
    static const std::array<NeighbourOffset, 26> n = [] {
        std::array<NeighbourOffset, 26> r{};
        int c = 0;
        for (int dk = -1; dk <= 1; ++dk)
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                    if (di == 0 && dj == 0 && dk == 0) continue;
                    const int s = di * di + dj * dj + dk * dk;
                    r[c++] = {di, dj, dk, s == 1 ? 1.0 : (s == 2 ? 1.4142135623730951 : 1.7320508075688772)};
                }
        return r;
    }();
    return n;
}

}  // namespace cavesim

/// @file surface_mesh.h
/// @brief A triangle surface as plain arrays with vertex normals: what src/mesh produces and the
/// export writers of src/formats consume (no OpenVDB or OpenMesh type involved).
///
/// Space: world space, metres, z up (the simulation's axes: voxel (i, j, k) is centred at
/// ((i, j, k) + 0.5) · voxelSize). Single precision, as the mesh files store it.
/// (`mesh::TriangleMesh` is src/mesh's working mesh: double precision, no normals.)
#pragma once

#include <array>
#include <cmath>
#include <vector>

namespace cavesim {

/// A closed cave surface: triangles wound counter-clockwise seen from outside the cave (from the
/// rock), so the right-hand face normal points out of the cave; `normals` follow the same side.
struct SurfaceMesh {
    std::vector<std::array<float, 3>> vertices;  ///< metres, world space, z up
    std::vector<std::array<float, 3>> normals;   ///< unit vertex normals, one per vertex, out of the cave
    std::vector<std::array<int, 3>> triangles;   ///< indices into `vertices`
};

/// The unit normal of the plane through a, b, c (right-hand rule), or (0, 0, 0) for a degenerate
/// triangle. Doubles inside, so round-off does not depend on the vertex order's magnitude.
inline std::array<float, 3> faceNormal(const std::array<float, 3>& a, const std::array<float, 3>& b,
                                       const std::array<float, 3>& c) {
    const double u[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
    const double v[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    const double len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    if (!(len2 > 0.0)) return {0.f, 0.f, 0.f};
    const double inv = 1.0 / std::sqrt(len2);
    return {float(n[0] * inv), float(n[1] * inv), float(n[2] * inv)};
}

}  // namespace cavesim

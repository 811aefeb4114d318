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

#include "core/vec3.h"

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
    const auto wide = [](const std::array<float, 3>& p) { return Vec3d{p[0], p[1], p[2]}; };
    const Vec3d n = cross(sub(wide(b), wide(a)), sub(wide(c), wide(a)));
    const double len2 = dot(n, n);
    if (!(len2 > 0.0)) return {0.f, 0.f, 0.f};
    const double inv = 1.0 / std::sqrt(len2);
    return {float(n[0] * inv), float(n[1] * inv), float(n[2] * inv)};
}

}  // namespace cavesim

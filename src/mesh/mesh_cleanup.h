/// @file mesh_cleanup.h
/// @brief Internal to src/mesh: OpenMesh clean-up of a triangle mesh (no OpenMesh types here).
#pragma once

#include <string>
#include <vector>

#include "mesh/cave_mesh.h"

namespace cavesim::mesh::detail {

/// Removes what `volumeToMesh` can leave behind that viewers and measures dislike: edges
/// shorter than `minEdge` metres are collapsed (when OpenMesh finds the collapse topologically
/// safe), triangles with a repeated vertex are dropped, and unused vertices are removed.
/// Triangles OpenMesh refuses as non-manifold are kept as they are (with their own copies of
/// the offending vertices), so nothing of the surface is lost.
TriangleMesh cleanMesh(const TriangleMesh& mesh, double minEdge);

/// writeMeshFile to each of `paths`, converting to OpenMesh (with normals) once.
void writeMeshFiles(const TriangleMesh& mesh, const std::vector<std::string>& paths);

}  // namespace cavesim::mesh::detail

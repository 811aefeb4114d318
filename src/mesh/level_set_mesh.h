/// @file level_set_mesh.h
/// @brief Internal to src/mesh and src/speleo: the iso-surface of an OpenVDB level set as a
/// `TriangleMesh`. Includes OpenVDB: include it only from .cpp files of those two folders.
#pragma once

#include <openvdb/openvdb.h>

#include "mesh/cave_mesh.h"

namespace cavesim::mesh::detail {

/// `openvdb::tools::volumeToMesh` of `grid` at `iso` (metres) with `adaptivity` in [0, 1],
/// disoriented triangles relaxed; faces turned outward, out of the negative side (OpenVDB winds
/// them inward), quads split along their shorter diagonal. Vertices in the grid's world space.
/// Defined in cave_mesh.cpp.
TriangleMesh meshLevelSet(const openvdb::FloatGrid& grid, double iso, double adaptivity);

}  // namespace cavesim::mesh::detail

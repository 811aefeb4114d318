/// @file cave_level_set.h
/// @brief Internal to src/mesh: the cave's narrow-band level set, shared by the mesh and the
/// ray-traced pictures. Includes OpenVDB: include it only from .cpp files of src/mesh.
#pragma once

#include <openvdb/openvdb.h>

#include <cstdint>
#include <string>

#include "core/grid.h"
#include "mesh/cave_mesh.h"

namespace cavesim::mesh::detail {

/// The cave surface as a level set.
struct CaveLevelSet {
    /// Narrow-band signed distance in metres (negative in the cave), GRID_LEVEL_SET class, voxel
    /// size voxelSize/subdivision, index m centred at (m + 0.5)·voxelSize/subdivision.
    /// nullptr when the mask has no cave voxel.
    openvdb::FloatGrid::Ptr grid;
    /// The iso value to mesh and ray-trace at (metres, >= 0): the volume-preserving offset.
    double isoValue = 0.0;
    /// Largest iso value allowed: the offset limit of the options, and a level-set voxel short of
    /// the narrow band's edge.
    double maxIsoValue = 0.0;
    /// Volume of the cave voxels, m³ (the target of the offset).
    double voxelVolume = 0.0;
    /// Wall time of the steps, seconds (benchmarks).
    double secondsCubes = 0, secondsCapsules = 0, secondsSmoothing = 0, secondsVolume = 0;
};

/// The level set and the mesh of the cave, built together.
struct CaveSurface {
    CaveLevelSet levelSet;
    TriangleMesh mesh;  ///< outward, cleaned; empty when the mask is
};

/// buildCaveLevelSet, then the mesh at the level set's iso value, whose volume refines the
/// volume-preserving offset (the mesh of a thin tube loses volume to its polygons): the mesh is
/// made again at the refined iso value, which the returned level set carries (so pictures show
/// the mesh's surface). Without `wantMesh` only the iso value is refined and the mesh is left
/// empty (pictures). Defined in cave_mesh.cpp.
CaveSurface buildCaveSurface(const Grid3<std::uint8_t>& mask, double voxelSize, const MeshOptions& options,
                             bool wantMesh = true);

/// Writes dir/cave.obj and dir/cave.ply (and dir/cave_voxels.obj for style "voxel") of a built
/// mesh; returns its measures (seconds left 0). Nothing is written for an empty mesh.
MeshStats writeMeshOutputs(const TriangleMesh& mesh, const Grid3<std::uint8_t>& mask, double voxelSize,
                           const std::string& dir, const MeshOptions& options);

/// Validates `options` (and the voxel size).
/// @throw InternalError naming the field and its range
void validateMeshOptions(const MeshOptions& options, double voxelSize);

/// Builds the smoothed level set of the cave voxels (see cave_mesh.h for the method).
/// @throw InternalError on bad options
CaveLevelSet buildCaveLevelSet(const Grid3<std::uint8_t>& mask, double voxelSize, const MeshOptions& options);

}  // namespace cavesim::mesh::detail

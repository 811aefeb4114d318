/// @file vdb_io.h
/// @brief Writing dense cavesim grids as named OpenVDB grids (state.vdb, stage1.vdb).
///
/// OpenVDB headers stay inside vdb_io.cpp; callers see only cavesim types.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/grid.h"
#include "mesh/cave_mesh.h"
#include "sim/cave.h"
#include "sim/domain.h"

namespace cavesim::mesh {

/// One grid to write: exactly one of the pointers is set. Zero (background) voxels are inactive.
struct NamedGrid {
    std::string name;
    const Grid3<float>* floats = nullptr;
    const Grid3<std::int32_t>* ints = nullptr;
    std::string description;  ///< stored as grid metadata "description"
};

/// Writes the grids to one .vdb file, world transform = uniform scale `voxelSize` (metres),
/// voxel (i,j,k) centred at `origin` + ((i, j, k) + 0.5)·voxelSize (`origin`: the world position of
/// the block's low corner, `Domain::origin`; 0 without a site).
/// @param background value treated as background for float grids (not stored)
/// @throw RuntimeError when the file cannot be written
void writeVdb(const std::string& path, const std::vector<NamedGrid>& grids, double voxelSize,
              const std::array<double, 3>& origin = {0, 0, 0});

/// Reads one named float grid back into a dense grid of `dims` (tests, `cavesim report`).
/// @throw RuntimeError when the file or grid is missing
Grid3<float> readVdbFloat(const std::string& path, const std::string& name, const Dims& dims);
Grid3<std::int32_t> readVdbInt(const std::string& path, const std::string& name, const Dims& dims);

/// Writes the export `.vdb` (cave.vdb) that every OpenVDB reader takes, pyopenvdb included
/// (whose `readAll` refuses the Int32 grids of state.vdb), and that gives Houdini and Blender a
/// cave surface:
///  - float grids `porosity`, `porosity0`, `pressure`, `flow`, `water` as in state.vdb (zero =
///    background, inactive), and `flags` and `zone` as float copies of the integer grids (values
///    exact: flags 0–127, zone −1 … number of sources − 1); class unknown, world transform as
///    state.vdb (uniform scale `voxelSize`, voxel (i, j, k) centred at ((i, j, k) + 0.5)·voxelSize);
///  - `cave`: the cave surface (the surface of cave.obj) as a narrow-band signed distance in
///    metres, negative inside the cave, class GRID_LEVEL_SET, background = half width × its voxel
///    size, voxels voxelSize / `options.subdivision` on a side, `options.halfWidth` voxels on
///    each side of the surface. Absent when the cave is empty.
/// Every grid carries string metadata "description" and "unit". Written under a temporary name
/// and renamed; the file's UUID is derived from its contents (same domain, same bytes).
/// state.vdb is not touched.
/// @param path     file to write (any name; `cave.vdb` by convention)
/// @param domain   the simulation state (index space grids, metres)
/// @param cave     the run's cave (`makeCave`), on the domain's grid: the `cave` grid is its surface
/// @param options  the mesh options of the run (the level set is the one the mesh is made from)
/// @throw InputError on bad options; RuntimeError when the file cannot be written
void writeExportVdb(const std::string& path, const Domain& domain, const Cave& cave, const MeshOptions& options = {});

}  // namespace cavesim::mesh

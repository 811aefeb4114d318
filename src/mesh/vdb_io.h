/// @file vdb_io.h
/// @brief Writing dense cavesim grids as named OpenVDB grids (state.vdb, stage1.vdb).
///
/// OpenVDB headers stay inside vdb_io.cpp; callers see only cavesim types.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/grid.h"

namespace cavesim::mesh {

/// One grid to write: exactly one of the pointers is set. Zero (background) voxels are inactive.
struct NamedGrid {
    std::string name;
    const Grid3<float>* floats = nullptr;
    const Grid3<std::int32_t>* ints = nullptr;
    std::string description;  ///< stored as grid metadata "description"
};

/// Writes the grids to one .vdb file, world transform = uniform scale `voxelSize` (metres),
/// voxel (i,j,k) centred at ((i, j, k) + 0.5)·voxelSize.
/// @param background value treated as background for float grids (not stored)
/// @throw RuntimeError when the file cannot be written
void writeVdb(const std::string& path, const std::vector<NamedGrid>& grids, double voxelSize);

/// Reads one named float grid back into a dense grid of `dims` (tests, `cavesim report`).
/// @throw RuntimeError when the file or grid is missing
Grid3<float> readVdbFloat(const std::string& path, const std::string& name, const Dims& dims);
Grid3<std::int32_t> readVdbInt(const std::string& path, const std::string& name, const Dims& dims);

}  // namespace cavesim::mesh

/// @file vtk_formats.h
/// @brief VTK XML files for ParaView and VTK's Python module: the simulation grids (state.vti)
/// and the centreline (skeleton.vtp).
///
/// Written by hand after "VTK File Formats" (VTK User's Guide, XML formats, version 1.0 with
/// 64-bit block headers), little-endian. Space: metres, world space, z up (x east, y north).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "morpho/graph_metrics.h"
#include "morpho/skeleton_graph.h"
#include "sim/cave.h"
#include "sim/domain.h"

namespace cavesim::formats {

/// `state.vti`: an ImageData with one cell per voxel: WholeExtent 0 nx 0 ny 0 nz (points),
/// Origin `domain.origin` (0 0 0 without a `[site]`), Spacing h h h (metres), so cell (i, j, k) is the voxel cube
/// [i, i+1]·h × [j, j+1]·h × [k, k+1]·h, centred where state.vdb and the mesh put it. CellData
/// arrays, raw appended binary: `porosity`, `porosity0`, `pressure`, `flow`, `water` (Float32),
/// `flags` (UInt8, bits as state.vdb), `zone` (Int32), and with a cave `cave` (UInt8, 1 = cave
/// voxel: `cave->mask`). A grid of the domain that is not filled (size ≠ voxel count) is left out.
/// FieldData: `units` (String, one "name: unit" per array), `length_unit` ("m"), `axes`
/// (String) and `voxel_size_m` (Float64).
/// @throw InputError on a domain without voxels; RuntimeError naming `path` when it cannot be written
/// @param cave  the run's cave (`makeCave`) on the domain's grid; may be null (no `cave` array)
void writeStateVti(const Domain& domain, const std::string& path, const Cave* cave = nullptr);

/// `skeleton.vtp`: a PolyData of the centreline. Points: the skeleton nodes (metres, world space,
/// Float64). Lines: one polyline per passage (`findPassages`, a loop passage closes on its first
/// point). PointData: `radius` (m, Float64), `passage_id` (Int32, the first passage through the
/// node; −1 for an isolated node), `degree` (Int32) and, with a domain, `flow` and `pressure`
/// (Float32, the grid values at the node's voxel; zero where stage 2 did not run). CellData:
/// `passage_id` (Int32) and `length_m` (Float64). FieldData `units` as in state.vti. ASCII.
/// @param domain  may be null (no flow, no pressure)
/// @throw InputError on an invalid skeleton; RuntimeError naming `path` when it cannot be written
/// One float grid as an ImageData of cells: WholeExtent 0 nx 0 ny 0 nz, Origin `origin` (the
/// world position in metres of the block's corner, voxel (0, 0, 0)'s low corner), Spacing h h h,
/// one CellData array `name` (Float32, raw appended), FieldData `units` ("name: unit"),
/// `length_unit`, `axes`, `voxel_size_m` and `world_origin_m` (Float64 ×3). Used for the
/// ensemble's probability.vti.
/// @throw RuntimeError naming `path` when the grid is empty or the file cannot be written
void writeScalarVti(const Grid3<float>& grid, const std::string& name, const std::string& unit, double voxelSize,
                    const std::array<double, 3>& origin, const std::string& path);

void writeSkeletonVtp(const morpho::Skeleton& skeleton, const std::string& path, const Domain* domain = nullptr);

}  // namespace cavesim::formats

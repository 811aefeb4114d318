/// @file skeleton_io.h
/// @brief Skeleton files of a run (README.md, outputs): `skeleton.json` and karstnet's
/// `skeleton_nodes.dat` / `skeleton_links.dat`.
///
/// `skeleton.json` (metres, world space; node ids 0-based):
/// ```
/// {"format": "cavesim-skeleton", "version": 1, "voxel_size_m": h, "grid": [nx, ny, nz],
///  "node_count": N, "edge_count": E,
///  "nodes": [[x, y, z], ...], "edges": [[i, j], ...], "radius": [r, ...],
///  "voxels": [[i, j, k], ...]}
/// ```
/// `radius` is the distance from the node's voxel to the nearest wall; `voxels` the index-space
/// voxel each node stands on. karstnet's pair (Collon et al. 2017, the `karstnet` Python package):
/// `skeleton_nodes.dat` holds `x y z` per line (metres), `skeleton_links.dat` holds `i j` per line
/// with 1-based node numbers. Numbers are written in the shortest form that reads back exactly.
#pragma once

#include <string>

#include "core/grid.h"
#include "morpho/skeleton_graph.h"

namespace cavesim::morpho {

/// Writes `skeleton.json`, `skeleton_nodes.dat` and `skeleton_links.dat` into the existing
/// directory `dir`, each through a temporary name in `dir` and a rename (a file appears complete
/// or not at all).
/// @param skeleton   the graph (positions and radii in metres)
/// @param dir        output directory; must exist
/// @param voxelSize  voxel edge length in metres (> 0), recorded as `voxel_size_m`
/// @param grid       the grid the skeleton was computed on (index space), recorded as `grid`; node
///                   voxels are decoded with it
/// @throw InternalError if the skeleton is malformed (edge out of range, a ≥ b, non-finite position
///        or radius, a voxel outside `grid`) or `voxelSize` is not finite and positive
/// @throw RuntimeError if `dir` is not a directory or a file cannot be written or renamed
void writeSkeletonFiles(const Skeleton& skeleton, const std::string& dir, double voxelSize, const Dims& grid);

/// What `skeleton.json` holds.
struct SkeletonFile {
    Skeleton skeleton;
    double voxelSize = 0;  ///< metres
    Dims grid;             ///< index space
};

/// Reads a `skeleton.json` written by `writeSkeletonFiles` (node voxels from `voxels` and `grid`).
/// @throw RuntimeError if the file cannot be read
/// @throw InputError if it is not valid JSON or lacks or misshapes a key (the message names it)
SkeletonFile readSkeletonJson(const std::string& path);

}  // namespace cavesim::morpho

/// @file skeleton_graph.h
/// @brief The cave's centreline as a graph: the one data structure the skeleton, the network
/// counts, the morphometric indices and the network metrics share.
///
/// Nodes sit on centreline voxels; positions are in metres, world space (voxel (i, j, k) has its
/// centre at ((i, j, k) + 0.5) · voxel size), after smoothing. A passage is a chain of degree-2
/// nodes between junctions (degree ≥ 3) and ends (degree 1); a loop of the cave is a cycle of the
/// graph.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "core/vec3.h"

namespace cavesim::morpho {

/// One centreline node.
struct SkeletonNode {
    Vec3d position{0, 0, 0};  ///< metres, world space, smoothed
    double radius = 0.0;      ///< metres: distance from the node's voxel to the nearest wall
    std::size_t voxel = 0;    ///< linear index (Dims::index) of the centreline voxel
};

/// The centreline graph. Edges are undirected, stored with `a < b`, without duplicates or self loops.
struct Skeleton {
    std::vector<SkeletonNode> nodes;
    std::vector<std::array<int, 2>> edges;
};

}  // namespace cavesim::morpho

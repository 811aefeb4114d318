/// @file passages.h
/// @brief The cave's passages as cavers and geomodellers read them: the skeleton's branches
/// (morpho::findBranches) with station names, and distances from a centreline point to the
/// passage walls measured in the cave mask (LRUD, widths, heights).
///
/// Space: positions and distances in metres, world space, z up; the mask is in index space,
/// voxel (i, j, k) the cube [i, i+1]·h × [j, j+1]·h × [k, k+1]·h. A wall is the first face of a
/// non-cave voxel, or the block's boundary.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/grid.h"
#include "morpho/graph_metrics.h"
#include "morpho/skeleton_graph.h"

namespace cavesim::formats {

/// Distance (metres) from `origin` along the unit vector `direction` to the first face of a
/// voxel where `cave == 0` or to the block's boundary (exact voxel traversal, Amanatides & Woo
/// 1987). 0 when `origin` itself is outside the block or in a non-cave voxel.
/// @param cave       cave mask, index space (non-zero = cave)
/// @param voxelSize  voxel edge, metres, > 0
/// @param origin     metres, world space
/// @param direction  unit vector (world axes)
double distanceToWall(const Grid3<std::uint8_t>& cave, double voxelSize, const std::array<double, 3>& origin,
                      const std::array<double, 3>& direction);

/// Left, right, up and down distances (metres) from a station to the walls: left and right
/// along the horizontal perpendicular of `heading` (left = heading turned 90° anticlockwise
/// seen from above), up and down along ±z.
struct Lrud {
    double left = 0, right = 0, up = 0, down = 0;
};

/// LRUD at `position` for a passage heading along `heading` (any length; only its horizontal
/// part counts; a vertical or zero heading is taken as north, +y, so left is −x).
Lrud measureLrud(const Grid3<std::uint8_t>& cave, double voxelSize, const std::array<double, 3>& position,
                 const std::array<double, 3>& heading);

/// The skeleton's passages: `morpho::findBranches` (branches between junctions and ends, and
/// pure cycles), in its order; passage id = position in the list.
/// @throw InputError on an invalid skeleton
std::vector<morpho::Branch> findPassages(const morpho::Skeleton& skeleton);

/// Station names by passage: node n of passage p at position s along it is named
/// `prefix + p + separator + s` (e.g. "p3.12"). A node shared by passages (a junction, an end
/// of a loop) keeps the name of the first passage that reaches it. Nodes in no passage
/// (isolated) get an empty name.
std::vector<std::string> stationNames(const morpho::Skeleton& skeleton, const std::vector<morpho::Branch>& passages,
                                      const std::string& prefix = "p", const std::string& separator = ".");

/// The passage of each skeleton node: the first passage (lowest id) through it; -1 for a node in
/// no passage (isolated).
std::vector<int> passageOfNodes(const morpho::Skeleton& skeleton, const std::vector<morpho::Branch>& passages);

/// The connected piece of each skeleton node, named by the lowest node index in it (an isolated
/// node is a piece of its own). A piece's first node is the one whose value is its own index.
std::vector<int> pieceOfNodes(const morpho::Skeleton& skeleton);

/// The heading of a passage at position s of its node chain: the mean of the unit directions of
/// the legs before and after it (one leg at the ends), in world axes (not normalised; zero when
/// the chain has no length there).
std::array<double, 3> passageHeading(const morpho::Skeleton& skeleton, const morpho::Branch& passage, std::size_t s);

/// Survey readings of the leg from `a` to `b` (metres, world space, z up, y north): tape length
/// (m), compass bearing in degrees clockwise from north (+y) in [0, 360), clino in degrees up
/// from the horizontal in [−90, 90]. `plumbed` when the horizontal part is below 1e-9 of the
/// length (the compass is then meaningless and written as omitted).
struct LegReading {
    double tape = 0, compass = 0, clino = 0;
    bool plumbed = false;
};
LegReading legReading(const std::array<double, 3>& a, const std::array<double, 3>& b);

}  // namespace cavesim::formats

/// @file protosinks.h
/// @brief Protosinks of a stage-1 pressure zone (Pytel & Mann, JCGT 2015, §3.1): the voxels on
/// the zone's boundary that drain the zone's flow network, all of them (isotropic growth) or a
/// few clusters of them (growth in preferred directions).
///
/// All positions are voxel indices (index space, unit spacing).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

#include "core/grid.h"
#include "core/vec3.h"

namespace cavesim::flownet {

/// Which faces of the grid count as zone boundary (a zone's outer surface where it meets the
/// grid's edge). Order: −x, +x, −y, +y, −z, +z. A face of extent 1 along its axis (the ±y faces
/// of a 2D section, ny = 1) is never a boundary: it is the section's plane, not an edge of rock.
using GridFaces = std::array<bool, 6>;

/// The boundary of zone `zone`: the voxels of `zoneVoxels` with a face neighbour whose label is
/// another zone (label ≥ 0, ≠ zone), or that lie on a grid face listed in `faces`. Voxels next
/// to unlabelled voxels (label −1: never reached, e.g. impermeable rock) are not boundary.
/// @param labels      zone label per voxel (−1 none)
/// @param zoneVoxels  the voxels labelled `zone`, linear indices, any order
/// @return boundary voxels, increasing
std::vector<std::size_t> zoneBoundary(const Grid3<std::int32_t>& labels, const std::vector<std::size_t>& zoneVoxels,
                                      int zone, const GridFaces& faces);

/// Cluster centres among `candidates` (the protosink candidates of one zone, increasing).
///
/// With `aim` points: one centre per point, the candidate nearest to it (ties: the lower index),
/// duplicates merged; `count` is not used. Without: `count` centres spread by best-candidate
/// sampling (Mitchell 1991) — each centre is the one of 16 uniform random draws farthest from the
/// centres chosen so far (the first is a single draw) — so they are random but rarely bunched.
/// Draws come only from `rng` (64-bit outputs mapped to an index by multiply-shift, identical on
/// every standard library); the same engine state gives the same centres. All candidates are
/// returned when there are at most `count`.
/// @param dims        the grid the indices refer to
/// @param count       number of centres wanted, ≥ 1
/// @param aim         optional aim points, voxel units
/// @return centres, in the order chosen (aimed: in `aim` order)
std::vector<std::size_t> chooseClusterCentres(const Dims& dims, const std::vector<std::size_t>& candidates, int count,
                                              const std::vector<Vec3d>& aim, std::mt19937_64& rng);

/// The candidates within Euclidean distance `radius` (voxels) of any centre: the protosinks of a
/// clustered zone. Radius 0 keeps just the centres.
/// @return increasing voxel indices
std::vector<std::size_t> clusterProtosinks(const Dims& dims, const std::vector<std::size_t>& candidates,
                                           const std::vector<std::size_t>& centres, double radius);

}  // namespace cavesim::flownet

/// @file skeleton.h
/// @brief The cave's centreline (curve skeleton) as a graph, the base of the network counts
/// (docs/network-definitions.md) and of the measures of morphometry.h and graph_metrics.h.
///
/// `skeletonize` turns the cave voxels into the `Skeleton` graph of skeleton_graph.h in five steps:
///
///  1. **Cavities filled.** A background (6-connected) pocket enclosed by a single cave component,
///     out of reach of the grid's outside, is filled first: a rock voxel floating inside a passage
///     would otherwise keep a closed surface in the skeleton around it. (A pocket that itself holds
///     a separate cave component is left alone, so components stay components.)
///  2. **Thinning** to a one-voxel-wide curve skeleton, topology preserved: the directional
///     scheme of Lee, Kashyap & Chu (CVGIP 56(6), 1994; the ITK/Fiji "Skeletonize3D" algorithm):
///     six sub-iterations per pass, one per border direction d (−x, +x, −y, +y, −z, +z). In each,
///     the voxels whose d-neighbour is background and that are simple and not end points (one
///     26-neighbour) are collected from the current image, then deleted one by one in
///     linear-index order, each re-checked against the image as it stands: still simple, still
///     not an end point, and — where the cave is one voxel thin along d, so that every voxel of
///     a thin band is a candidate — not become a *tip* (all its neighbours within one 2×2×2 block
///     with it) through this sub-iteration's deletions. Without that last rule the sequential
///     re-check eats a two-voxel-wide band or shaft from one end (it stays topologically a point).
///     On a 2D section (exactly one extent 1) the two sub-iterations along its normal are
///     skipped. Passes repeat until one deletes nothing. The simple-point test is the exact
///     characterisation of Bertrand & Malandain (Pattern Recognit. Lett. 15, 1994) for (26, 6)
///     connectivity: one 26-component of cave in N26*(p) and one 6-component of background in
///     N18*(p) 6-adjacent to p. So loops stay loops, components stay components, no cavity or
///     tunnel is created, and the result is deterministic. Voxels outside the grid are background.
///  3. **Graph.** Skeleton voxels are nodes, 26-adjacent skeleton voxels are edges. Then
///     (a) *short cuts*: kept are a spanning forest of shortest edges first (Kruskal; ties by node
///     ids) and, of the other edges (shortest first), those closing a loop of the voxel set: a
///     cycle independent, over GF(2), of the cycles kept so far and of the triangles of the
///     26-adjacency graph (the triangles fill its clique complex, which by the nerve theorem has
///     the topology of the union of the closed voxel cubes, i.e. (26, 6) digital topology). So a
///     staircase corner or a blob of junction voxels reads as a chain or a tree, never a triangle
///     or a square; connectivity is kept; and the graph has exactly one independent cycle
///     (E − V + C) per tunnel of the cave. (b) *junction clusters*: the nodes left with degree ≥ 3
///     that are joined by edges form one junction; each cluster becomes one node, at its voxel
///     farthest from the wall (ties: nearest the cluster's centroid, then lowest index); its inner
///     edges go, its outer edges are re-attached to that node and duplicates merged — unless that
///     would remove a cycle (a loop of the cave through the junction), when the cluster stays.
///  4. **Pruning.** An end spur is the chain from a degree-1 node to the first node of degree ≥ 3
///     (its junction); its length is the sum of its edge lengths. A spur shorter than
///     max(`pruneFactor` × the junction's radius, `minSpurLength` voxels) is removed. All short
///     spurs of a junction go together as long as one other branch stays at it; when all of a
///     junction's branches are short (a star), the two longest stay as one branch. Rounds repeat
///     until nothing changes. Chains between junctions and cycles are never touched, so loops and
///     components survive and a component always keeps at least one branch.
///  5. **Ends and smoothing.** With `extendEnds`, passage ends are restored: thinning eats about
///     one passage radius off every blunt end and bends the last voxels toward a corner of the end
///     wall. Each end chain is cut back to its deepest node (largest wall distance d) among those
///     no farther from the end, along the chain, than 2d; from there it is extended voxel by voxel
///     along the passage direction (principal axis of its last ≤ 8 nodes) while it stays in the
///     cave, and the end node is placed where that direction meets the cave's boundary (the end
///     wall, or the grid face where a passage leaves the grid). So a straight passage of L voxels
///     has a skeleton of length L voxels. Then node positions are smoothed along chains:
///     `smoothingIterations` Jacobi steps of x ← x + w·(mean of its two neighbours − x) for
///     degree-2 nodes (junctions and ends fixed), each node kept within its radius of its voxel
///     centre, so a voxel staircase reads as the straight passage it approximates and the
///     centreline does not leave the passage.
///
/// **Radius** of a node: the Euclidean distance from its voxel centre to the nearest non-cave
/// voxel centre (exact separable distance transform, Felzenszwalb & Huttenlocher 2012), minus
/// half a voxel: the distance to the wall face, in metres. A one-voxel passage has radius h/2 (its
/// width is h); a passage whose cross-section holds the voxels within r voxels of its axis has
/// radius ≈ r + 1/2 voxels. On a 2D section (exactly one grid extent 1) distances are measured
/// within the section: the faces of the one-voxel slab are not walls.
///
/// Output order: nodes sorted by voxel linear index; edges (a < b) sorted lexicographically.
#pragma once

#include <cstdint>
#include <vector>

#include "core/grid.h"
#include "morpho/skeleton_graph.h"

namespace cavesim::morpho {

/// One line of the exact squared Euclidean distance transform (Felzenszwalb & Huttenlocher 2012):
/// out[q] = min_p f[p] + (q − p)² for q in [0, n), n ≥ 1 (the lower envelope of the parabolas
/// rooted at p). `vtx` and `z` are scratch, resized here. Run it along each axis in turn for the
/// squared distance to the cells where f = 0 (f large elsewhere).
void envelope1d(const double* f, int n, double* out, std::vector<int>& vtx, std::vector<double>& z);

/// Settings of `skeletonize`.
struct SkeletonOptions {
    /// Fill enclosed background pockets (6-connected, not reaching the grid's outside) that touch a
    /// single cave component before thinning.
    bool fillCavities = true;
    /// Spurs (chains from an end to their junction, length along the chain) shorter than
    /// `pruneFactor` × the radius of their junction node are removed. ≥ 0; 0 disables this.
    double pruneFactor = 1.5;
    /// Spurs shorter than this many voxel edge lengths are removed whatever the radius. ≥ 0;
    /// 0 disables this.
    double minSpurLength = 2.0;
    /// Extend every end along its passage to the passage's end wall (see step 5).
    bool extendEnds = true;
    /// Laplacian smoothing steps along chains. 0 keeps the voxel centres. ≥ 0.
    int smoothingIterations = 10;
    /// Weight w of each smoothing step, in (0, 1].
    double smoothingWeight = 0.5;
};

/// Centreline graph of the voxels where `mask != 0` (26-connectivity for the cave, 6 for the
/// background; outside the grid is background).
/// @param mask       cave mask in index space (any extent may be 1; may be empty)
/// @param voxelSize  edge length of a voxel in metres (> 0); positions and radii are in metres,
///                   world space, voxel (i, j, k) centred at ((i, j, k) + 0.5) · voxelSize
/// @param options    see `SkeletonOptions`
/// @return the skeleton; empty when the mask is empty
/// @throw InternalError if `voxelSize` is not finite and positive, the options are out of range, or
///        `mask.data` does not hold `mask.dims.count()` values
Skeleton skeletonize(const Grid3<std::uint8_t>& mask, double voxelSize, const SkeletonOptions& options = {});

/// Steps 1–2 alone: the one-voxel-wide, topology-preserving curve skeleton of the voxels where
/// `mask != 0`, as a mask (1 = skeleton voxel) on the same grid, index space.
/// @param fillCavities  fill enclosed background pockets first (as `SkeletonOptions::fillCavities`)
/// @throw InternalError if `mask.data` does not hold `mask.dims.count()` values
Grid3<std::uint8_t> thinToCurveSkeleton(const Grid3<std::uint8_t>& mask, bool fillCavities = true);

}  // namespace cavesim::morpho

/// @file pattern.h
/// @brief Which cave pattern the network shows (Palmer 1991, Ford & Williams 2007): branchwork,
/// network maze, anastomotic maze, spongework, ramiform or single passage, with the measured
/// criteria. Decision rules and their reasoning: docs/geology.md, "Which pattern did I get?".
///
/// Criteria, all from the skeleton (positions in metres, world space, z up). A *chamber stub* — a
/// branch between two junctions shorter than the sum of their radii plus one voxel (a radius is
/// measured from the node's voxel centre to the wall face, so junction voxels that touch are still
/// a voxel apart) — lies inside one junction chamber: its two junctions count as one (its loop
/// too, when it closes one inside the chamber: a pillar), and it counts as no branch. The skeleton
/// splits a wide junction into such stubs.
///  - **loops per km**: independent cycles (edges − nodes + components) per km of centreline;
///    **loops per branch**: the same cycles per branch (`findBranches`), the scale-free measure
///    the rules use (a grid maze of n × n cells has n² loops and 2n(n + 1) − 4 branches: → 0.5).
///  - **junction degree**: mean degree of the junctions (nodes of degree ≥ 3, merged as above) (3: a fork or a braid,
///  4: a
///    crossing of two fissures).
///  - **dead-end share**: branches with an end of degree 1 / branches.
///  - **orientation**: `h_or` (graph_metrics.h) and the *orthogonal share*: the largest share of
///    horizontal centreline length (each edge weighted by its horizontal length) whose azimuth lies
///    within `alignedToleranceDeg` of θ or θ + 90°, over θ in whole degrees [0°, 90°) (ties: the θ
///    whose pair lies nearest the aligned edges, length-weighted, then the smallest θ). An even
///    spread of directions gives 4·tol/180° (0.22 for 10°). With fracture family strikes given,
///    the *family share*: the share within the tolerance of any strike.
///  - **planarity along beds**: the largest share of centreline length (edge midpoints, weighted
///    by edge length) within one slab normal to `bedNormal` of thickness
///    `slabDiameters` × the mean passage diameter (2 × length-weighted mean node radius);
///    **vertical spread**: the length-weighted standard deviation of the edge midpoints along
///    `bedNormal`, metres.
///  - **plan coverage**: cave plan area / plan area of its convex hull (morphometry.h).
///  - **width variation**: coefficient of variation (sample) of the branches' mean node radius.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/vec3.h"
#include "morpho/graph_metrics.h"
#include "morpho/skeleton_graph.h"

namespace cavesim::morpho {

/// Thresholds of the decision rules (docs/geology.md gives the reasons). Not scenario keys.
struct PatternOptions {
    /// Fewer branches than this: too small for a maze; "single passage" or "branchwork". ≥ 1.
    int minBranches = 10;
    /// A maze holds at least this many independent loops per branch. In (0, 1].
    double mazeLoopsPerBranch = 0.2;
    /// Half-width of the direction bins of the orthogonal and family shares, degrees, in (0, 45].
    double alignedToleranceDeg = 10.0;
    /// A maze whose orthogonal (or family) share reaches this is a network maze, in (0, 1].
    double networkAlignedShare = 0.6;
    /// A network whose bed share reaches this is planar (along one bed), in (0, 1].
    double planarBedShare = 0.6;
    /// Slab thickness in mean passage diameters, > 0.
    double slabDiameters = 2.0;
    /// A branching network that is not planar and whose width variation reaches this is ramiform. > 0.
    double ramiformWidthCv = 0.6;
    /// Voxel edge, metres, ≥ 0: added to the two junction radii in the chamber-stub test.
    double voxelSize = 0.0;
    /// Normal of the bedding, world axes (any length > 0); vertical by default (horizontal beds).
    Vec3d bedNormal{0, 0, 1};
};

/// The class and the criteria measured (`report.json` "pattern").
struct PatternResult {
    std::string pattern;  ///< "branchwork", "network maze", "anastomotic maze", "spongework", "ramiform",
                          ///< "single passage", or "none" (no branch)
    std::string rule;     ///< the rule that decided, in words
    double length_m = 0;
    long branches = 0;          ///< branches of the skeleton, chamber stubs aside
    long chamber_branches = 0;  ///< stubs inside a junction chamber, merged into one junction
    long loops = 0;             ///< independent loops, pillars inside a chamber aside
    double loops_per_km = 0;
    double loops_per_branch = 0;
    long junctions = 0;                            ///< nodes of degree ≥ 3, chamber stubs merged
    std::optional<double> junction_degree_mean;    ///< empty without junctions
    long dead_ends = 0;                            ///< nodes of degree 1
    std::optional<double> dead_end_share;          ///< empty without branches
    std::optional<double> orientation_entropy;     ///< h_or
    std::optional<double> orthogonal_share;        ///< empty without horizontal length
    std::optional<double> orthogonal_azimuth_deg;  ///< θ of the best orthogonal pair
    std::optional<double> family_share;            ///< only with fracture family strikes
    double slab_thickness_m = 0;
    std::optional<double> bed_share;  ///< empty without length
    double vertical_spread_m = 0;
    double plan_coverage = 0;
    std::optional<double> width_cv;  ///< empty for fewer than 2 branches
};

/// Measures the criteria and applies the rules.
/// @param skeleton         the cave's centreline (metres, world space)
/// @param metrics          its network metrics (computeGraphMetrics): loops, branches, h_or
/// @param planCoverage     cave plan area / convex-hull plan area, in [0, 1]
/// @param familyStrikesDeg strikes of the fracture families, degrees clockwise from north (+y);
///                         empty: none known, the orthogonal share decides instead
/// @throw InternalError on an invalid skeleton or options out of range
PatternResult classifyPattern(const Skeleton& skeleton, const GraphMetrics& metrics, double planCoverage,
                              const PatternOptions& options = {}, const std::vector<double>& familyStrikesDeg = {});

/// Share of horizontal centreline length within `toleranceDeg` of any of `azimuthsDeg` (modulo 180°);
/// empty without horizontal length.
std::optional<double> alignedShare(const Skeleton& skeleton, const std::vector<double>& azimuthsDeg,
                                   double toleranceDeg);

/// report.json "pattern": {"class", "rule", "criteria": {...}}.
nlohmann::json toJson(const PatternResult& p);

}  // namespace cavesim::morpho

/// @file morphometry.h
/// @brief Morphometric indices of the cave (paper §4.2; Klimchouk 2006, Frumkin & Fischhendler 2005):
/// length, plan area, volume, cave field A_field and block V_block, network density,
/// areal coverage, porosity and mean passage width W, for a rectangular and an optimised field,
/// and the cave category these indices point to (paper Tables 2 and 3).
///
/// Geometry, all in metres (the mask is in index space, z up; voxel (i, j, k) is the cube
/// [i, i+1]·h × [j, j+1]·h × [k, k+1]·h):
///  - plan: the set of columns (i, j) holding at least one cave voxel; area = cells · h².
///  - length: total length of the skeleton's edges (its node positions, world space). A skeleton
///    whose end nodes sit on end-voxel centres is shorter than the passage by about half a voxel per
///    end; W = area / length then exceeds the passage width by that much.
///  - volume = cave voxels · h³; vertical range = (k_max − k_min + 1) · h (cell faces).
///  - A_field rect: the plan's bounding rectangle, taken on cell edges.
///  - A_field hull: the convex hull of the plan cells' corners (Boost.Geometry); never exceeds the
///    rectangle.
///  - A_field opt, Klimchouk's optimised field (a contour around the cave at half the mean passage
///    spacing, instead of Worthington's rectangle): mean passage spacing S = A_field hull / length
///    (parallel passages at spacing S have density 1/S), margin r = S / 2; the field is the cells of
///    the plan's bounding box whose centre lies within r of the centre of a plan cell (exact
///    Euclidean distance transform) and inside or on the hull. So plan ≤ opt ≤ hull ≤ rect; a
///    margin under one cell gives the plan itself. Without a centreline (length 0) opt = hull.
///  - V_block = A_field · vertical range (for each field); network density = length / A_field (m/m²);
///    areal coverage = 100 · area / A_field (%); porosity = 100 · volume / V_block (%);
///    W = area / length (m).
/// An empty mask gives zeros everywhere; a ratio whose denominator is 0 is reported as 0.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "core/grid.h"
#include "morpho/reference_ranges.h"
#include "morpho/skeleton_graph.h"

namespace cavesim::morpho {

/// The `report.json` "morphometry" values (member names are the JSON keys) and supporting values.
struct Morphometry {
    double length_m = 0.0;                 ///< total skeleton length, m
    double area_m2 = 0.0;                  ///< plan area, m²
    double volume_m3 = 0.0;                ///< cave volume, m³
    double a_field_rect_m2 = 0.0;          ///< bounding rectangle of the plan, m²
    double a_field_opt_m2 = 0.0;           ///< Klimchouk's optimised field (plan + margin, within the hull), m²
    double a_field_hull_m2 = 0.0;          ///< convex hull of the plan, m²
    double passage_spacing_m = 0.0;        ///< mean passage spacing a_field_hull / length, m (0 without length)
    double field_margin_m = 0.0;           ///< margin of the optimised field, passage_spacing / 2, m
    double v_block_rect_m3 = 0.0;          ///< a_field_rect · vertical range, m³
    double v_block_opt_m3 = 0.0;           ///< a_field_opt · vertical range, m³
    double v_block_hull_m3 = 0.0;          ///< a_field_hull · vertical range, m³
    double network_density_hull = 0.0;     ///< length / a_field_hull, m/m²
    double areal_coverage_pct_hull = 0.0;  ///< 100 · area / a_field_hull, %
    double porosity_pct_hull = 0.0;        ///< 100 · volume / v_block_hull, %
    double network_density_opt = 0.0;      ///< length / a_field_opt, m/m²
    double network_density_rect = 0.0;     ///< length / a_field_rect, m/m²
    double areal_coverage_pct_opt = 0.0;   ///< 100 · area / a_field_opt, %
    double areal_coverage_pct_rect = 0.0;  ///< 100 · area / a_field_rect, %
    double porosity_pct_opt = 0.0;         ///< 100 · volume / v_block_opt, %
    double porosity_pct_rect = 0.0;        ///< 100 · volume / v_block_rect, %
    double mean_width_m = 0.0;             ///< W = area / length, m (0 when the length is 0)
    double vertical_range_m = 0.0;         ///< (k_max − k_min + 1) · h over the cave voxels, m
    long cave_voxels = 0;                  ///< voxels of the mask that are cave (non-zero)
    long plan_cells = 0;                   ///< columns (i, j) with at least one cave voxel
};

/// The morphometric indices of a cave.
/// @param mask       cave voxels (non-zero = cave), index space, z up
/// @param skeleton   the cave's centreline, positions in metres (world space); only its edge lengths are used
/// @param voxelSize  edge of a voxel, metres, > 0
/// @throw cavesim::InternalError on a non-positive or non-finite voxel size, a mask whose data does not
///        match its dims, or an invalid skeleton (see `validateSkeleton`)
Morphometry computeMorphometry(const Grid3<std::uint8_t>& mask, const Skeleton& skeleton, double voxelSize);

/// The index keys (the member names above) plus "vertical_range_m", "cave_voxels", "plan_cells" and
/// "field_opt_method" ("plan_margin_in_hull").
nlohmann::json toJson(const Morphometry& m);

/// How close the centreline and the block lie to a set of marked voxels (report.json
/// `stage2.near_protochannels`, with the stage-1 protochannels marked).
struct NearMarked {
    double radius_vox = 0;                   ///< the distance, index units (voxel centre to voxel centre)
    double length_m = 0;                     ///< skeleton length, m
    double length_near_m = 0;                ///< of it, within the distance (see `nearMarked`), m
    std::optional<double> centreline_share;  ///< length_near / length; empty without length
    long block_voxels = 0;                   ///< voxels of the grid
    long block_voxels_near = 0;              ///< of them, within the distance of a marked voxel
    std::optional<double> block_share;       ///< block_voxels_near / block_voxels; empty for an empty grid
};

/// Share of the skeleton's length, and of the block's voxels, within `radius` voxels (Euclidean,
/// voxel centre to voxel centre, index units) of a marked voxel (`marked` non-zero). Each edge's
/// length is split half to each end node; a node is near when its voxel is.
/// @throw cavesim::InternalError on an invalid skeleton, a node outside the grid or a negative radius
NearMarked nearMarked(const Skeleton& skeleton, const Grid3<std::uint8_t>& marked, double radius);

/// {"radius_vox", "centreline_share", "block_share", "length_near_m", "block_voxels_near"}.
nlohmann::json toJson(const NearMarked& n);

/// How many of the category's ranges (`categoryRanges`) hold the cave's value.
struct CategoryVotes {
    int unconfined = 0;  ///< of 4 (Table 2)
    int confined = 0;    ///< of 7 (Table 2: 4, Table 3: 3)
    int chamber = 0;     ///< of 3 (Table 3)
};

/// Counts, for each category, the indices that fall inside its ranges.
CategoryVotes categoryVotes(const Morphometry& m);

/// The category the indices point to: the one with the most votes (`categoryVotes`); "mixed" when
/// two or more share the largest count, "none" when no index falls in any range (e.g. an empty cave).
/// Confined caves are described by both tables, so "confined" can collect up to 7 votes against 4
/// (unconfined) and 3 (chamber): the rule reads the two tables together as the paper does (§4.2:
/// Figures 10–12 "fit well into the confined category") and gives "confined" for all three caves of
/// the paper's Table 4.
std::string caveCategory(const Morphometry& m);

}  // namespace cavesim::morpho

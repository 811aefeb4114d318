/// @file csv_formats.h
/// @brief Tables for spreadsheets and pandas: the stage-2 history (`history.csv`) and the
/// cave's branches (`branches.csv`). Comma-separated, one header line, '\n' line ends, numbers
/// in the shortest form that reads back exactly, an empty field where a value is undefined.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/grid.h"
#include "morpho/network.h"
#include "morpho/skeleton_graph.h"
#include "sim/domain.h"
#include "sim/stage2.h"

namespace cavesim::formats {

/// `history.csv`: one row per stage-2 iteration (`Stage2Result::history`), columns
/// iteration, injected, drained, stored, flow, eroded, channel_voxels, pressure_updates,
/// sources_connected, balance_error (water and volumes in voxel units, see Stage2Record).
/// @throw RuntimeError naming `path` when it cannot be written
void writeHistoryCsv(const std::vector<Stage2Record>& history, const std::string& path);

/// One row of `branches.csv`.
struct BranchRow {
    int id = 0;                         ///< passage id (`findPassages` order, as skeleton.vtp and the survey)
    int fromNode = 0, toNode = 0;       ///< skeleton node indices of its ends (equal for a loop)
    int nodes = 0;                      ///< skeleton nodes along it, ends included
    double length_m = 0;                ///< along the centreline, m
    double straight_m = 0;              ///< between its ends, m
    double meanRadius_m = 0;            ///< mean skeleton radius of its nodes, m
    double meanWidth_m = 0;             ///< mean left + right (LRUD) over its nodes, m
    double meanHeight_m = 0;            ///< mean up + down (LRUD) over its nodes, m
    std::optional<double> azimuth_deg;  ///< trend of the end-to-end line, clockwise from north (+y), [0, 360)
    std::optional<double> dip_deg;      ///< plunge of that line below the horizontal, [0, 90]
    std::optional<double> meanFlow;     ///< mean stage-2 flow at its nodes' voxels (voxel volumes/iteration)
    std::string role;                   ///< "main", "tributary", "unconnected", "side"; empty when unknown
    int loopTroughs = 0;                ///< phreatic-loop troughs (network analysis) among its nodes
};

/// The rows of `branches.csv`. Orientation: the end-to-end line as a geological lineation,
/// pointing down (plunge ≥ 0; a horizontal branch has its azimuth in [0, 180)); undefined for a
/// loop branch (its ends coincide). Role from the flow paths of the network analysis: "main" on
/// the path of a source that reached a sink on its own channel, or after the join of a captured
/// one; "tributary" on a captured source's path before its join node; "unconnected" on the path
/// of a source that reached no sink; "side" on no flow path; the first of these that any of its
/// edges has wins.
/// @param cave      cave mask (index space) for widths and heights
/// @param voxelSize metres, > 0
/// @param flow      stage-2 flow grid (index space); null: no mean flow
/// @param network   network analysis of the same skeleton; null: no role, no troughs
/// @throw InputError on an invalid skeleton
std::vector<BranchRow> branchRows(const morpho::Skeleton& skeleton, const Grid3<std::uint8_t>& cave, double voxelSize,
                                  const Grid3<float>* flow = nullptr, const morpho::NetworkCounts* network = nullptr);

/// `branches.csv`: columns id, from_node, to_node, nodes, length_m, straight_m, mean_radius_m,
/// mean_width_m, mean_height_m, azimuth_deg, dip_deg, mean_flow, role, loop_troughs.
/// @throw RuntimeError naming `path` when it cannot be written
void writeBranchesCsv(const std::vector<BranchRow>& rows, const std::string& path);

}  // namespace cavesim::formats

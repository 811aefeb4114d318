/// @file network.h
/// @brief Events of channel linkage read off the cave skeleton: sources connected to a sink,
/// confluences, tributary captures and phreatic loops (Pytel & Mann, JCGT 2015, §2.2, §3.2).
///
/// The flow path of a source follows the stage-2 flow: the steepest descent of the final stage-2
/// pressure through cave voxels, from the source to a sink, mapped onto the skeleton. Exact
/// definitions, with the reasons for each choice: docs/network-definitions.md.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/grid.h"
#include "morpho/skeleton_graph.h"

namespace cavesim::morpho {

/// What the network analysis needs of a run, in index space.
struct NetworkInput {
    Dims dims;
    double voxelSize = 0;  ///< metres; > 0: elevations from the smoothed node positions, else from node voxels
    const Grid3<std::uint8_t>* cave = nullptr;      ///< cave voxels (1) — the mask the skeleton was made from
    const Grid3<float>* pressure = nullptr;         ///< stage-2 pressure; nullptr when there was no stage 2
    std::vector<std::vector<std::size_t>> sources;  ///< voxels of each source, scenario order
    std::vector<std::vector<std::size_t>> sinks;    ///< voxels of each sink, scenario order
    /// Iteration at which each source was first joined to a sink during stage 2 (scenario order);
    /// decides which of two merging channels is the tributary. Empty or null entries: unknown.
    std::vector<std::optional<int>> connectedIteration;
};

struct NetworkOptions {
    /// A phreatic loop: along a flow path, a descent followed by a rise of at least this many
    /// voxels (index units, z); docs/network-definitions.md, "Phreatic loops": 2.
    double loopRise = 2;
    /// How far a terminal (source or sink) may be from the skeleton, measured through cave
    /// voxels (26-connected steps, index units), for the two to be joined.
    int attachDistance = 6;
};

/// The flow path of one source: skeleton nodes from the source to a sink, pressure decreasing.
struct FlowPath {
    int source = 0;                   ///< scenario index
    std::optional<int> sink;          ///< scenario index of the sink reached; empty: not connected
    std::vector<int> nodes;           ///< skeleton node indices, source end first
    std::vector<std::size_t> voxels;  ///< the descent through cave voxels (linear indices), source end first
    /// true when the descent did not reach a sink and the path is the shortest skeleton path instead
    bool fallback = false;
    bool downhill = true;           ///< false when the path has an uphill step (only a fallback path can)
    std::vector<int> loopTroughs;   ///< skeleton nodes at the bottom of each phreatic loop on the path
    std::optional<int> capturedBy;  ///< the source whose channel this one joined before the sink
    std::optional<int> joinNode;    ///< where it joined that channel
};

struct NetworkCounts {
    int sourcesTotal = 0;
    int sourcesConnected = 0;     ///< sources with a flow path to a sink
    int confluences = 0;          ///< distinct nodes where the flow paths of different sources first meet
    int tributaryCaptures = 0;    ///< sources whose channel joins an earlier-connected source's channel before a sink
    int phreaticLoops = 0;        ///< distinct loop troughs over all flow paths
    bool oriented = false;        ///< a stage-2 pressure was given (else paths are shortest skeleton paths)
    int fallbackPaths = 0;        ///< connected sources whose path is a fallback (oriented runs only)
    std::vector<FlowPath> paths;  ///< one per source, scenario order
};

/// The end of a steepest descent through cave voxels.
struct Descent {
    std::vector<std::size_t> voxels;  ///< linear indices, start first
    bool reachedExit = false;         ///< the last voxel is an exit
};

/// Steepest descent of `pressure` through cave voxels from `start`: from each voxel, the step to
/// the 26-neighbour cave voxel of strictly lower pressure with the largest drop per unit length
/// (ΔP / |offset|, offsets of length 1, √2, √3 in index units); ties: the lower pressure, then the
/// lower linear index. Stops at an exit voxel (`exit[v] != 0`) or where no neighbour is lower.
/// Pressure strictly falls along the path, so it ends.
/// @throw cavesim::InternalError if the grids do not match or `start` is outside them
Descent descendPressure(const Grid3<std::uint8_t>& cave, const Grid3<float>& pressure, std::size_t start,
                        const std::vector<char>& exit);

/// Analyses the skeleton of a cave. Never throws for an empty cave or skeleton (all counts 0).
/// @throw cavesim::InternalError if the grids do not match `dims`
NetworkCounts analyseNetwork(const Skeleton& skeleton, const NetworkInput& input, const NetworkOptions& options = {});

/// report.json "network": sources_total, sources_connected, confluences, tributary_captures,
/// phreatic_loops, fallback_paths, fallback_fraction (of the connected sources; null without
/// pressure or without a connected source), and per-source details under "paths".
nlohmann::json toJson(const NetworkCounts& counts, const Skeleton& skeleton);

}  // namespace cavesim::morpho

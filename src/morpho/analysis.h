/// @file analysis.h
/// @brief The whole measurement of a cave: skeleton → network counts, morphometric
/// indices (paper §4.2) and network metrics (Collon et al. 2017), in one call.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "morpho/cross_sections.h"
#include "morpho/graph_metrics.h"
#include "morpho/morphometry.h"
#include "morpho/network.h"
#include "morpho/pattern.h"
#include "morpho/skeleton.h"
#include "morpho/skeleton_io.h"  // writeSkeletonFiles, for callers
#include "sim/cave.h"

namespace cavesim::morpho {

struct CaveAnalysis {
    Skeleton skeleton;
    NetworkCounts network;
    Morphometry morphometry;
    GraphMetrics metrics;
    /// Centreline and block near the stage-1 protochannels; set by the caller that knows them.
    std::optional<NearMarked> nearProtochannels;
    /// Cave pattern (pattern.h). A 2D section (one grid extent 1) has no plan pattern: "not classified".
    PatternResult pattern;
    /// Passage cross-sections (cross_sections.h); none for a 2D section.
    CrossSections sections;
    double seconds = 0;  ///< wall time of the analysis
};

/// Skeletonizes the cave (sim/cave.h) and measures it. `pressure`: the stage-2 pressure that
/// orients the passages from sources to sinks, or nullptr when stage 2 did not run (then the
/// network is read unoriented). `connectedIteration`: the stage-2 iteration at which each source
/// joined a sink (scenario order; empty when unknown), used to tell a captured tributary from the
/// channel that captured it. `familyStrikesDeg`: strikes of the rock's fracture families, degrees
/// clockwise from north, for the pattern's orientation criterion (empty: none known).
CaveAnalysis analyseCave(const Cave& cave, const Grid3<float>* pressure,
                         const std::vector<std::optional<int>>& connectedIteration = {},
                         const SkeletonOptions& skeletonOptions = {}, const std::vector<double>& familyStrikesDeg = {});

}  // namespace cavesim::morpho

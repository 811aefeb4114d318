/// @file speleo_report.h
/// @brief The speleothems' part of report.json and report.md (src/speleo/decorate.h).
#pragma once

#include <sstream>

#include <nlohmann/json.hpp>

#include "speleo/decorate.h"

namespace cavesim::app {

/// report.json "speleothems": counts, the longest stalactites (up to 20) and the run's numbers.
/// A stalactite counts when it grew at least one level-set voxel: its `length_m` is the grown
/// length, from the original ceiling straight above its tip down to the tip
/// (`Stalactite::grownLength`); convex ceiling patches that did not grow are only counted
/// (`convex_patches`).
nlohmann::json speleothemsJson(const speleo::DecorationSummary& summary);

/// The "Speleothems" section of report.md (nothing when `report` has no "speleothems").
void writeSpeleothemsMarkdown(std::ostringstream& md, const nlohmann::json& report);

}  // namespace cavesim::app

/// @file report_section.h
/// @brief What report.md shows for a 2D section (a grid one voxel thick in y, the paper's Figures
/// 8 and 9) in place of the plan indices of paper §4.2, which measure the plan of a 3D cave.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "sim/scenario.h"

namespace cavesim::app {

/// True when the scenario's grid is a 2D section (app/cave_maps.h `isSection`).
bool isSectionScenario(const Scenario& s);

/// The "Section measures" part of report.md: cave length, cave area in the section, the
/// section's area, the cave's share of it, mean passage width in the section plane (area /
/// length) and vertical range, from report.json's `morphometry` (metres, m², %).
std::string sectionMeasuresMarkdown(const Scenario& s, const nlohmann::json& report);

}  // namespace cavesim::app

/// @file speleo_report.h
/// @brief The speleothems' part of report.json and report.md (src/speleo/decorate.h).
#pragma once

#include <sstream>

#include <nlohmann/json.hpp>

#include "speleo/decorate.h"

namespace cavesim::app {

/// report.json "speleothems": counts, the largest stalactites (up to 20) and the run's numbers.
nlohmann::json speleothemsJson(const speleo::DecorationSummary& summary);

/// The "Speleothems" section of report.md (nothing when `report` has no "speleothems").
void writeSpeleothemsMarkdown(std::ostringstream& md, const nlohmann::json& report);

}  // namespace cavesim::app

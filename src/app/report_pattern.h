/// @file report_pattern.h
/// @brief What report.md says about the cave's pattern (morpho/pattern.h) and its passage
/// cross-sections (morpho/cross_sections.h), from report.json's `pattern` and `cross_sections`.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace cavesim::app {

/// "## Cave pattern": the class, the rule that decided and the table of criteria; empty when the
/// report has no `pattern`.
std::string patternMarkdown(const nlohmann::json& report);

/// "## Cross-sections": count, length, mean width, height, w/h and elevations per class, and
/// (up to kSectionRowsShown passages) one row per passage; empty when the report has none.
std::string crossSectionsMarkdown(const nlohmann::json& report);

/// Passages listed one by one in report.md (all of them are in report.json).
inline constexpr int kSectionRowsShown = 40;

}  // namespace cavesim::app

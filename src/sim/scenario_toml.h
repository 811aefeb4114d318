/// @file scenario_toml.h
/// @brief Scenarios as TOML tables (toml++), for code that builds or edits a scenario key by key
/// (the public API, src/lib) rather than from text. Includes toml++: use it only in .cpp files.
///
/// `parseScenarioTable` is the parser of scenario_io.h after the text stage: the same checks and
/// the same messages, registry-driven; a table built in code has no line numbers, so its messages
/// name the source, the key, the value and what is allowed.
#pragma once

#include <string>

#include <toml++/toml.h>

#include "sim/scenario.h"

namespace cavesim {

/// Reads and validates a scenario from a TOML table; `sourceName` stands for the file name in
/// messages (and becomes `Scenario::path`).
/// @throw InputError on any invalid content (as parseScenarioString)
Scenario parseScenarioTable(const toml::table& root, const std::string& sourceName);

/// The effective scenario as a TOML table, every key with its value (what scenarioToToml prints:
/// a table marked `omitAtDefaults` is left out when all its keys hold their defaults, unless
/// `everyTable`).
toml::table scenarioTable(const Scenario& scenario, bool everyTable = false);

}  // namespace cavesim

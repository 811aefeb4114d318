/// @file scenario_io.h
/// @brief Reading and writing scenario files (TOML). The format: docs/scenario-format.md.
///
/// Parsing is strict: an unknown or misspelt key, a wrong type, an out-of-range value, a source
/// or sink outside the domain, a source overlapping a sink or a stage 2 without sinks is an
/// `InputError` whose message names the file, the line, the key, the value and what is allowed.
#pragma once

#include <string>
#include <string_view>

#include "sim/scenario.h"

namespace cavesim {

/// Parses and validates a scenario file.
/// @throw InputError on a missing file, malformed TOML or any invalid content
Scenario parseScenarioFile(const std::string& path);

/// Parses and validates scenario text; `sourceName` stands for the file name in messages.
Scenario parseScenarioString(std::string_view text, const std::string& sourceName);

/// Checks the relations between fields (sources inside the domain, no overlap with sinks, …).
/// Called by the parsers; callers that change a scenario afterwards (e.g. `--seed`) may call it again.
/// @throw InputError naming the offending entry
void validateScenario(const Scenario& scenario);

/// Checks that every `[[phase]]` `sources` and `sinks` number names a source or sink of the run:
/// sources are numbered 1… over the `[[source]]` entries in file order, then the `[[recharge]]`
/// inputs, then a `[site]`'s sinkholes; sinks over the `[[sink]]` entries, then the site's springs
/// (the order stage 2 sees them). A scenario whose site has sinkholes or springs is checked once the
/// site is read (site::loadSite); validateScenario checks the others.
/// @throw InputError naming the phase's line, the key and the number
void validatePhaseTerminals(const Scenario& scenario);

/// Whether two boxes (inclusive voxel indices) share a voxel.
bool boxesOverlap(const VoxelBox& a, const VoxelBox& b);

/// The effective scenario as TOML, every default filled in; parses back to an equal scenario.
std::string scenarioToToml(const Scenario& scenario);

/// The dotted scenario key of the field at address `field` inside `scenario`,
/// from the parameter registry, for messages that point at a key.
/// @throw InternalError if `field` is not a registered field of `scenario`
std::string scenarioKey(const Scenario& scenario, const void* field);

/// The line in `scenario`'s file of the key of the field at address `field` (in a plain table or
/// in an entry of a table of arrays), or 0 when the file does not give it (or `field` is not a
/// registered field).
int keyLine(const Scenario& scenario, const void* field);

/// The built-in default scenario (the Figure 10 scenario, scenarios/fig10.toml).
Scenario defaultScenario();

}  // namespace cavesim

/// @file state.h
/// @brief The run's state files (state.vdb, stage1.vdb): the one place that knows which grids
/// they hold, under which names, and how they are read back and checked.
///
/// Grids, in world space (metres; voxel (i, j, k) has its centre at (ijk + 0.5) · voxel size):
/// `porosity`, `porosity0`, `zone`, `flags` always; `pressure`, `flow`, `water` after stage 2.
#pragma once

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "sim/domain.h"
#include "sim/scenario.h"

namespace cavesim::app {

/// Which moment of a run a state file records.
enum class StateMoment {
    kAfterStage1,  ///< stage1.vdb: protochannels shown opened (Stage1Options::protochannelPorosity)
    kFinal,        ///< state.vdb: the final state; after stage 2 with its fields
};

/// Writes the state grids of `domain` to `path` (.vdb). After stage 1 (and as the final state of
/// a run without stage 2) the porosity grid shows the protochannels opened to
/// `scenario.stage1.protochannelPorosity`, as the paper displays them; the domain is not changed.
/// @throw RuntimeError when the file cannot be written
void writeState(const std::string& path, const Domain& domain, const Scenario& scenario, StateMoment moment);

/// The file `cavesim report` reads back: the final state in our own checked format (app/state_file.h).
inline constexpr const char* kCheckedStateFile = "state.cavesim";

/// Writes the final state of `domain` twice from one set of grids: `dir`/state.vdb and, in the
/// checked format, `dir`/state.cavesim. Returns their records (see stateRecord), keyed by file name.
/// @throw RuntimeError when a file cannot be written
nlohmann::json writeFinalState(const std::filesystem::path& dir, const Domain& domain, const Scenario& scenario);

/// The porosity a state file records for `moment` (see writeState).
Grid3<float> recordedPorosity(const Domain& domain, const Scenario& scenario, StateMoment moment);

/// Size and FNV-1a 64 checksum of a file's bytes, {"bytes": n, "fnv1a64": "hex"}: the record
/// `loadState` checks state.cavesim against before it decodes the file.
/// @throw RuntimeError if the file cannot be read
nlohmann::json fileFingerprint(const std::string& path);

/// The record of a run's state file: its fingerprint, grid and voxel size.
nlohmann::json stateRecord(const nlohmann::json& fingerprint, const Scenario& scenario);

/// A run's final domain as `run` wrote it: grids from dir/state.cavesim (checked against the record
/// in `report` or in the last line of dir/scenario.toml first, then decoded with every size and
/// checksum checked, then range-checked), sources and sinks from the scenario. state.vdb is not read.
/// @throw InputError when the file is missing, changed, damaged or does not match the scenario
Domain loadState(const std::filesystem::path& dir, const Scenario& scenario, const nlohmann::json& report);

}  // namespace cavesim::app

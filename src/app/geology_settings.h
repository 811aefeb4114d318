/// @file geology_settings.h
/// @brief `cavesim reproduce geology`: the shipped geological settings of docs/geology.md
/// ("Shipped settings"; Palmer 1991's patterns in their settings), their pictures and the generated
/// page of their numbers (docs/geology_settings.md), from the runs' report.json documents.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace cavesim::app {

/// One shipped setting: the scenario `scenarios/<scenario>.toml` and the picture of its run that
/// shows its pattern.
struct GeologySetting {
    const char* scenario;  ///< scenario file name without `.toml` (also the run's name)
    const char* picture;   ///< picture in the run's `images/` folder, e.g. "plan.png"
    const char* view;      ///< what the picture shows, for its caption ("plan", "side view x–z")
};

/// The four settings, in the order of docs/geology.md: branchwork, network_maze, anastomotic
/// (plan each) and multilevel (its x–z side view: the levels lie one above the other).
const std::vector<GeologySetting>& geologySettings();

/// The seed every setting is run with (overrides the scenario's), so the pictures are reproducible.
inline constexpr std::uint64_t kGeologySeed = 1;

/// The file name of a setting's picture in the docs' `images/` folder: "geology_<scenario>.png".
std::string geologyPictureName(const std::string& scenario);

/// Levels of phreatic passages: the tube and keyhole passages of report.json `cross_sections`
/// grouped by elevation, two passages in one level when their vertical extents overlap (directly
/// or through other passages of the level). A tube's extent is its centreline's elevation range
/// widened by half its height: [z_min_m − height_m/2, z_max_m + height_m/2] (metres, world z); a
/// keyhole's is its centreline's range alone (its height is mostly the canyon cut into the tube).
/// Only sub-horizontal passages form levels: a tube or keyhole whose centreline climbs more than its
/// own height (z_max_m − z_min_m > height_m: a ramp, or a round shaft, between two levels) does not
/// count, nor do canyons and shafts (vadose passages between levels), "other" and "short" passages.
/// @param crossSections report.json's `cross_sections` object (null or without `passages`: 0)
/// @return the number of levels, 0 when there is no tube or keyhole passage
int passageLevels(const nlohmann::json& crossSections);

/// One setting's run, as the generated page needs it.
struct GeologyRun {
    std::string scenario;   ///< GeologySetting::scenario
    std::string view;       ///< GeologySetting::view
    nlohmann::json report;  ///< the run's report.json document
};

/// The generated page (Markdown): how it was made, a summary table (pattern class, passage length,
/// branches, loops, karstnet metrics inside the 34 real caves' range, levels, breakthrough, run
/// time) and a section per setting with the class's rule, the metrics out of range, the
/// cross-section classes with their elevations, the base-level phases and the picture, linked as
/// `images/<geologyPictureName>` relative to the page.
/// @param runs the settings' runs, in the order to show them
/// @param threads the thread count the runs used (stated on the page)
std::string geologySettingsMarkdown(const std::vector<GeologyRun>& runs, int threads);

}  // namespace cavesim::app

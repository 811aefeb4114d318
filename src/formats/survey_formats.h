/// @file survey_formats.h
/// @brief The cave's centreline as cavers survey it: Survex (`cave.svx`, processed by `cavern`)
/// and Therion (`cave.th`, compiled by `therion`), with passage dimensions (LRUD).
///
/// Stations are the skeleton's nodes (morpho/skeleton_graph.h), named by passage: node s of
/// passage p (`findPassages`) is `p<p>.<s>` (Survex) or `p<p>_<s>` (Therion), a junction keeps
/// the name of its first passage. Each skeleton edge is one leg along its passage: tape (m),
/// compass (degrees clockwise from grid north = +y), clino (degrees up); a vertical leg has clino
/// `up`/`down` and an omitted compass (`-`). Readings are rounded to 0.1 mm and 0.001°, so the
/// processed station positions agree with the skeleton to well under a millimetre per leg. The
/// first station of each connected piece is fixed at its world position (metres, x east, y north,
/// z up), so the processed survey lands in the simulation's coordinates. LRUD at every station
/// of a passage: `measureLrud` (passages.h) in the cave mask, perpendicular to the passage's
/// heading there (`passageHeading`), rounded to the millimetre.
#pragma once

#include <cstdint>
#include <string>

#include "core/grid.h"
#include "morpho/skeleton_graph.h"

namespace cavesim::formats {

/// Options of the survey writers.
struct SurveyOptions {
    std::string name = "cave";           ///< survey name (Survex `*begin`, Therion `survey`); letters, digits, _
    std::string title = "cavesim cave";  ///< title (comment in Survex, `-title` in Therion)
};

/// Survex `.svx`: `*begin <name>`, `*units` tape metres, compass and clino degrees, `*fix` per
/// connected piece, then per passage its legs (`*data normal from to tape compass clino`) and
/// its LRUD (`*data passage station left right up down`), `*end <name>`.
/// @param skeleton   the centreline (metres, world space)
/// @param cave       the cave mask the skeleton was made from (index space), for the LRUD
/// @param voxelSize  metres, > 0
/// @throw InputError on an invalid skeleton, a bad name, or a skeleton without edges;
///        RuntimeError naming `path` when it cannot be written
void writeSurvex(const morpho::Skeleton& skeleton, const Grid3<std::uint8_t>& cave, double voxelSize,
                 const std::string& path, const SurveyOptions& options = {});

/// Therion `.th`: `encoding utf-8`, `survey <name> -title "<title>"` holding one `centreline`
/// with `units length meters`, `units compass clino degrees`, a `fix` per connected piece, then
/// per passage `data normal from to length compass clino` legs and `data dimensions station left
/// right up down` LRUD (Therion's per-station form of the same dimensions), `endcentreline`,
/// `endsurvey`. Compile with a thconfig holding `source cave.th` and an export.
/// @throw as writeSurvex
void writeTherion(const morpho::Skeleton& skeleton, const Grid3<std::uint8_t>& cave, double voxelSize,
                  const std::string& path, const SurveyOptions& options = {});

}  // namespace cavesim::formats

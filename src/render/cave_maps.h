/// @file cave_maps.h
/// @brief Cave maps as surveyors draw them: a plan and an extended elevation of the centreline,
/// passages drawn as wide as the cave, coloured by elevation, with station names, a scale bar, a
/// north arrow (plan) and a colour bar; drawn once with Cairo into PNG and SVG.
///
/// - **Plan**: seen from above, x east to the right, y north up, true scale; passages drawn from
///   the lowest to the highest so that upper passages cover lower ones.
/// - **Extended elevation**: the profile unrolled along the passages. Each passage is laid out in
///   turn, from the station nearest the first source (the entrance), in depth-first order: its
///   horizontal distance along the centreline on the x axis, its elevation on the y axis, the same
///   scale on both. A passage that leaves from the end of the one before continues it; any other
///   starts after a small gap, and the station names at its ends say where it joins.
/// - **Section**: a 2D section (grid one voxel thick in y) is drawn as itself (x right, z up)
///   instead of a plan.
///
/// Space: positions in metres, world space (x east, y north, z up, block from 0 to `blockMax`).
/// No simulation type appears here: the application builds `CaveMapInput` from the skeleton.
#pragma once

#include <string>
#include <vector>

#include "core/vec3.h"

namespace cavesim::render {

/// One survey station: a centreline node.
struct MapStation {
    Vec3d position{0, 0, 0};  ///< metres, world space
    double radius = 0;        ///< passage radius at the station, metres
    std::string name;         ///< e.g. "p3.12"; empty: unnamed
};

/// What a map is drawn from.
struct CaveMapInput {
    std::string title;                       ///< e.g. the scenario name
    Vec3d blockMax{1, 1, 1};                 ///< the rock block spans [0, blockMax], metres
    std::vector<MapStation> stations;        ///< every centreline node
    std::vector<std::vector<int>> passages;  ///< station indices along each passage (≥ 2 each)
    std::vector<Vec3d> sources, sinks;       ///< centres of the sources (S1, S2, …) and sinks, metres
};

/// Kinds of map.
enum class MapKind { kPlan, kExtendedElevation, kSection };

/// File stem of a map kind: "map_plan", "map_extended_elevation", "map_section".
std::string mapStem(MapKind kind);

/// Horizontal position (metres along the unrolled centreline) of each station of each passage in
/// the extended elevation, in the layout described in the file comment: result[p][s] for station
/// s of passage p. Also gives the total unrolled length in `extent` (gaps included) when not null.
/// @throw InternalError if a passage has fewer than 2 stations or a station index is out of range
std::vector<std::vector<double>> extendedElevationLayout(const CaveMapInput& input, double* extent = nullptr);

/// A map as a PNG (RGB, `width` pixels wide) and as an SVG of the same drawing, in memory.
struct MapDrawing {
    std::string png, svg;
};

/// Draws one map `width` pixels wide (height from the drawing's proportions).
/// @throw InternalError if width is outside [256, 16384]; RuntimeError if Cairo fails
MapDrawing drawCaveMap(const CaveMapInput& input, MapKind kind, int width);

/// The maps of a cave into `dir`: map_plan (or map_section for a 2D section, `section`) and
/// map_extended_elevation, each as .png and .svg, each through a temporary name and a rename.
/// @return the file names written (relative to `dir`)
/// @throw RuntimeError when a file cannot be written
std::vector<std::string> writeCaveMaps(const CaveMapInput& input, bool section, const std::string& dir, int width);

}  // namespace cavesim::render

/// @file cave_maps.h
/// @brief The run's cave maps (render/cave_maps.h) from its skeleton: stations named as in the
/// survey exports (formats/passages.h, "p<passage>.<n>"), passage radii from the skeleton.
#pragma once

#include <string>
#include <vector>

#include "morpho/skeleton_graph.h"
#include "render/cave_maps.h"
#include "sim/cave.h"

namespace cavesim::app {

/// True for a 2D section: a grid exactly one voxel thick in y (the paper's Figures 8 and 9).
bool isSection(const Dims& dims);

/// What the maps of `cave` are drawn from: the skeleton's passages and stations (metres, world
/// space), the centres of the sources and sinks, the block; `title` heads each map.
/// @throw InputError on an invalid skeleton
render::CaveMapInput caveMapInput(const Cave& cave, const morpho::Skeleton& skeleton, const std::string& title);

/// Writes imagesDir/map_plan (map_section for a 2D section) and map_extended_elevation, .png and
/// .svg, `width` pixels wide.
/// @return the file names written, relative to imagesDir
/// @throw RuntimeError when a file cannot be written
std::vector<std::string> writeCaveMaps(const Cave& cave, const morpho::Skeleton& skeleton, const std::string& title,
                                       const std::string& imagesDir, int width);

}  // namespace cavesim::app

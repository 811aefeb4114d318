/// @file ensemble_figures.h
/// @brief Figures of an ensemble of runs (`cavesim ensemble`): the histogram of one measure over
/// the members, and the plan-view map of the karstification probability.
///
/// Not a figure of the paper: the paper runs one cave per scenario. Drawn with the primitives of
/// render/image.h; no OpenVDB here.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/grid.h"
#include "render/image.h"

namespace cavesim::render {

/// A histogram of `values` (any unit) in `bins` equal bins from the smallest to the largest value,
/// with the median (solid) and the quartiles (dashed) marked, a box plot above the bars, the axis
/// in `unit`, and "n = …" in the title. An empty `values` gives a frame that says so.
/// @param width  pixels, 256–4096
/// @throw InternalError if width or bins is out of range
Image histogramFigure(const std::vector<double>& values, const std::string& title, const std::string& unit, int bins,
                      int width);

/// Plan view of a probability grid (values in [0, 1], index space, z up): each column shows the
/// largest probability along it (where a passage is most likely at any depth), x right, y up,
/// colour bar 0–1, axes in metres (`voxelSize` metres per voxel; `originX`, `originY` the world
/// position of the block's corner, printed under the map). `sources` and `sinks` (plan-view voxel
/// columns (i, j), index space) are drawn as red circles and blue squares.
/// @param width  pixels, 256–4096
/// @throw InternalError if width is out of range or the grid is empty
Image probabilityPlanFigure(const Grid3<float>& probability, double voxelSize, double originX, double originY,
                            const std::string& title, int width, const std::vector<std::array<double, 2>>& sources = {},
                            const std::vector<std::array<double, 2>>& sinks = {});

}  // namespace cavesim::render

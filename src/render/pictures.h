/// @file pictures.h
/// @brief 2D figures of the voxel state: stage-1 zones, stage-2 pressure and flow, snapshots.
///
/// All figures use the frames of render/view.h: a 3D block is shown from above (plan view,
/// x right, y up) and, where a figure has a second panel, from the front (x–z); a 2D section
/// (ny = 1) is shown as itself (x right, z up), like the paper's Figures 8 and 9. Pictures of the
/// same view and width line up with each other and with the ray-traced views of the cave.
/// Sources are red circles (S1, S2, ... in scenario order), sinks blue squares; every figure has
/// axes in metres, a scale bar and a legend or colour bar with values. No OpenVDB here.
#pragma once

#include <string>
#include <vector>

#include "render/image.h"
#include "sim/domain.h"
#include "sim/fractures.h"

namespace cavesim::render {

/// The zones figure of stage 1 (paper §3.1, Figures 5 and 6): each source's pressure zone in its
/// own colour (plan view: the zone holding most voxels of each column), protochannels drawn dark
/// on top (projected from all depths), zone borders, sources and sinks, a legend with each zone's
/// source, pressure and size. Written as PNG through a temporary file.
/// @throw InternalError if width is outside [64, 16384]; RuntimeError when the file cannot be written
void writeZonesPicture(const Domain& domain, const std::string& path, int width);
/// The zones figure as an image (writeZonesPicture without the file).
Image zonesPicture(const Domain& domain, int width);

/// imagesDir/pressure.png and imagesDir/flow.png. Pressure: the section (ny = 1) or, for a block,
/// a horizontal slice at the depth holding most cave voxels above a vertical x–z slice at the y
/// holding most; linear colour bar. Flow: the section, or the largest flow along each column
/// (plan) and row (x–z); logarithmic colour bar over four decades. The voxels of `mask` (the
/// cave) are outlined.
/// @throw InternalError if width is outside [64, 16384]; RuntimeError when a file cannot be written
void writeFieldPictures(const Domain& domain, const Grid3<std::uint8_t>& mask, const std::string& imagesDir, int width);
/// The pressure and flow figures as images (writeFieldPictures without the files).
Image pressurePicture(const Domain& domain, const Grid3<std::uint8_t>& mask, int width);
Image flowPicture(const Domain& domain, const Grid3<std::uint8_t>& mask, int width);

/// One stage-2 snapshot `width` pixels wide titled `title` (e.g. "iteration 120"). A section
/// (ny = 1) is drawn like the paper's Figure 8: the porosity (channels dark) with, under it,
/// pressure and flow. A block is drawn as a plan: the largest porosity of each column in greys
/// with the cave coloured by the height of its top.
/// @throw InternalError if width is outside [64, 16384]
Image stateFrame(const Domain& domain, const Grid3<std::uint8_t>& mask, const std::string& title, int width);

/// Frames laid out in `rows` rows (filled left to right, top to bottom) with a small white gap,
/// e.g. images/sequence.png with rows = 1.
/// @throw InternalError if `frames` is empty, a frame is empty or rows < 1
Image composeStrip(const std::vector<Image>& frames, int rows);

/// Stacks images top to bottom, each centred horizontally.
Image stackVertically(const std::vector<Image>& images);

/// The legend line of family `family` (0-based) in images/fractures.png: its disc count, measured
/// mean dip direction / dip (degrees) and concentration estimate. What report.json gives as null
/// is shown as "n/a": the orientation of a family with no disc, kappa of one with fewer than 2.
std::string fractureFamilyLabel(int family, const FractureFamilyStats& stats);

/// images/fractures.png: the fracture network in plan, each disc's outline projected onto the
/// horizontal plane (a steep disc is nearly its strike line) and lightly filled in its family's
/// colour, over the plan shadow of the cave (`mask`), with the sources and sinks; the legend gives
/// each family's disc count and measured mean dip direction / dip. Block metres, z up.
Image fracturesPicture(const Domain& domain, const Grid3<std::uint8_t>& mask, const FractureNetwork& network,
                       int width);
void writeFracturesPicture(const Domain& domain, const Grid3<std::uint8_t>& mask, const FractureNetwork& network,
                           const std::string& path, int width);

}  // namespace cavesim::render

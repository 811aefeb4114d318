/// @file cave_pictures.h
/// @brief Ray-traced pictures of the cave: plan, two sides and a perspective (images/*.png).
///
/// The cave's smooth surface (the level set of cave_mesh.h, at the mesh's iso value) is
/// ray-traced with OpenVDB's `LevelSetRayIntersector`, one ray per pixel through the cameras of
/// render/view.h, so these pictures line up with the 2D figures of the voxel state drawn at the
/// same width. Shading: the perspective is coloured by elevation (viridis, block base to top), the
/// plan and sides by depth along the view (warm = near, slate = far), each with a colour bar; diffuse and head lights,
/// dark outlines where the depth jumps. Overlays: the rock block's outline (hidden edges dashed in perspective), axes
/// in metres, a scale bar, sources (red, S1…) and sinks (blue). No OpenVDB type appears in this header.
#pragma once

#include <array>
#include <string>

#include "mesh/cave_mesh.h"
#include "render/image.h"
#include "render/view.h"
#include "sim/cave.h"

namespace cavesim::mesh {

/// The views, in the order `renderCaveViews` returns them.
inline constexpr std::array<render::View, 4> kCaveViews{render::View::kPerspective, render::View::kPlan,
                                                        render::View::kSideXZ, render::View::kSideYZ};

/// Renders the four views of the cave, each `width` pixels wide (height from the
/// block's proportions). An empty cave still gives the block, its sources and sinks and a note
/// "no cave". Deterministic for any thread count.
/// @throw InternalError if width is outside [64, 16384] or the options are bad
std::array<render::Image, 4> renderCaveViews(const Cave& cave, int width, const MeshOptions& options = {});

/// Writes imagesDir/perspective.png, plan.png, side_xz.png and side_yz.png (creating imagesDir),
/// each through a temporary name and a rename; for a 2D section (one voxel thick in y) only
/// side_xz.png, the section itself.
/// @throw InternalError on a bad width; RuntimeError when a file cannot be written
void writeCavePictures(const Cave& cave, const std::string& imagesDir, int width);

/// writeCaveMesh(cave, dir, options) and writeCavePictures(cave, imagesDir, width) sharing
/// one level set: the same files, about a fifth less time. `seconds` covers both.
/// @throw InternalError on a bad width or options; RuntimeError when a file cannot be written
/// @param built  when not null, receives the mesh written (as `toSurfaceMesh`, cave_mesh.h)
MeshStats writeCaveMeshAndPictures(const Cave& cave, const std::string& dir, const std::string& imagesDir, int width,
                                   const MeshOptions& options = {}, SurfaceMesh* built = nullptr);

}  // namespace cavesim::mesh

/// @file decorate.h
/// @brief A run's speleothems: the cave's surface resampled finer, grown (speleothems.h), and
/// written as cave_decorated.obj/.ply/.glb with growth pictures (images/speleo_*.png).
///
/// The fine level set is made from the smooth cave mesh (mesh/cave_mesh.h, the same surface as
/// cave.obj) at `SpeleothemOptions::voxelSize`, seeded relief is added to the downward-facing rock
/// (`roughness`), then growth runs for `years`. Pictures are z-buffered renderings of the grown
/// surface's mesh: the cave's perspective (the camera of render/view.h, as images/perspective.png)
/// and a close-up inside the cave on the longest stalactite, at `frames` evenly spaced times.
/// Space: world space, metres, z up.
#pragma once

#include <string>
#include <vector>

#include "mesh/cave_mesh.h"
#include "render/image.h"
#include "render/view.h"
#include "sim/cave.h"
#include "sim/options.h"
#include "speleo/speleothems.h"

namespace cavesim::speleo {

/// What a decoration produced, for the report.
struct DecorationSummary {
    std::vector<Stalactite> stalactites;  ///< on the final surface, longest grown first (measureGrowth)
    int steps = 0;
    double years = 0;
    double maxSpeed = 0;                ///< m/yr
    double voxelSize = 0;               ///< metres
    long levelSetVoxels = 0;            ///< active voxels of the fine level set at the end
    mesh::MeshStats mesh;               ///< of cave_decorated.obj
    std::vector<std::string> pictures;  ///< written, relative to the run folder
    double secondsGrowth = 0, secondsOutput = 0;
};

/// Decorates `cave` and writes `dir`/cave_decorated.obj, .ply, .glb and, when `images`,
/// `dir`/images/speleo_perspective_NN.png and speleo_closeup_NN.png (NN = frame).
/// An empty cave or `!options.drained` still writes the (undecorated) surface.
/// @throw RuntimeError when a file cannot be written
DecorationSummary decorateCave(const Cave& cave, const SpeleothemOptions& options, const std::string& dir,
                               int imageWidth, bool images);

/// Z-buffered picture of `mesh` through `camera` on a `width` × `height` canvas: diffuse and
/// head light, stone colour shaded by height between `zLow` and `zHigh` (metres).
render::Image renderMesh(const mesh::TriangleMesh& mesh, const render::Camera& camera, int width, int height,
                         double zLow, double zHigh);

}  // namespace cavesim::speleo

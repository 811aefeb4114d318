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

#include "core/progress.h"
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
    double maxSpeed = 0;                 ///< m/yr
    double voxelSize = 0;                ///< metres
    long levelSetVoxels = 0;             ///< active voxels of the fine level set at the end
    mesh::MeshStats mesh;                ///< of the decorated surface (cave_decorated.obj when written)
    std::vector<std::string> meshFiles;  ///< cave_decorated.obj, .ply, .glb when written, relative to the run folder
    std::vector<std::string> pictures;   ///< written, relative to the run folder
    bool emptyCave = false;              ///< nothing to decorate: no growth ran (`years` means nothing)
    /// Why nothing grew, or stopped growing before `options.years` (empty when it grew throughout).
    /// `years` is then still the years decorated: a surface on which nothing moves stays as it is.
    std::string note;
    double secondsGrowth = 0, secondsOutput = 0;
};

/// Decorates `cave` and writes, when `meshes`, `dir`/cave_decorated.obj, .ply, .glb and, when
/// `images`, `dir`/images/speleo_perspective_NN.png and speleo_closeup_NN.png (NN = frame).
/// `!options.drained` still writes the (undecorated) surface; an empty cave writes nothing.
/// `progress` is told "speleothems" and the years grown after every step (a safe point: it may
/// throw `Cancelled`, and nothing has been written then).
/// @throw RuntimeError when a file cannot be written
DecorationSummary decorateCave(const Cave& cave, const SpeleothemOptions& options, const std::string& dir,
                               int imageWidth, bool images, bool meshes, const ProgressFn& progress = {});

/// Z-buffered picture of `mesh` through `camera` on a `width` × `height` canvas: diffuse and
/// head light, stone colour shaded by height between `zLow` and `zHigh` (metres).
render::Image renderMesh(const mesh::TriangleMesh& mesh, const render::Camera& camera, int width, int height,
                         double zLow, double zHigh);

}  // namespace cavesim::speleo

/// @file cave_mesh.h
/// @brief The cave as a smooth, closed, consistently oriented triangle mesh (cave.obj, cave.ply).
///
/// The paper (Pytel & Mann, JCGT 2015, §5) shows its caves as voxels; later work criticises that
/// output as "a set of cubes". Here the cave voxels (`caveMask`, sim/cave.h) become a narrow-band
/// signed-distance level set (OpenVDB) on a grid `subdivision` times finer than the simulation
/// grid:
///  1. the cubes: `tools::topologyToLevelSet` puts the zero crossing on the voxel faces, refined
///     to the fine grid by trilinear interpolation;
///  2. the net: round capsules of radius `tubeRadius` along the links of a depth-weighted maximum
///     spanning forest of the 26-neighbour graph of cave voxels (through the middle of wide
///     passages, along thin ones; shallow branches pruned), united with the cubes;
///  3. constrained mean-curvature flow (`tools::LevelSetFilter::meanCurvature`, the net united
///     back after every step): it rounds the voxel staircase but cannot thin a channel below the
///     net nor pinch the cave apart, so every 26-connected piece of cave voxels stays one piece
///     and a one-voxel channel is a tube (at subdivision >= 2);
///  4. an outward offset so the surface encloses the cave voxels' volume again
///     (`preserveVolume`), applied as the iso value;
///  5. `tools::volumeToMesh` at `adaptivity`; faces reversed (OpenVDB winds them inward), quads
///     split along their shorter diagonal; OpenMesh collapses degenerate edges and writes OBJ and
///     PLY with vertex normals.
///
/// Space: meshes are in world space (metres); voxel (i, j, k) of the simulation grid is centred at
/// ((i, j, k) + 0.5)·voxelSize, so the block spans [0, n·voxelSize] on each axis. Normals point
/// out of the cave (into the rock). No OpenVDB or OpenMesh type appears in this header.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/grid.h"
#include "core/vec3.h"
#include "core/surface_mesh.h"
#include "sim/cave.h"
#include "sim/options.h"

namespace cavesim::mesh {

/// Options of the cave mesh. Defaults give a smooth, closed mesh of a 60×60×20 cave in well
/// under a second.
struct MeshOptions {
    /// kSmooth (cave.obj, cave.ply) or kVoxel (additionally cave_voxels.obj: the faces between
    /// cave and rock voxels, the paper's blocky look, for comparison).
    MeshStyle style = MeshStyle::kSmooth;
    /// Level-set voxels per simulation voxel edge, [1, 4]. 2 resolves a one-voxel tube with about
    /// eight vertices around; 3 is rounder and costs ~2.5× the time and memory; 1 is coarse (tubes
    /// of at least 0.9 voxel radius, pieces closer than two voxels may merge).
    int subdivision = 2;
    /// Half width of the narrow band, in level-set voxels, [3, 8].
    int halfWidth = 3;
    /// Radius of the net's capsules in simulation voxels, [0.25, 0.85] (raised to at least 0.9
    /// level-set voxels): the thinnest a channel can become.
    double tubeRadius = 0.45;
    /// Mean-curvature flow steps, [0, 100]; each advances the flow by (voxelSize/subdivision)²/3
    /// (OpenVDB's stable step). 0 keeps the cubes (with rounded edges) and the net as they are.
    int smoothingIterations = 6;
    /// Offset the surface outward (never inward) so the mesh encloses the cave voxels' volume
    /// (to about 1 %), undoing the shrinkage of the curvature flow on convex parts and the volume
    /// thin tubes lose to their polygons: first from the level set's measures, then refined by
    /// Newton steps on the mesh's own volume.
    bool preserveVolume = true;
    /// Largest outward offset of `preserveVolume`, in simulation voxels, [0, 1].
    double maxVolumeOffset = 0.5;
    /// `volumeToMesh` adaptivity, [0, 1]: 0 = uniform, well-shaped triangles; 0.1 gives ~30 %
    /// and 0.3 ~55 % fewer, larger triangles on flat parts (still closed and manifold).
    double adaptivity = 0.0;
};

/// Numbers describing a mesh (all from the triangles, see `measureMesh`).
struct MeshStats {
    long vertices = 0, faces = 0;
    double areaM2 = 0, volumeM3 = 0;  ///< surface area; signed enclosed volume (> 0 when outward)
    long eulerCharacteristic = 0;     ///< V − E + F (2 − 2·genus per closed component)
    bool closed = false, manifold = false;
    long components = 0;  ///< edge-connected pieces (closed shells: a rock pocket sealed
                          ///< inside the cave adds an inner shell)
    double seconds = 0;   ///< wall time of writeCaveMesh (0 from measureMesh)
};

/// A triangle mesh as plain arrays. Vertices in metres; triangles index `vertices`,
/// counter-clockwise seen from outside (right-hand normal points out).
struct TriangleMesh {
    std::vector<Vec3d> vertices;
    std::vector<std::array<int, 3>> triangles;
};

/// Meshes a voxel mask (1 = cave). Deterministic for a given mask and options.
/// @param mask      cave voxels; any extents (ny = 1 gives a thin closed slab along y)
/// @param voxelSize edge of a voxel in metres, > 0
/// @return the smooth closed mesh; empty when the mask has no cave voxel
/// @throw InternalError on a non-positive voxel size or options out of range
TriangleMesh buildCaveMesh(const Grid3<std::uint8_t>& mask, double voxelSize, const MeshOptions& options = {});

/// The paper's blocky look: one quad (two triangles) per face between a cave voxel and rock or
/// the outside of the block. Closed and outward; where voxels touch only along an edge or at a
/// corner the surface is not manifold there (as voxel surfaces are).
TriangleMesh buildVoxelMesh(const Grid3<std::uint8_t>& mask, double voxelSize);

/// Area, signed volume (divergence theorem), Euler characteristic over the vertices used,
/// closedness (every edge in exactly two triangles), manifoldness (every edge in at most two
/// triangles, traversed in opposite directions by the two, and the triangles around every
/// vertex forming a single fan) and edge-connected components.
MeshStats measureMesh(const TriangleMesh& mesh);

/// Meshes `caveMask(domain)` and writes `dir/cave.obj` and `dir/cave.ply` (binary PLY), with
/// vertex normals, in metres and world space (see file comment); with style "voxel" also
/// `dir/cave_voxels.obj`. Files are written under temporary names and renamed, so they appear
/// complete or not at all. An empty cave writes nothing and returns zero stats.
/// @throw InternalError on bad options; RuntimeError when a file cannot be written
/// @param built  when not null, receives the mesh written (as `toSurfaceMesh`), for the export
///               writers of src/formats; left empty for an empty cave
MeshStats writeCaveMesh(const Cave& cave, const std::string& dir, const MeshOptions& options = {},
                        SurfaceMesh* built = nullptr);

/// `mesh` in single precision with unit, area-weighted vertex normals (the normalised sum of the
/// unnormalised normals of the triangles at a vertex; (0, 0, 1) where that sum is zero): the
/// normals cave.obj and cave.ply carry. World space and metres are kept; triangles unchanged.
SurfaceMesh toSurfaceMesh(const TriangleMesh& mesh);

/// The smooth cave mesh of `cave` (what `writeCaveMesh` writes to cave.obj) as a `SurfaceMesh`,
/// without writing anything. Empty when the cave is.
/// @throw InternalError on bad options
SurfaceMesh buildCaveSurfaceMesh(const Cave& cave, const MeshOptions& options = {});

/// Writes `mesh` as OBJ or PLY (by the extension of `path`: ".obj" or ".ply") through OpenMesh,
/// with area-weighted vertex normals, via a temporary file and a rename.
/// @throw InternalError on an unknown extension; RuntimeError when the file cannot be written
void writeMeshFile(const TriangleMesh& mesh, const std::string& path);

/// Reads an OBJ or PLY file written by `writeMeshFile` (tests, tools).
/// @throw RuntimeError when the file is missing or unreadable
TriangleMesh readMeshFile(const std::string& path);

}  // namespace cavesim::mesh

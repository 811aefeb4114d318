/// @file mesh_formats.h
/// @brief The cave surface for game engines, the web and 3D printing: glTF 2.0 binary (cave.glb)
/// and binary STL (cave.stl).
///
/// Input: a `SurfaceMesh` (core/surface_mesh.h): metres, world space, z up, normals out of the
/// cave, as `mesh::buildCaveSurfaceMesh` or `mesh::writeCaveMesh(…, &built)` give it.
#pragma once

#include <string>

#include "core/surface_mesh.h"
#include "sim/options.h"

namespace cavesim::formats {

/// Which side of the cave wall the glTF normals face (`[output] mesh_normals`). kInward: triangles
/// re-wound and normals negated, so a renderer that culls back faces shows the walls from inside.
using NormalSide = MeshNormals;

/// Options of `writeGlb`.
struct GlbOptions {
    NormalSide normals = NormalSide::kOutward;
    std::string name = "cave";  ///< name of the glTF mesh and node
};

/// glTF 2.0 binary (one .glb: JSON chunk + BIN chunk) through tinygltf: one scene, one node, one
/// mesh of one triangle primitive with POSITION (float32, min/max set), NORMAL (float32, unit) and
/// uint32 indices, and one grey, single-sided PBR material. Units metres (glTF's own unit). glTF
/// is y-up, right-handed: positions and normals are rotated −90° about x,
/// (x, y, z) → (x, z, −y), so the cave's up (+z) is glTF's up (+y), east (+x) stays +x and north
/// (+y) becomes −z (glTF's "forward"). A rotation: lengths, angles and handedness are kept.
/// @param mesh  non-empty mesh (metres, world space, z up)
/// @param path  file to write (cave.glb); written through a temporary name and a rename
/// @throw InputError for an empty mesh or one whose normals do not match its vertices
/// @throw RuntimeError naming `path` when the file cannot be written
void writeGlb(const SurfaceMesh& mesh, const std::string& path, const GlbOptions& options = {});

/// Binary STL: 80-byte header ("cavesim cave: metres, world space, z up, normals out"), the
/// triangle count, then per triangle its unit face normal (computed from the vertices, outward),
/// the three vertices (float32, metres, world space, z up, as in the mesh: no axis change) and a
/// zero attribute word. STL has no unit field: readers must be told metres.
/// @throw InputError for an empty mesh; RuntimeError naming `path` when the file cannot be written
void writeStl(const SurfaceMesh& mesh, const std::string& path);

}  // namespace cavesim::formats

/// @file exports.h
/// @brief Every export file of a run in one call: `writeExports(inputs, dir, formats)`, with the
/// set of formats parsed from a comma list (`--formats glb,vtk,…` / `all`).
///
/// | format  | files                        | opened by                                   |
/// |---------|------------------------------|---------------------------------------------|
/// | `glb`   | cave.glb                     | Blender, three.js, game engines (glTF 2.0)  |
/// | `vtk`   | state.vti, skeleton.vtp      | ParaView, VTK (Python)                      |
/// | `stl`   | cave.stl                     | slicers, MeshLab, CAD                       |
/// | `svx`   | cave.svx                     | Survex (cavern, aven)                       |
/// | `th`    | cave.th                      | Therion                                     |
/// | `gocad` | cave.ts, skeleton.pl         | GOCAD/SKUA, geomodelling tools              |
/// | `csv`   | history.csv, branches.csv    | spreadsheets, pandas                        |
/// | `vdb`   | cave.vdb                     | pyopenvdb, Houdini, Blender (level set)     |
///
/// Default set (`kDefaultFormats`): glb, vtk, svx, csv — small files that open the cave in a web
/// or game viewer, ParaView, a cave-survey program and a spreadsheet. stl, th, gocad and vdb
/// (cave.vdb repeats state.vdb's grids) on request or with `all`.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/surface_mesh.h"
#include "formats/mesh_formats.h"
#include "mesh/cave_mesh.h"
#include "morpho/network.h"
#include "morpho/skeleton_graph.h"
#include "sim/cave.h"
#include "sim/domain.h"
#include "sim/stage2.h"

namespace cavesim::formats {

/// One export format (a group of files, see the file comment): `[output] formats`.
using Format = ExportFormat;

/// A set of formats, in the fixed order of `Format`.
struct FormatSet {
    std::uint32_t bits = 0;
    bool has(Format f) const { return bits & (1u << unsigned(f)); }
    FormatSet& add(Format f) {
        bits |= 1u << unsigned(f);
        return *this;
    }
    bool empty() const { return bits == 0; }
    friend bool operator==(const FormatSet& a, const FormatSet& b) { return a.bits == b.bits; }
};

/// The set of a scenario's `[output] formats` list.
FormatSet formatSet(const std::vector<Format>& list);

/// The formats of a set, in `Format` order.
std::vector<Format> formatList(const FormatSet& set);

/// The default `--formats` value (`OutputOptions::formats`' default).
inline constexpr const char* kDefaultFormats = "glb,vtk,svx,csv";

/// Parses a comma list of format names (glb, vtk, stl, svx, th, gocad, csv, vdb), `all`, or
/// `none` (nothing). Case-sensitive; spaces around names and repeats are allowed.
/// @throw InputError naming the unknown or empty entry and listing the allowed names
FormatSet parseFormatSet(const std::string& list);

/// The canonical comma list of a set ("glb,vtk,…" in `Format` order; "none" when empty).
std::string toString(const FormatSet& set);

/// What the exports are made from. Everything is borrowed; a null pointer means "not available":
/// the files that need it are skipped (not an error), see `writeExports`.
struct ExportInputs {
    const Domain* domain = nullptr;  ///< the final simulation state (grids, voxel size)
    /// The run's cave (`makeCave(domain, scenario.output.cave)`): the mask for LRUD, widths, the
    /// `cave` array and the mesh or level set built here. Null: `makeCave(*domain, kChannels)`.
    const Cave* cave = nullptr;
    const SurfaceMesh* mesh = nullptr;               ///< the cave mesh (metres, z up, normals out)
    const morpho::Skeleton* skeleton = nullptr;      ///< the centreline (metres)
    const morpho::NetworkCounts* network = nullptr;  ///< flow paths, for the branch roles (optional)
    const Stage2Result* stage2 = nullptr;            ///< the stage-2 history (history.csv)
    mesh::MeshOptions meshOptions;                   ///< the run's mesh options (mesh and level set when built here)
    GlbOptions glb;                                  ///< glTF normals side (`--mesh-normals inward|outward`)
    /// Build the mesh from the cave when `mesh` is null and a mesh format is asked for (costs a
    /// second meshing). Off: those files are skipped.
    bool buildMeshIfMissing = true;
};

/// Writes the files of `formats` into the existing directory `dir`, each through a temporary
/// name and a rename. A file whose inputs are missing or empty is skipped: no mesh (and none
/// built) or an empty one → no cave.glb, cave.stl, cave.ts; no skeleton or one without edges →
/// no skeleton.vtp, cave.svx, cave.th, skeleton.pl, branches.csv; no domain → no state.vti,
/// cave.vdb, and (without a cave either) no cave.svx, cave.th, branches.csv; no stage 2 → no
/// history.csv.
/// @return the names (relative to `dir`) of the files written, in the order of `Format`
/// @throw InputError on bad inputs (invalid skeleton, bad mesh options); RuntimeError naming
///        the file when one cannot be written
std::vector<std::string> writeExports(const ExportInputs& inputs, const std::string& dir, const FormatSet& formats);

}  // namespace cavesim::formats

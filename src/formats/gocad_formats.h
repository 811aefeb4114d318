/// @file gocad_formats.h
/// @brief GOCAD ASCII objects for geomodellers (SKUA-GOCAD, Move, GemPy, karstnet's PLine
/// readers): the cave surface as a TSurf (`cave.ts`) and the centreline as a PLine (`skeleton.pl`).
///
/// Both carry a GOCAD_ORIGINAL_COORDINATE_SYSTEM block: axes X Y Z in metres, ZPOSITIVE
/// Elevation (z up), world space as the simulation (x east, y north). Vertex ids are 1-based.
#pragma once

#include <string>

#include "core/surface_mesh.h"
#include "morpho/skeleton_graph.h"
#include "sim/domain.h"

namespace cavesim::formats {

/// `GOCAD TSurf 1`: one TFACE, a `VRTX id x y z` per vertex, a `TRGL a b c` per triangle (as
/// wound in the mesh: counter-clockwise seen from the rock), `END`.
/// @throw InputError for an empty mesh; RuntimeError naming `path` when it cannot be written
void writeGocadTSurf(const SurfaceMesh& mesh, const std::string& path, const std::string& name = "cave");

/// `GOCAD PLine 1`: one ILINE per connected piece of the skeleton, a `PVRTX id x y z radius
/// passage_id [flow pressure]` per node (PROPERTIES line names them; flow and pressure only with
/// a domain, the grid values at the node's voxel) and a `SEG a b` per skeleton edge, `END`.
/// Isolated nodes are left out. Node n has id n + 1.
/// @param domain  may be null
/// @throw InputError on an invalid skeleton; RuntimeError naming `path` when it cannot be written
void writeGocadPLine(const morpho::Skeleton& skeleton, const std::string& path, const Domain* domain = nullptr,
                     const std::string& name = "skeleton");

}  // namespace cavesim::formats

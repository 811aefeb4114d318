/// @file recharge.h
/// @brief Recharge (`[[recharge]]`): sinkholes, diffuse inputs and sinking streams on the land
/// surface, expanded into ordinary sources before stage 1.
///
/// Not in Pytel & Mann (2015), whose sources are placed by hand; the patterns it allows are those
/// karst geomorphology ties to recharge (Palmer 1991): point recharge through sinkholes, diffuse
/// recharge over an area, a sinking stream. Each entry becomes `SourceSpec`s at the land surface —
/// the block's top layer (z = nz − 1), or with a `[site] dem` the highest rock voxel of each column
/// (the highest whose centre is not above the DEM) — after the scenario's `[[source]]` entries (a
/// site's sinkholes come after them), so stages,
/// report and files see only sources. Positions are voxel (index) units. Random choices (where
/// the sinkholes are, where a diffuse input sits in its cell) come from an engine of their own per
/// entry, seeded from the scenario seed and the entry's index; the run's `Rng` is not touched.
#pragma once

#include <cstddef>
#include <vector>

#include "sim/scenario.h"

namespace cavesim {

/// The most sources a run may have, all kinds together (`[[source]]`, recharge inputs, a site's
/// sinkholes): stage 1 marches one zone per source.
constexpr std::size_t kMaxSources = 256;

/// The sources of every `[[recharge]]` entry of `scenario`, entry by entry, each with the entry's
/// line (docs/geology.md, "Recharge"):
/// - sinkholes: `count` columns of `area` drawn without replacement (a seeded shuffle), each at
///   least radius columns inside the area (others are passed over) and at least 2·radius + 1
///   columns (Chebyshev) from the ones taken before; each a box of
///   (2·radius + 1)² columns and radius + 1 layers hanging from the lowest land-surface voxel of
///   those columns (the top face without a DEM), of `pressure`;
/// - diffuse: `area` cut into cells of `spacing` columns (the last ones shorter); one one-voxel
///   input per cell at a seeded column of it, each of `pressure` / the number of cells;
/// - stream: one one-voxel input every `spacing` voxels of arc length along `points` from the
///   first point (the voxel nearest the point, lowered to its column's land-surface voxel where it
///   lies above it; repeats dropped), each of `pressure` / their number.
/// `perEntry`, when given, receives the number of sources of each entry.
/// @throw InputError when sinkholes do not fit in their area (validateRecharge says so first), or an
///   input's column is all air under a `[site] dem`
std::vector<SourceSpec> rechargeSources(const Scenario& scenario, std::vector<std::size_t>* perEntry = nullptr);

/// Every source of the run in the domain's order (source index i is `Domain::sourceVoxels[i]`):
/// the `[[source]]` entries, the recharge's inputs, then a loaded site's sinkholes.
/// @throw InputError as `rechargeSources`
std::vector<SourceSpec> allSources(const Scenario& scenario);

/// The highest layer of a column whose land surface lies at elevation `land` (world metres): the
/// highest voxel whose centre, `site.origin` z + (k + 0.5) · voxelSize, is not above it — the rule
/// that makes the voxels above the land air (domain.cpp); −1 when every voxel of the column is air.
int landSurfaceLayer(const Scenario& scenario, double land);

/// Checks every `[[recharge]]` entry against the block: an area inside the top face, `points`
/// only and at least two for a stream and inside the block, sinkholes that fit, at most 256
/// sources with the `[[source]]` entries, no input on a sink (or, once the site is loaded, on a
/// `[site] springs` voxel), no input on a column that a `[site] dem` leaves all air. Called by the
/// scenario check (without the site's data: inputs on the top layer) and again by
/// `site::loadSite` once the land surface is known.
/// @throw InputError naming the file, the key's line (the entry's when the file leaves the key out), the key, its value
/// and what is allowed
void validateRecharge(const Scenario& scenario);

/// Checks every `[[rock.fracture_family]]` entry against the block (sim/fractures.h): min_length
/// ≤ max_length, min_length and spacing at most the block's longest side, exactly one of spacing and
/// density, between 1 and 10⁶ discs.
/// @throw InputError naming the file, the key's line (the entry's when the file leaves the key out), the key, its value
/// and what is allowed
void validateFractureFamilies(const Scenario& scenario);

}  // namespace cavesim

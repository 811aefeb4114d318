/// @file connectivity.h
/// @brief Which sources open passages already join to a sink: the state stage 2 starts from
/// (Pytel & Mann, JCGT 2015, §3.1–3.2: protochannels "have not yet broken through to a sink"), and
/// the breadth-first search from the sinks that stage 2's own count (sim/stage2_steps.h) uses too.
#pragma once

#include <cstdint>
#include <deque>
#include <vector>

#include "sim/domain.h"

namespace cavesim {

/// Grows `reached` (one entry per voxel) from the voxels in `queue`, already marked, to every voxel
/// joined to them through voxels with a flag in `passes` (26-connectivity); empties `queue`.
void spreadThrough(const Domain& domain, std::uint8_t passes, std::deque<std::size_t>& queue,
                   std::vector<bool>& reached);

/// Every voxel joined to a sink voxel through voxels with a flag in `passes` (26-connectivity),
/// the sink voxels included: one entry per voxel.
std::vector<bool> reachedFromSinks(const Domain& domain, std::uint8_t passes);

/// Per source (scenario order): whether one of its voxels is marked in `reached`.
std::vector<bool> sourcesReached(const Domain& domain, const std::vector<bool>& reached);

/// Per source (scenario order): whether one of its voxels is joined to a sink voxel through
/// voxels flagged channel or protochannel (26-connectivity; source and sink voxels pass too, as
/// in stage 2's own count).
std::vector<bool> sourcesJoinedThroughPassages(const Domain& domain);

/// The number of sources joined to a sink through channel or protochannel voxels: after the
/// interim step (sim/stage2.h `prepareStage2`), before stage 2's first iteration, this is
/// `report.json` `stage2.connected_at_start`, 0 when stage 1 kept its gap to the sinks.
int sourcesConnectedAtStart(const Domain& domain);

}  // namespace cavesim

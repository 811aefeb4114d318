/// @file cave.h
/// @brief Which voxels are "the cave": the one definition meshing, pictures and the report share.
#pragma once

#include <cstdint>

#include "sim/domain.h"

namespace cavesim {

/// The cave mask: 1 where a voxel is cave, 0 elsewhere.
///
/// After stage 2 the cave is every voxel flagged channel (eroded to `[stage2] channel_threshold`);
/// with `CaveExtent::kWithProtochannels` (`[output] cave = "with_protochannels"`) the stage-1
/// protochannels too. When no voxel is channel (stage 2 disabled, or zero iterations), the
/// protochannel voxels stand in, so a stage-1-only run still has something to mesh and measure. A source voxel is an inlet:
/// it is cave when it touches (26-neighbour) a cave voxel, so a passage begins at its source and a
/// source inside a passage leaves no solid speck in it; a source no passage reached is not cave.
/// Sink voxels are outlets in the rock (often a whole wall) and are never cave.
inline Grid3<std::uint8_t> caveMask(const Domain& domain) {
    Grid3<std::uint8_t> mask(domain.dims, 0);
    bool any = false;
    for (std::size_t n = 0; n < domain.flags.size(); ++n) {
        if ((domain.flags[n] & kChannel) && !(domain.flags[n] & kSink)) {
            mask[n] = 1;
            any = true;
        }
    }
    if (!any || domain.caveExtent == CaveExtent::kWithProtochannels) {
        for (std::size_t n = 0; n < domain.flags.size(); ++n)
            if ((domain.flags[n] & kProtochannel) && !(domain.flags[n] & kSink)) mask[n] = 1;
    }
    // Inlets, tested against the passages alone (a source box does not grow through itself).
    std::vector<std::size_t> inlets;
    const Dims& d = domain.dims;
    for (const auto& voxels : domain.sourceVoxels)
        for (std::size_t v : voxels) {
            if (mask[v] || (domain.flags[v] & kSink)) continue;
            const Index3 p = d.coord(v);
            for (const NeighbourOffset& o : allNeighbours()) {
                const Index3 q{p.i + o.di, p.j + o.dj, p.k + o.dk};
                if (d.contains(q) && mask.at(q) && !(domain.flags[d.index(q)] & kSource)) {
                    inlets.push_back(v);
                    break;
                }
            }
        }
    for (std::size_t v : inlets) mask[v] = 1;
    return mask;
}

}  // namespace cavesim

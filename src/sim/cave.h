/// @file cave.h
/// @brief Which voxels are "the cave": the one definition meshing, pictures and the report share.
#pragma once

#include <cstdint>

#include "sim/domain.h"
#include "sim/options.h"

namespace cavesim {

/// The cave mask: 1 where a voxel is cave, 0 elsewhere.
///
/// After stage 2 the cave is every voxel flagged channel (eroded to the channel threshold); with
/// `CaveExtent::kWithProtochannels` the stage-1 protochannels too. When no voxel is channel (stage 2 disabled, or zero iterations), the
/// protochannel voxels stand in, so a stage-1-only run still has something to mesh and measure. A source voxel is an inlet:
/// it is cave when it touches (26-neighbour) a cave voxel, so a passage begins at its source and a
/// source inside a passage leaves no solid speck in it; a source no passage reached is not cave.
/// Sink voxels are outlets in the rock (often a whole wall) and are never cave.
inline Grid3<std::uint8_t> caveMask(const Domain& domain, CaveExtent extent) {
    Grid3<std::uint8_t> mask(domain.dims, 0);
    bool any = false;
    for (std::size_t n = 0; n < domain.flags.size(); ++n) {
        if ((domain.flags[n] & kChannel) && !(domain.flags[n] & kSink)) {
            mask[n] = 1;
            any = true;
        }
    }
    if (!any || extent == CaveExtent::kWithProtochannels) {
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

/// The cave as every consumer needs it (mesh, pictures, measurements): which voxels are cave, how
/// large a voxel is, and where the sources and sinks are. Computed once per run from the final
/// domain (`makeCave`) and passed down, so all outputs describe the same voxels.
struct Cave {
    Grid3<std::uint8_t> mask;  ///< 1 where a voxel is cave (caveMask)
    double voxelSize = 1.0;    ///< metres
    std::vector<std::vector<std::size_t>> sourceVoxels;  ///< linear indices per source, scenario order
    std::vector<std::vector<std::size_t>> sinkVoxels;    ///< linear indices per sink, scenario order
    const Dims& dims() const { return mask.dims; }
};

/// The cave of `domain` under `extent`, with its voxel size and terminals.
inline Cave makeCave(const Domain& domain, CaveExtent extent) {
    return Cave{caveMask(domain, extent), domain.voxelSize, domain.sourceVoxels, domain.sinkVoxels};
}

}  // namespace cavesim

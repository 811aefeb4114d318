/// @file cave.h
/// @brief Which voxels are "the cave": the one definition meshing, pictures and the report share.
#pragma once

#include <cstdint>

#include "sim/domain.h"

namespace cavesim {

/// The cave mask: 1 where a voxel is cave, 0 elsewhere.
///
/// After stage 2 the cave is every voxel flagged channel (eroded to `[stage2] channel_threshold`);
/// source and sink voxels are inlets and outlets, not passage, and are not included. When no voxel is channel (stage 2 disabled, or zero iterations), the
/// protochannel voxels stand in, so a stage-1-only run still has something to mesh and measure.
inline Grid3<std::uint8_t> caveMask(const Domain& domain) {
    Grid3<std::uint8_t> mask(domain.dims, 0);
    bool any = false;
    for (std::size_t n = 0; n < domain.flags.size(); ++n) {
        if (domain.flags[n] & kChannel) {
            mask[n] = 1;
            any = true;
        }
    }
    if (!any) {
        for (std::size_t n = 0; n < domain.flags.size(); ++n)
            if (domain.flags[n] & kProtochannel) mask[n] = 1;
    }
    return mask;
}

}  // namespace cavesim

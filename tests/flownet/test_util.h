// Helpers shared by the flownet test files.
#pragma once

#include <cstddef>
#include <numeric>
#include <vector>

#include "core/grid.h"
#include "flownet/flow_network.h"

namespace cavesim::flownet {

/// Every voxel of the box, in increasing index order: a zone that is the whole grid.
inline std::vector<std::size_t> allVoxels(const Dims& d) {
    std::vector<std::size_t> v(d.count());
    std::iota(v.begin(), v.end(), std::size_t(0));
    return v;
}

/// Options linking face neighbours only: the hand-computed cuts and routes of the tests.
inline FlowNetworkOptions face6() {
    FlowNetworkOptions o;
    o.links = LinkStencil::kFace6;
    return o;
}

}  // namespace cavesim::flownet

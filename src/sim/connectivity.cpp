/// @file connectivity.cpp
/// @brief Sources joined to sinks through open passages: one breadth-first search from the sinks.
#include "sim/connectivity.h"

#include <deque>

namespace cavesim {

std::vector<bool> sourcesJoinedThroughPassages(const Domain& dom) {
    const Dims& d = dom.dims;
    constexpr std::uint8_t kPasses = kChannel | kProtochannel | kSource | kSink;
    std::vector<std::uint8_t> seen(d.count(), 0);
    std::deque<std::size_t> queue;
    for (const auto& sink : dom.sinkVoxels)
        for (std::size_t v : sink)
            if (!seen[v]) {
                seen[v] = 1;
                queue.push_back(v);
            }
    while (!queue.empty()) {
        const std::size_t v = queue.front();
        queue.pop_front();
        const Index3 p = d.coord(v);
        for (const NeighbourOffset& o : allNeighbours()) {
            const int i = p.i + o.di, j = p.j + o.dj, k = p.k + o.dk;
            if (!d.contains(i, j, k)) continue;
            const std::size_t w = d.index(i, j, k);
            if (seen[w] || !(dom.flags[w] & kPasses)) continue;
            seen[w] = 1;
            queue.push_back(w);
        }
    }
    std::vector<bool> out;
    out.reserve(dom.sourceVoxels.size());
    for (const auto& source : dom.sourceVoxels) {
        bool joined = false;
        for (std::size_t v : source) joined = joined || seen[v];
        out.push_back(joined);
    }
    return out;
}

int sourcesConnectedAtStart(const Domain& domain) {
    int n = 0;
    for (bool joined : sourcesJoinedThroughPassages(domain)) n += joined ? 1 : 0;
    return n;
}

}  // namespace cavesim

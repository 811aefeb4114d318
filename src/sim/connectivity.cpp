/// @file connectivity.cpp
/// @brief Sources joined to sinks through open passages: one breadth-first search from the sinks.
#include "sim/connectivity.h"

namespace cavesim {

void spreadThrough(const Domain& dom, std::uint8_t passes, std::deque<std::size_t>& queue, std::vector<bool>& reached) {
    const Dims& d = dom.dims;
    while (!queue.empty()) {
        const std::size_t v = queue.front();
        queue.pop_front();
        const Index3 p = d.coord(v);
        for (const NeighbourOffset& o : allNeighbours()) {
            const int i = p.i + o.di, j = p.j + o.dj, k = p.k + o.dk;
            if (!d.contains(i, j, k)) continue;
            const std::size_t w = d.index(i, j, k);
            if (reached[w] || !(dom.flags[w] & passes)) continue;
            reached[w] = true;
            queue.push_back(w);
        }
    }
}

std::vector<bool> reachedFromSinks(const Domain& dom, std::uint8_t passes) {
    std::vector<bool> reached(dom.dims.count(), false);
    std::deque<std::size_t> queue;
    for (const auto& sink : dom.sinkVoxels)
        for (std::size_t v : sink)
            if (!reached[v]) {
                reached[v] = true;
                queue.push_back(v);
            }
    spreadThrough(dom, passes, queue, reached);
    return reached;
}

std::vector<bool> sourcesReached(const Domain& dom, const std::vector<bool>& reached) {
    std::vector<bool> out;
    out.reserve(dom.sourceVoxels.size());
    for (const auto& source : dom.sourceVoxels) {
        bool joined = false;
        for (std::size_t v : source) joined = joined || reached[v];
        out.push_back(joined);
    }
    return out;
}

std::vector<bool> sourcesJoinedThroughPassages(const Domain& dom) {
    return sourcesReached(dom, reachedFromSinks(dom, kChannel | kProtochannel | kSource | kSink));
}

int sourcesConnectedAtStart(const Domain& domain) {
    int n = 0;
    for (bool joined : sourcesJoinedThroughPassages(domain)) n += joined ? 1 : 0;
    return n;
}

}  // namespace cavesim

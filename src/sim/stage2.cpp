#include "sim/stage2.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "fastmarch/fast_marching.h"

namespace cavesim {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr std::uint8_t kOpen = kSource | kSink;
constexpr std::uint8_t kLowRate = kChannel | kProtochannel | kSource | kSink;

/// Neighbour offsets grouped so that each sum visits (−x, +x) as a pair, then the x = 0 one:
/// group g = (dj, dk) in a fixed order; slot 0 = di −1, slot 1 = di +1, slot 2 = di 0 (absent for
/// the centre group). The index into allNeighbours() of each entry is kept for offer storage.
struct PairedNeighbours {
    struct Entry {
        int di, dj, dk;
        double invLength;
        int slot;  ///< index in allNeighbours(); the opposite direction is 25 − slot
    };
    // 9 groups × 3 entries; the centre group (dj = dk = 0) has no x = 0 entry.
    std::array<std::array<Entry, 3>, 9> groups{};
    PairedNeighbours() {
        const auto& all = allNeighbours();
        auto slotOf = [&](int di, int dj, int dk) {
            for (int s = 0; s < 26; ++s)
                if (all[s].di == di && all[s].dj == dj && all[s].dk == dk) return s;
            return -1;
        };
        int g = 0;
        for (int dk = -1; dk <= 1; ++dk)
            for (int dj = -1; dj <= 1; ++dj, ++g) {
                for (int c = 0; c < 3; ++c) {
                    const int di = c == 0 ? -1 : (c == 1 ? 1 : 0);
                    const int s = slotOf(di, dj, dk);
                    const double len = std::sqrt(double(di * di + dj * dj + dk * dk));
                    groups[g][c] = Entry{di, dj, dk, len > 0 ? 1.0 / len : 0.0, s};
                }
            }
    }
};

const PairedNeighbours& paired() {
    static const PairedNeighbours p;
    return p;
}

/// Σ over the 26 neighbours of v of term(entry, neighbourIndex), paired −x/+x first.
/// Out-of-domain neighbours contribute nothing.
template <typename Term>
inline double pairedSum(const Dims& d, int i, int j, int k, Term&& term) {
    double total = 0;
    for (const auto& grp : paired().groups) {
        const int jj = j + grp[0].dj, kk = k + grp[0].dk;
        if (jj < 0 || kk < 0 || jj >= d.ny || kk >= d.nz) continue;
        const double a = (i > 0) ? term(grp[0], d.index(i - 1, jj, kk)) : 0.0;
        const double b = (i + 1 < d.nx) ? term(grp[1], d.index(i + 1, jj, kk)) : 0.0;
        double s = a + b;
        if (grp[2].slot >= 0) s += term(grp[2], d.index(i, jj, kk));
        total += s;
    }
    return total;
}

template <typename Body>
void forEachSlab(const Dims& d, Body&& body) {
    tbb::parallel_for(tbb::blocked_range<int>(0, d.nz * d.ny), [&](const tbb::blocked_range<int>& r) {
        for (int row = r.begin(); row != r.end(); ++row) {
            const int k = row / d.ny, j = row % d.ny;
            for (int i = 0; i < d.nx; ++i) body(i, j, k, d.index(i, j, k));
        }
    });
}

Grid3<float> rateField(const Domain& dom, const Stage2Settings& g) {
    Grid3<float> rate(dom.dims, float(g.pRate));
    for (std::size_t v = 0; v < rate.size(); ++v)
        if (dom.flags[v] & kLowRate) rate[v] = float(g.pRateChannel);
    return rate;
}

std::vector<fastmarch::Seed> sinkSeeds(const Domain& dom) {
    std::vector<fastmarch::Seed> seeds;
    for (const auto& sink : dom.sinkVoxels)
        for (std::size_t v : sink) seeds.push_back({v, 0.0, 0});
    return seeds;
}

/// Sources joined to a sink through channel voxels (26-connected through kChannel | kSource | kSink).
std::vector<bool> connectedSources(const Domain& dom) {
    const Dims& d = dom.dims;
    std::vector<std::uint8_t> seen(d.count(), 0);
    std::deque<std::size_t> queue;
    for (const auto& sink : dom.sinkVoxels)
        for (std::size_t v : sink)
            if (!seen[v]) {
                seen[v] = 1;
                queue.push_back(v);
            }
    const auto& nb = allNeighbours();
    while (!queue.empty()) {
        const std::size_t v = queue.front();
        queue.pop_front();
        const Index3 p = d.coord(v);
        for (const auto& o : nb) {
            const int i = p.i + o.di, j = p.j + o.dj, k = p.k + o.dk;
            if (!d.contains(i, j, k)) continue;
            const std::size_t w = d.index(i, j, k);
            if (seen[w] || !(dom.flags[w] & (kChannel | kSource | kSink))) continue;
            seen[w] = 1;
            queue.push_back(w);
        }
    }
    std::vector<bool> out;
    for (const auto& src : dom.sourceVoxels) {
        bool c = false;
        for (std::size_t v : src) c = c || seen[v];
        out.push_back(c);
    }
    return out;
}

}  // namespace

double stage2PressureCap(const Scenario& s) {
    double pmax = 0;
    for (const auto& src : s.sources) pmax = std::max(pmax, src.pressure);
    if (pmax <= 0) pmax = 1;
    const double scale = s.stage2.pressureScale > 0
                             ? s.stage2.pressureScale
                             : 2.0 * s.stage2.pRate * double(s.size[0] + s.size[1] + s.size[2]);
    return pmax * scale;
}

void prepareStage2(Domain& dom, const Scenario& s) {
    const float proto = float(s.stage2.protochannelPorosity);
    const float sourcePorosity = float(s.stage2.sourcePorosity);
    for (std::size_t v = 0; v < dom.porosity.size(); ++v) {
        float R = dom.porosity0[v];
        std::uint8_t& f = dom.flags[v];
        f &= std::uint8_t(~kChannel);
        if (f & kProtochannel) R = std::max(R, proto);
        if (f & kSink) R = 1.f;
        if (f & kSource) R = sourcePorosity;
        dom.porosity[v] = R;
    }
    std::fill(dom.water.data.begin(), dom.water.data.end(), 0.f);
    std::fill(dom.flow.data.begin(), dom.flow.data.end(), 0.f);
    std::fill(dom.pressure.data.begin(), dom.pressure.data.end(), 0.f);
}

Grid3<double> solvePressureFull(const Domain& dom, const Scenario& s) {
    fastmarch::EikonalField field;
    field.solve(dom.dims, rateField(dom, s.stage2), sinkSeeds(dom), stage2PressureCap(s));
    return field.value();
}

Stage2Result runStage2(Domain& dom, const Scenario& s, const ProgressFn& progress, const SnapshotFn& snapshot) {
    const auto t0 = Clock::now();
    const Stage2Settings& g = s.stage2;
    const Dims d = dom.dims;
    const std::size_t n = d.count();
    Stage2Result res;
    res.pressureCap = stage2PressureCap(s);
    res.sourceConnectedIteration.assign(dom.sourceVoxels.size(), std::nullopt);

    // Relative refill level of each source: the strongest source refills to full capacity,
    // a weaker one in proportion to its pressure.
    double pmax = 0;
    for (double p : dom.sourcePressure) pmax = std::max(pmax, p);
    std::vector<std::pair<std::size_t, double>> refill;
    for (std::size_t si = 0; si < dom.sourceVoxels.size(); ++si)
        for (std::size_t v : dom.sourceVoxels[si]) refill.push_back({v, dom.sourcePressure[si] / pmax});

    Grid3<float> rate = rateField(dom, g);
    fastmarch::EikonalField pressure;
    {
        const auto tp = Clock::now();
        pressure.solve(d, rate, sinkSeeds(dom), res.pressureCap);
        res.pressureSeconds += since(tp);
    }

    std::vector<double> water(n, 0.0);
    std::vector<double> scale(n, 0.0), norm(n, 0.0), accept(n, 0.0), fc(n, 0.0), fa(n, 0.0), upShare(n, 0.0);
    std::vector<std::size_t> changed;
    const bool proportional = g.weight == "proportional";
    double stored = 0;

    for (int it = 1; it <= g.iterations; ++it) {
        Stage2Record rec;
        rec.iteration = it;
        const double storedBefore = stored;
        const Grid3<double>& P = pressure.value();
        const auto tt = Clock::now();

        // Sources refill.
        for (const auto& [v, level] : refill) {
            const double target = level * dom.porosity[v];
            if (water[v] < target) {
                rec.injected += target - water[v];
                water[v] = target;
            }
        }

        // Phase 1 (Listing 1): every voxel's offers, from the state at the start of the iteration.
        // offer(v→u) = scale_v · weight(ΔP)/Σweight · (capacity_u − contents_u) for each lower-pressure
        // neighbour u with free capacity; scale_v ≤ 1 keeps the total within v's contents.
        // Offers are recomputed where needed (same expression, same bits) instead of stored.
        auto weightNum = [&](std::size_t v, std::size_t u, double invLength) {
            if (!(P[u] < P[v]) || !(dom.porosity[u] > water[u])) return 0.0;
            return proportional ? (P[v] - P[u]) * invLength : 1.0;
        };
        auto offer = [&](std::size_t v, std::size_t u, double invLength) {
            if (scale[v] == 0) return 0.0;
            const double num = weightNum(v, u, invLength);
            return num == 0 ? 0.0 : scale[v] * (num / norm[v]) * (double(dom.porosity[u]) - water[u]);
        };
        forEachSlab(d, [&](int i, int j, int k, std::size_t v) {
            scale[v] = 0;
            norm[v] = 0;
            const double w = water[v];
            if (w <= 0 || (dom.flags[v] & kSink)) return;
            norm[v] = pairedSum(d, i, j, k, [&](const PairedNeighbours::Entry& e, std::size_t u) {
                return weightNum(v, u, e.invLength);
            });
            if (norm[v] <= 0) return;
            const double total = pairedSum(d, i, j, k, [&](const PairedNeighbours::Entry& e, std::size_t u) {
                const double num = weightNum(v, u, e.invLength);
                return num == 0 ? 0.0 : (num / norm[v]) * (double(dom.porosity[u]) - water[u]);
            });
            scale[v] = total > w ? w / total : 1.0;
        });

        // Phase 2: each receiver accepts the same fraction of every offer it got.
        forEachSlab(d, [&](int i, int j, int k, std::size_t u) {
            const double incoming = pairedSum(d, i, j, k, [&](const PairedNeighbours::Entry& e, std::size_t v) {
                return offer(v, u, e.invLength);
            });
            const double freeCap = (dom.flags[u] & kSink) ? incoming : double(dom.porosity[u]) - water[u];
            accept[u] = incoming > freeCap ? std::max(0.0, freeCap) / incoming : 1.0;
        });

        // Phase 3: move the accepted water; f_c = water that left the voxel.
        forEachSlab(d, [&](int i, int j, int k, std::size_t v) {
            fc[v] = pairedSum(d, i, j, k, [&](const PairedNeighbours::Entry& e, std::size_t u) {
                return offer(v, u, e.invLength) * accept[u];
            });
            fa[v] = accept[v] * pairedSum(d, i, j, k, [&](const PairedNeighbours::Entry& e, std::size_t u) {
                return offer(u, v, e.invLength);
            });  // inflow; fa is reused for blending below
        });
        double drained = 0, moved = 0;
        for (std::size_t v = 0; v < n; ++v) {
            water[v] += fa[v] - fc[v];
            moved += fc[v];
            if (dom.flags[v] & kSink) {
                drained += water[v];
                water[v] = 0;
            }
        }
        rec.drained = drained;
        rec.flow = moved;
        res.transportSeconds += since(tt);

        // Flow blending (Eq. 2): each voxel passes f_c, split equally, to its uphill neighbours.
        const auto te = Clock::now();
        forEachSlab(d, [&](int i, int j, int k, std::size_t v) {
            const double pv = P[v];
            const double up = pairedSum(d, i, j, k, [&](const PairedNeighbours::Entry&, std::size_t u) {
                return P[u] > pv ? 1.0 : 0.0;
            });
            upShare[v] = up > 0 ? fc[v] / up : 0.0;
        });
        forEachSlab(d, [&](int i, int j, int k, std::size_t v) {
            const double pv = P[v];
            fa[v] = pairedSum(d, i, j, k, [&](const PairedNeighbours::Entry&, std::size_t u) {
                return P[u] < pv ? upShare[u] : 0.0;
            });
        });

        // Erosion (Eq. 1) and channel flags.
        double eroded = 0;
        changed.clear();
        const float threshold = float(g.channelThreshold);
        for (std::size_t v = 0; v < n; ++v) {
            std::uint8_t& f = dom.flags[v];
            if (f & kOpen) continue;
            const double flow = g.wa * fa[v] + fc[v];
            if (flow > 0) {
                const float R = dom.porosity[v];
                const double dR = std::min(g.w0 * std::pow(flow, g.m), 1.0 - double(R));
                if (dR > 0) {
                    dom.porosity[v] = std::min(1.f, float(double(R) + dR));
                    eroded += double(dom.porosity[v]) - double(R);
                }
            }
            if (!(f & kChannel) && dom.porosity[v] >= threshold && dom.porosity[v] > dom.porosity0[v]) {
                f |= kChannel;
                if (rate[v] > float(g.pRateChannel)) {
                    rate[v] = float(g.pRateChannel);
                    changed.push_back(v);
                }
            }
            dom.flow[v] = float(flow);
        }
        rec.eroded = eroded;
        res.erosionSeconds += since(te);

        // Pressure: propagate the decreases caused by new channel voxels.
        {
            const auto tp = Clock::now();
            rec.pressureUpdates = changed.empty() ? 0 : long(pressure.decrease(rate, changed));
            res.pressureSeconds += since(tp);
        }

        // Bookkeeping.
        stored = 0;
        long channels = 0;
        for (std::size_t v = 0; v < n; ++v) {
            stored += water[v];
            if (!std::isfinite(water[v])) throw RuntimeError("stage 2: water became non-finite");
            channels += (dom.flags[v] & kChannel) ? 1 : 0;
        }
        rec.stored = stored;
        rec.channelVoxels = channels;
        rec.balanceError = std::abs((stored - storedBefore) - (rec.injected - rec.drained));
        res.totalInjected += rec.injected;
        res.totalDrained += rec.drained;
        const std::vector<bool> conn = connectedSources(dom);
        for (std::size_t si = 0; si < conn.size(); ++si) {
            if (conn[si]) {
                ++rec.sourcesConnected;
                if (!res.sourceConnectedIteration[si]) res.sourceConnectedIteration[si] = it;
            }
        }
        if (rec.sourcesConnected > 0 && !res.breakthroughIteration) res.breakthroughIteration = it;
        res.history.push_back(rec);
        res.iterations = it;

        if (snapshot && std::find(g.snapshots.begin(), g.snapshots.end(), it) != g.snapshots.end()) {
            for (std::size_t v = 0; v < n; ++v) {
                dom.water[v] = float(water[v]);
                dom.pressure[v] = float(pressure.value()[v]);
            }
            snapshot(it, dom);
        }
        reportProgress(progress, "stage 2", it, g.iterations);
    }

    for (std::size_t v = 0; v < n; ++v) {
        dom.water[v] = float(water[v]);
        dom.pressure[v] = float(pressure.value()[v]);
    }
    const double net = stored - (res.totalInjected - res.totalDrained);
    res.waterBalanceRelError = res.totalInjected > 0 ? std::abs(net) / res.totalInjected : 0.0;
    if (!(res.waterBalanceRelError < 1e-6)) {
        throw RuntimeError("stage 2: water not conserved (relative error " + std::to_string(res.waterBalanceRelError) + ")");
    }
    res.seconds = since(t0);
    return res;
}

}  // namespace cavesim

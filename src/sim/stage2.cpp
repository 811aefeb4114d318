#include "sim/stage2.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <tuple>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "core/timer.h"
#include "fastmarch/fast_marching.h"
#include "sim/stage2_steps.h"

namespace cavesim {
namespace stage2 {
namespace {

constexpr std::uint8_t kOpen = kSource | kSink;
/// Voxels erosion never touches: the terminals, and rock that is not karst ([site]: air, insoluble).
constexpr std::uint8_t kNotEroded = kOpen | kInert;
constexpr std::uint8_t kLowRate = kChannel | kProtochannel | kSource | kSink;

/// Contents below this (porosity units, i.e. a 10⁻⁹ part of a voxel) stay where they are: a film
/// too thin to flow. Listing 1 moves all of a voxel's water every iteration, so water spreads
/// into ever thinner films far from the channels; leaving those films in place changes porosity
/// by less than w0 · 10⁻⁹ per iteration and halves the work of a typical run. Water is still
/// conserved exactly (the film is stored, and counted).
constexpr double kMinFlowingWater = 1e-9;


std::array<Slot, 26> makeSlots() {
    std::array<Slot, 26> slot{};
    int c = 0;
    for (int dk = -1; dk <= 1; ++dk)
        for (int dj = -1; dj <= 1; ++dj)
            for (int di : {-1, 1, 0}) {
                if (di == 0 && dj == 0 && dk == 0) continue;
                slot[std::size_t(c++)] = Slot{di, dj, dk, 1.0 / std::sqrt(double(di * di + dj * dj + dk * dk)), -1};
            }
    for (auto& a : slot)
        for (int b = 0; b < 26; ++b)
            if (slot[std::size_t(b)].di == -a.di && slot[std::size_t(b)].dj == -a.dj && slot[std::size_t(b)].dk == -a.dk)
                a.opposite = b;
    return slot;
}

/// One row (j, k) of the grid with the linear index of the start of each of its 9 neighbour rows
/// (j + dj, k + dk) in paired-group order, or −1 where that row lies outside the grid.
struct Row {
    int nx = 0;
    std::size_t index = 0;               ///< row number j + ny·k
    std::size_t first = 0;               ///< linear index of voxel (0, j, k)
    std::array<std::ptrdiff_t, 9> base{};
    Row(const Dims& d, int j, int k) : nx(d.nx), index(std::size_t(j) + std::size_t(d.ny) * std::size_t(k)) {
        first = d.index(0, j, k);
        int g = 0;
        for (int dk = -1; dk <= 1; ++dk)
            for (int dj = -1; dj <= 1; ++dj, ++g) {
                const int jj = j + dj, kk = k + dk;
                base[std::size_t(g)] =
                    (jj >= 0 && kk >= 0 && jj < d.ny && kk < d.nz) ? std::ptrdiff_t(d.index(0, jj, kk)) : -1;
            }
    }
    /// True when `flag` is set for this row or any of its 8 neighbour rows.
    bool anyAround(const std::vector<std::uint8_t>& flag) const {
        for (std::ptrdiff_t b : base)
            if (b >= 0 && flag[std::size_t(b) / std::size_t(nx)]) return true;
        return false;
    }
};

/// Σ over the 26 neighbours of voxel i of `row` inside the grid of term(slot, neighbourIndex), in
/// paired order. Out-of-grid neighbours contribute nothing.
template <typename Term>
inline double pairedSum(const Row& row, int i, Term&& term) {
    double total = 0;
    int s = 0;
    for (int g = 0; g < 9; ++g) {
        const std::ptrdiff_t b = row.base[std::size_t(g)];
        if (b >= 0) {
            const std::size_t at = std::size_t(b + i);
            const double lo = i > 0 ? term(s, at - 1) : 0.0;
            const double hi = i + 1 < row.nx ? term(s + 1, at + 1) : 0.0;
            double sum = lo + hi;
            if (g != 4) sum += term(s + 2, at);  // the centre group (dj, dk) = (0, 0) has no x = 0 entry
            total += sum;
        }
        s += g == 4 ? 2 : 3;
    }
    return total;
}

/// Σ of per-slot values in the same paired order as pairedSum (slots outside the grid hold 0,
/// and adding 0 is exact, so both sums agree bit for bit).
inline double pairedSlotSum(const std::array<double, 26>& x) {
    double total = 0;
    int s = 0;
    for (int g = 0; g < 9; ++g) {
        double sum = x[std::size_t(s)] + x[std::size_t(s + 1)];
        if (g != 4) sum += x[std::size_t(s + 2)];
        total += sum;
        s += g == 4 ? 2 : 3;
    }
    return total;
}

/// Calls body(row) for every row (j, k) of the grid, rows in parallel. Each call may write only
/// the voxels of its own row (and per-row flags), so the result does not depend on scheduling.
template <typename Body>
void forEachRow(const Dims& d, Body&& body) {
    tbb::parallel_for(tbb::blocked_range<int>(0, d.nz * d.ny), [&](const tbb::blocked_range<int>& r) {
        for (int rowIndex = r.begin(); rowIndex != r.end(); ++rowIndex) body(Row(d, rowIndex % d.ny, rowIndex / d.ny));
    });
}

std::vector<fastmarch::Seed> sinkSeeds(const Domain& dom) {
    std::vector<fastmarch::Seed> seeds;
    for (const auto& sink : dom.sinkVoxels)
        for (std::size_t v : sink) seeds.push_back({v, 0.0, 0});
    return seeds;
}

/// Sources joined to a sink through channel voxels (26-connected through kChannel | kSource | kSink).
std::vector<bool> connectedSourcesImpl(const Domain& dom) {
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

const std::array<Slot, 26>& slots() {
    static const std::array<Slot, 26> t = makeSlots();
    return t;
}

Stage2State::Stage2State(const Dims& d)
    : water(d.count(), 0.0),
      incoming(d.count(), 0.0),
      accept(d.count(), 0.0),
      fc(d.count(), 0.0),
      fa(d.count(), 0.0),
      upShare(d.count(), 0.0),
      offerStore(26 * d.count(), 0.0),
      hadOffers(d.count(), 0),
      wetRow(std::size_t(d.ny) * std::size_t(d.nz), 0),
      offerRow(std::size_t(d.ny) * std::size_t(d.nz), 0),
      flowRow(std::size_t(d.ny) * std::size_t(d.nz), 0) {}

Grid3<float> rateField(const Domain& dom, const Stage2Options& g) {
    Grid3<float> rate(dom.dims, float(g.pRate));
    for (std::size_t v = 0; v < rate.size(); ++v)
        if (dom.flags[v] & kLowRate) rate[v] = float(g.pRateChannel);
    return rate;
}

std::vector<bool> connectedSources(const Domain& dom) { return connectedSourcesImpl(dom); }

std::vector<Refill> refillLevels(const Domain& dom) {
    // The strongest source refills to full capacity, a weaker one in proportion to its pressure.
    double pmax = 0;
    for (double p : dom.sourcePressure) pmax = std::max(pmax, p);
    std::vector<Refill> refill;
    for (std::size_t si = 0; si < dom.sourceVoxels.size(); ++si)
        for (std::size_t v : dom.sourceVoxels[si]) refill.push_back({v, dom.sourcePressure[si] / pmax});
    return refill;
}

double refillSources(const Domain& dom, const std::vector<Refill>& levels, Stage2State& st) {
    double injected = 0;
    for (const auto& [v, level] : levels) {
        const double target = level * dom.porosity[v];
        if (st.water[v] < target) {
            injected += target - st.water[v];
            st.water[v] = target;
        }
        if (st.water[v] > 0) st.wetRow[v / std::size_t(dom.dims.nx)] = 1;
    }
    return injected;
}

void computeOffers(const Domain& dom, const Grid3<double>& P, TransportWeight weight, Stage2State& st) {
    const bool proportional = weight == TransportWeight::kProportional;
    std::array<double*, 26> offer{};
    std::array<double, 26> invLength{};
    for (int sl = 0; sl < 26; ++sl) {
        offer[std::size_t(sl)] = st.offer(sl);
        invLength[std::size_t(sl)] = slots()[std::size_t(sl)].invLength;
    }
    const std::vector<double>& water = st.water;
    // Rows far from any water are skipped: they neither offer nor receive.
    forEachRow(dom.dims, [&](const Row& row) {
        if (!st.wetRow[row.index] && !st.offerRow[row.index]) return;
        bool any = false;
        for (int i = 0; i < row.nx; ++i) {
            const std::size_t v = row.first + std::size_t(i);
            const double w = water[v];
            if (w < kMinFlowingWater || (dom.flags[v] & kSink)) {
                if (st.hadOffers[v]) {
                    for (double* o : offer) o[v] = 0;
                    st.hadOffers[v] = 0;
                }
                continue;
            }
            // Participants (Listing 1, lines 1–4) and their weights, gathered once.
            std::array<double, 26> num{}, freeCap{};
            const double pv = P[v];
            const double norm = pairedSum(row, i, [&](int sl, std::size_t u) {
                const double pu = P[u];
                if (!(pu < pv)) return 0.0;
                const double fr = double(dom.porosity[u]) - water[u];
                if (!(fr > 0)) return 0.0;
                const double x = proportional ? (pv - pu) * invLength[std::size_t(sl)] : 1.0;
                num[std::size_t(sl)] = x;
                freeCap[std::size_t(sl)] = fr;
                return x;
            });
            st.hadOffers[v] = 1;
            any = true;
            if (!(norm > 0)) {
                for (double* o : offer) o[v] = 0;
                continue;
            }
            // Shares weight · free capacity; their total, in the same paired order.
            std::array<double, 26> share{};
            for (std::size_t sl = 0; sl < 26; ++sl) share[sl] = num[sl] != 0 ? (num[sl] / norm) * freeCap[sl] : 0.0;
            const double total = pairedSlotSum(share);
            const double scale = total > w ? w / total : 1.0;  // never more in total than the contents
            for (std::size_t sl = 0; sl < 26; ++sl) offer[sl][v] = share[sl] * scale;
        }
        st.offerRow[row.index] = any ? 1 : 0;
    });
}

void computeAcceptance(const Domain& dom, Stage2State& st) {
    std::array<const double*, 26> offer{};
    std::array<int, 26> opposite{};
    for (int sl = 0; sl < 26; ++sl) {
        offer[std::size_t(sl)] = st.offer(sl);
        opposite[std::size_t(sl)] = slots()[std::size_t(sl)].opposite;
    }
    forEachRow(dom.dims, [&](const Row& row) {
        if (!row.anyAround(st.offerRow)) {
            std::fill_n(st.incoming.begin() + std::ptrdiff_t(row.first), row.nx, 0.0);
            std::fill_n(st.accept.begin() + std::ptrdiff_t(row.first), row.nx, 1.0);
            return;
        }
        for (int i = 0; i < row.nx; ++i) {
            const std::size_t u = row.first + std::size_t(i);
            // The offer reaching u from its neighbour v in direction s was made by v in the opposite direction.
            const double in =
                pairedSum(row, i, [&](int sl, std::size_t v) { return offer[std::size_t(opposite[std::size_t(sl)])][v]; });
            st.incoming[u] = in;
            const double freeCap = (dom.flags[u] & kSink) ? in : double(dom.porosity[u]) - st.water[u];
            // Round-off in moveWater may leave a voxel an ulp over full (freeCap < 0); nobody
            // offers to a full voxel, so in = 0 there, and 0 / 0 must not be taken: with nothing
            // incoming there is nothing to refuse.
            st.accept[u] = in > 0 && in > freeCap ? std::max(0.0, freeCap) / in : 1.0;
        }
    });
}

std::pair<double, double> moveWater(const Domain& dom, Stage2State& st) {
    std::array<const double*, 26> offer{};
    for (int sl = 0; sl < 26; ++sl) offer[std::size_t(sl)] = st.offer(sl);
    forEachRow(dom.dims, [&](const Row& row) {
        bool any = false;
        for (int i = 0; i < row.nx; ++i) {
            const std::size_t v = row.first + std::size_t(i);
            st.fc[v] = st.offerRow[row.index] && st.hadOffers[v]
                           ? pairedSum(row, i, [&](int sl, std::size_t u) { return offer[std::size_t(sl)][v] * st.accept[u]; })
                           : 0.0;
            any = any || st.fc[v] > 0;
        }
        st.flowRow[row.index] = any ? 1 : 0;
    });
    double drained = 0, moved = 0;
    std::fill(st.wetRow.begin(), st.wetRow.end(), 0);
    const std::size_t n = st.water.size();
    for (std::size_t v = 0; v < n; ++v) {
        st.water[v] += st.accept[v] * st.incoming[v] - st.fc[v];
        moved += st.fc[v];
        if (dom.flags[v] & kSink) {
            drained += st.water[v];
            st.water[v] = 0;
        }
        if (st.water[v] > 0) st.wetRow[v / std::size_t(dom.dims.nx)] = 1;
    }
    return {moved, drained};
}

void blendFlow(const Domain& dom, const Grid3<double>& P, FlowBlending blending, Stage2State& st) {
    const bool split = blending == FlowBlending::kSplit;
    if (split) forEachRow(dom.dims, [&](const Row& row) {
        for (int i = 0; i < row.nx; ++i) {
            const std::size_t v = row.first + std::size_t(i);
            if (st.fc[v] == 0) {
                st.upShare[v] = 0;
                continue;
            }
            const double pv = P[v];
            const double up = pairedSum(row, i, [&](int, std::size_t u) { return P[u] > pv ? 1.0 : 0.0; });
            st.upShare[v] = up > 0 ? st.fc[v] / up : 0.0;
        }
    });
    forEachRow(dom.dims, [&](const Row& row) {
        if (!row.anyAround(st.flowRow)) {
            std::fill_n(st.fa.begin() + std::ptrdiff_t(row.first), row.nx, 0.0);
            return;
        }
        for (int i = 0; i < row.nx; ++i) {
            const std::size_t v = row.first + std::size_t(i);
            const double pv = P[v];
            if (split) {
                st.fa[v] = pairedSum(row, i, [&](int, std::size_t u) { return P[u] < pv ? st.upShare[u] : 0.0; });
            } else {
                double strongest = 0;  // max is order-free: mirror symmetry and determinism hold
                pairedSum(row, i, [&](int, std::size_t u) {
                    if (P[u] < pv) strongest = std::max(strongest, st.fc[u]);
                    return 0.0;
                });
                st.fa[v] = strongest;
            }
        }
    });
}

double erode(Domain& dom, const Stage2Options& g, const Stage2State& st, Grid3<float>& rate,
             std::vector<std::size_t>& newChannel) {
    double eroded = 0;
    const float threshold = float(g.channelThreshold);
    const std::size_t n = dom.dims.count();
    for (std::size_t v = 0; v < n; ++v) {
        std::uint8_t& f = dom.flags[v];
        if (f & kNotEroded) continue;
        const double flow = g.wa * st.fa[v] + st.fc[v];
        if (flow > 0) {
            const float R = dom.porosity[v];
            const double dR = std::min(g.w0 * (g.m == 1.0 ? flow : std::pow(flow, g.m)), 1.0 - double(R));
            if (dR > 0) {
                dom.porosity[v] = std::min(1.f, float(double(R) + dR));
                eroded += double(dom.porosity[v]) - double(R);
            }
        }
        if (!(f & kChannel) && dom.porosity[v] >= threshold && dom.porosity[v] > dom.porosity0[v]) {
            f |= kChannel;
            if (rate[v] > float(g.pRateChannel)) {
                rate[v] = float(g.pRateChannel);
                newChannel.push_back(v);
            }
        }
        dom.flow[v] = float(flow);
    }
    return eroded;
}

std::size_t updatePressure(fastmarch::EikonalField& pressure, const Grid3<float>& rate,
                           const std::vector<std::size_t>& newChannel) {
    return newChannel.empty() ? 0 : pressure.decrease(rate, newChannel);
}

std::pair<double, long> waterAndChannels(const Domain& dom, const Stage2State& st, const Grid3<double>& pressure,
                                         int iteration) {
    double stored = 0;
    long channels = 0;
    bool finite = true;
    const std::size_t n = st.water.size();
    for (std::size_t v = 0; v < n; ++v) {
        stored += st.water[v];
        finite = finite && std::isfinite(st.water[v]) && std::isfinite(dom.flow[v]) && std::isfinite(pressure[v]);
        channels += (dom.flags[v] & kChannel) ? 1 : 0;
    }
    if (finite) return {stored, channels};
    // Name the quantity that went bad first, in cause-before-effect order, and its first voxel.
    const auto fail = [&](const char* name, std::size_t v, double x) {
        const Index3 p = dom.dims.coord(v);
        throw RuntimeError("stage 2, iteration " + std::to_string(iteration) + ": " + name + " became non-finite (" +
                           std::to_string(x) + ") at voxel (" + std::to_string(p.i) + ", " + std::to_string(p.j) +
                           ", " + std::to_string(p.k) + ")");
    };
    const std::pair<const char*, const std::vector<double>*> fields[] = {
        {"accept", &st.accept}, {"incoming water", &st.incoming}, {"outflow f_c", &st.fc},
        {"water", &st.water},   {"blended flow f_a", &st.fa},     {"pressure", &pressure.data}};
    for (const auto& [name, x] : fields)
        for (std::size_t v = 0; v < n; ++v)
            if (!std::isfinite((*x)[v])) fail(name, v, (*x)[v]);
    for (std::size_t v = 0; v < n; ++v)
        if (!std::isfinite(dom.porosity[v])) fail("porosity", v, dom.porosity[v]);
    for (std::size_t v = 0; v < n; ++v)
        if (!std::isfinite(dom.flow[v])) fail("flow", v, dom.flow[v]);
    throw RuntimeError("stage 2, iteration " + std::to_string(iteration) + ": state became non-finite");
}

}  // namespace stage2

using namespace stage2;


double stage2PressureCap(const Domain& dom, const Stage2Options& g) {
    double pmax = 0;
    for (double p : dom.sourcePressure) pmax = std::max(pmax, p);
    if (pmax <= 0) pmax = 1;
    const double scale = g.pressureScale > 0 ? g.pressureScale
                                             : 2.0 * g.pRate * double(dom.dims.nx + dom.dims.ny + dom.dims.nz);
    return pmax * scale;
}

void prepareStage2(Domain& dom, const Stage2Options& g) {
    const float proto = float(g.protochannelPorosity);
    const float sourcePorosity = float(g.sourcePorosity);
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

Grid3<double> solvePressureFull(const Domain& dom, const Stage2Options& g) {
    fastmarch::EikonalField field;
    field.solve(dom.dims, rateField(dom, g), sinkSeeds(dom), stage2PressureCap(dom, g), fastmarch::Stencil::kAvalanche26);
    return field.value();
}

Stage2Result runStage2(Domain& dom, const Stage2Options& g, const ProgressFn& progress, const SnapshotFn& snapshot) {
    const Stopwatch t0;
    const Dims d = dom.dims;
    const std::size_t n = d.count();
    Stage2Result res;
    res.pressureCap = stage2PressureCap(dom, g);
    res.sourceConnectedIteration.assign(dom.sourceVoxels.size(), std::nullopt);
    const std::vector<Refill> refill = refillLevels(dom);

    Grid3<float> rate = rateField(dom, g);
    fastmarch::EikonalField pressure;
    {
        const Stopwatch tp;
        pressure.solve(d, rate, sinkSeeds(dom), res.pressureCap, fastmarch::Stencil::kAvalanche26);
        res.pressureSeconds += tp.seconds();
    }

    Stage2State st(d);
    std::vector<std::size_t> changed;
    double stored = 0;

    for (int it = 1; it <= g.iterations; ++it) {
        Stage2Record rec;
        rec.iteration = it;
        const double storedBefore = stored;
        const Grid3<double>& P = pressure.value();

        const Stopwatch tt;
        rec.injected = refillSources(dom, refill, st);
        computeOffers(dom, P, g.weight, st);
        computeAcceptance(dom, st);
        std::tie(rec.flow, rec.drained) = moveWater(dom, st);
        res.transportSeconds += tt.seconds();

        const Stopwatch te;
        blendFlow(dom, P, g.blending, st);
        changed.clear();
        rec.eroded = erode(dom, g, st, rate, changed);
        res.erosionSeconds += te.seconds();

        // Pressure: propagate the decreases caused by new channel voxels.
        {
            const Stopwatch tp;
            rec.pressureUpdates = long(updatePressure(pressure, rate, changed));
            res.pressureSeconds += tp.seconds();
        }

        // Bookkeeping.
        std::tie(stored, rec.channelVoxels) = waterAndChannels(dom, st, P, it);
        rec.stored = stored;
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
                dom.water[v] = float(st.water[v]);
                dom.pressure[v] = float(pressure.value()[v]);
            }
            snapshot(it, dom);
        }
        reportProgress(progress, "stage 2", it, g.iterations);
    }

    for (std::size_t v = 0; v < n; ++v) {
        dom.water[v] = float(st.water[v]);
        dom.pressure[v] = float(pressure.value()[v]);
    }
    const double net = stored - (res.totalInjected - res.totalDrained);
    res.waterBalanceRelError = res.totalInjected > 0 ? std::abs(net) / res.totalInjected : 0.0;
    if (!(res.waterBalanceRelError < 1e-6)) {
        throw RuntimeError("stage 2: water not conserved (relative error " + std::to_string(res.waterBalanceRelError) + ")");
    }
    res.seconds = t0.seconds();
    return res;
}

}  // namespace cavesim

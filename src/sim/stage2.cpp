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
#include "core/vec3.h"
#include "fastmarch/fast_marching.h"
#include "sim/connectivity.h"
#include "sim/stage2_checkpoint.h"
#include "sim/stage2_steps.h"

namespace cavesim {
namespace stage2 {
namespace {

constexpr std::uint8_t kOpen = kSource | kSink;
/// Voxels erosion never touches: the terminals, and rock that is not karst ([site]: air, insoluble).
constexpr std::uint8_t kNotEroded = kOpen | kInert;
constexpr std::uint8_t kLowRate = kChannel | kProtochannel | kSource | kSink;
/// Voxels water conducts through from a source to a sink (what counts as connected).
constexpr std::uint8_t kConducting = kChannel | kSource | kSink;

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
            if (slot[std::size_t(b)].di == -a.di && slot[std::size_t(b)].dj == -a.dj &&
                slot[std::size_t(b)].dk == -a.dk)
                a.opposite = b;
    return slot;
}

/// One active tile, as the loops over it see it.
struct TileCtx {
    std::size_t slot = 0;
    int i0 = 0, j0 = 0, k0 = 0;  ///< first voxel
    int ni = 0, nj = 0, nk = 0;  ///< extent inside the grid (≤ 8)
    std::size_t base = 0;        ///< pool index of local voxel 0
    const std::array<std::int64_t, 27>* nb = nullptr;
};

/// The tile id of voxel v.
std::uint32_t tileOf(const Stage2State& st, std::size_t v) {
    const Index3 p = st.dims.coord(v);
    return std::uint32_t(p.i / kTileSize + st.tilesX * (p.j / kTileSize + st.tilesY * (p.k / kTileSize)));
}

/// The tile coordinates (ti, tj, tk) of tile id t.
Index3 tileCoord(const Stage2State& st, std::uint32_t t) {
    return {int(t % std::uint32_t(st.tilesX)), int((t / std::uint32_t(st.tilesX)) % std::uint32_t(st.tilesY)),
            int(t / (std::uint32_t(st.tilesX) * std::uint32_t(st.tilesY)))};
}

/// Calls fn(n, tile) for the 27 tiles around tile t (itself included), n = (dx+1) + 3(dy+1) + 9(dz+1)
/// in increasing order; tile is −1 outside the grid.
template <typename Fn>
void forEachTileAround(const Stage2State& st, std::uint32_t t, Fn&& fn) {
    const Index3 c = tileCoord(st, t);
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int a = c.i + dx, b = c.j + dy, e = c.k + dz;
                const bool inside = a >= 0 && b >= 0 && e >= 0 && a < st.tilesX && b < st.tilesY && e < st.tilesZ;
                fn(std::size_t((dx + 1) + 3 * (dy + 1) + 9 * (dz + 1)),
                   inside ? std::int64_t(a + st.tilesX * (b + st.tilesY * e)) : std::int64_t(-1));
            }
}

TileCtx tileCtx(const Stage2State& st, std::size_t slot) {
    const Index3 t = tileCoord(st, st.activeTiles[slot]);
    TileCtx c;
    c.slot = slot;
    c.i0 = t.i * kTileSize;
    c.j0 = t.j * kTileSize;
    c.k0 = t.k * kTileSize;
    c.ni = std::min(kTileSize, st.dims.nx - c.i0);
    c.nj = std::min(kTileSize, st.dims.ny - c.j0);
    c.nk = std::min(kTileSize, st.dims.nz - c.k0);
    c.base = slot * kTileVoxels;
    c.nb = &st.neighbourBase[slot];
    return c;
}

/// Pool index of the voxel at tile-local (a, b, e), each in [−1, 8] (a neighbour of a local
/// voxel), or −1 when its tile is inactive.
inline std::int64_t nbPool(const TileCtx& c, int a, int b, int e) {
    const std::int64_t base = (*c.nb)[std::size_t(((a >> 3) + 1) + 3 * ((b >> 3) + 1) + 9 * ((e >> 3) + 1))];
    return base < 0 ? -1 : base + (a & 7) + 8 * ((b & 7) + 8 * (e & 7));
}

/// Calls body(ctx) for every active tile, tiles in parallel. Each call may write only the voxels
/// of its own tile, so the result does not depend on scheduling.
template <typename Body>
void forEachTile(const Stage2State& st, Body&& body) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, st.activeTiles.size()),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t s = r.begin(); s != r.end(); ++s) body(tileCtx(st, s));
                      });
}

/// Calls fn(v, pool, li, lj, lk) for every voxel of a tile.
template <typename Fn>
inline void forEachVoxel(const Dims& d, const TileCtx& c, Fn&& fn) {
    for (int lk = 0; lk < c.nk; ++lk)
        for (int lj = 0; lj < c.nj; ++lj) {
            const std::size_t row = d.index(c.i0, c.j0 + lj, c.k0 + lk);
            const std::size_t prow = c.base + std::size_t(8 * (lj + 8 * lk));
            for (int li = 0; li < c.ni; ++li) fn(row + std::size_t(li), prow + std::size_t(li), li, lj, lk);
        }
}

/// Calls fn(v, pool, li, lj, lk) for the voxels of a tile whose bit is set in `mask`.
template <typename Fn>
inline void forEachMasked(const Dims& d, const TileCtx& c, const TileMask& mask, Fn&& fn) {
    for (int r = 0; r < 64; ++r) {
        unsigned bits = mask[std::size_t(r)];
        if (!bits) continue;
        const int lj = r & 7, lk = r >> 3;
        const std::size_t row = d.index(c.i0, c.j0 + lj, c.k0 + lk);
        const std::size_t prow = c.base + std::size_t(r * 8);
        while (bits) {
            const int li = __builtin_ctz(bits);
            bits &= bits - 1;
            fn(row + std::size_t(li), prow + std::size_t(li), li, lj, lk);
        }
    }
}

/// Σ over the 26 neighbours u of the voxel at tile-local (li, lj, lk) (linear index v) inside the
/// grid of term(slot, u, poolOf(u)), in paired order (−x, +x, then x = 0 per (dj, dk) group).
/// Out-of-grid neighbours contribute nothing. With `senders` (the tile's sender mask), a term must
/// be +0 at every neighbour that does not send this iteration: groups of three such neighbours
/// inside the tile are skipped (adding +0 to a sum of non-negative terms changes no bit).
template <typename Term>
inline double pairedSum(const Dims& d, const TileCtx& c, int li, int lj, int lk, std::size_t v, Term&& term,
                        const TileMask* senders = nullptr) {
    const int i = c.i0 + li, j = c.j0 + lj, k = c.k0 + lk;
    const std::ptrdiff_t sy = d.nx, sz = std::ptrdiff_t(d.nx) * d.ny;
    double total = 0;
    int s = 0;
    if (li > 0 && lj > 0 && lk > 0 && li + 1 < c.ni && lj + 1 < c.nj && lk + 1 < c.nk) {
        // Inside the tile and the grid: every neighbour is in this tile, at fixed offsets. The
        // same terms in the same order as below.
        const std::int64_t p = std::int64_t(c.base) + li + 8 * (lj + 8 * lk);
        for (int g = 0; g < 9; ++g) {
            const int dj = g % 3 - 1, dk = g / 3 - 1;
            if (senders && !(((*senders)[std::size_t(lj + dj + 8 * (lk + dk))] >> (li - 1)) & 7u)) {
                s += g == 4 ? 2 : 3;  // no sender among the group's three voxels: every term is +0
                continue;
            }
            const std::size_t at = std::size_t(std::ptrdiff_t(v) + dj * sy + dk * sz);
            const std::int64_t q = p + 8 * dj + 64 * dk;
            const double lo = term(s, at - 1, q - 1);
            const double hi = term(s + 1, at + 1, q + 1);
            double sum = lo + hi;
            if (g != 4) sum += term(s + 2, at, q);
            total += sum;
            s += g == 4 ? 2 : 3;
        }
        return total;
    }
    for (int g = 0; g < 9; ++g) {
        const int dj = g % 3 - 1, dk = g / 3 - 1;
        const int jj = j + dj, kk = k + dk;
        if (jj >= 0 && kk >= 0 && jj < d.ny && kk < d.nz) {
            const std::size_t at = std::size_t(std::ptrdiff_t(v) + dj * sy + dk * sz);
            const double lo = i > 0 ? term(s, at - 1, nbPool(c, li - 1, lj + dj, lk + dk)) : 0.0;
            const double hi = i + 1 < d.nx ? term(s + 1, at + 1, nbPool(c, li + 1, lj + dj, lk + dk)) : 0.0;
            double sum = lo + hi;
            if (g != 4) sum += term(s + 2, at, nbPool(c, li, lj + dj, lk + dk));  // the centre group has no x = 0 entry
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

/// Listing 1's offer from a sender (pressure pv, norm nv > 0, scale sc) to a neighbour (pressure
/// pu, free capacity fr) at 1/distance invLength: exactly the arithmetic of the sender-side share.
inline double offerValue(double pv, double nv, double sc, double pu, double fr, double invLength, bool proportional) {
    if (!(pu < pv) || !(fr > 0)) return 0.0;
    const double num = proportional ? (pv - pu) * invLength : 1.0;
    return (num != 0 ? (num / nv) * fr : 0.0) * sc;
}

/// 1 / |offset| of each slot, copied out of `slots()` for the inner loops.
std::array<double, 26> invLengths() {
    std::array<double, 26> out{};
    for (std::size_t sl = 0; sl < 26; ++sl) out[sl] = slots()[sl].invLength;
    return out;
}

/// Whether the 0-based `index` is in the 1-based `list` (empty = all).
bool listed(const std::vector<int>& list, std::size_t index) {
    return list.empty() || std::find(list.begin(), list.end(), int(index + 1)) != list.end();
}

/// The voxels of the sinks in `sinks` (1-based; empty = all) as pressure seeds.
std::vector<fastmarch::Seed> sinkSeeds(const Domain& dom, const std::vector<int>& sinks = {}) {
    std::vector<fastmarch::Seed> seeds;
    for (std::size_t si = 0; si < dom.sinkVoxels.size(); ++si)
        if (listed(sinks, si))
            for (std::size_t v : dom.sinkVoxels[si]) seeds.push_back({v, 0.0, 0});
    return seeds;
}

}  // namespace

const std::array<Slot, 26>& slots() {
    static const std::array<Slot, 26> t = makeSlots();
    return t;
}

namespace {

/// Whether any voxel of a tile mask is set.
inline bool anyBit(const TileMask& mask) {
    std::uint8_t any = 0;
    for (std::uint8_t b : mask) any |= b;
    return any != 0;
}

/// Sets or clears the flowing bit of the tile-local voxel (li, lj, lk) from its water.
inline void setFlowing(TileMask& mask, int li, int lj, int lk, double water) {
    std::uint8_t& row = mask[std::size_t(lj + 8 * lk)];
    const std::uint8_t bit = std::uint8_t(1u << li);
    row = water >= kMinFlowingWater ? std::uint8_t(row | bit) : std::uint8_t(row & ~bit);
}

/// What a tile's voxels hold, read from `water` (by tile id; needs no slot, so a tile being
/// activated can ask): their water, an order-free sum, and the voxels holding at least
/// kMinFlowingWater.
struct TileContents {
    ExactSum water;
    TileMask flowing{};
};
TileContents contentsOfTile(const Stage2State& st, std::uint32_t tile) {
    const Dims& d = st.dims;
    const Index3 t = tileCoord(st, tile);
    const int i0 = t.i * kTileSize, j0 = t.j * kTileSize, k0 = t.k * kTileSize;
    TileContents out;
    for (int k = k0; k < std::min(d.nz, k0 + kTileSize); ++k)
        for (int j = j0; j < std::min(d.ny, j0 + kTileSize); ++j)
            for (int i = i0; i < std::min(d.nx, i0 + kTileSize); ++i) {
                const double w = st.water[d.index(i, j, k)];
                out.water.add(w);
                setFlowing(out.flowing, i - i0, j - j0, k - k0, w);
            }
    return out;
}

/// Sets or clears voxel v's flowing bit (its tile is active at `slot`).
inline void markFlowing(Stage2State& st, std::size_t slot, std::size_t v) {
    const Index3 p = st.dims.coord(v);
    setFlowing(st.flowingMask[slot], p.i % kTileSize, p.j % kTileSize, p.k % kTileSize, st.water[v]);
}

}  // namespace

Stage2State::Stage2State(const Dims& d)
    : dims(d),
      tilesX((d.nx + kTileSize - 1) / kTileSize),
      tilesY((d.ny + kTileSize - 1) / kTileSize),
      tilesZ((d.nz + kTileSize - 1) / kTileSize),
      water(d.count(), 0.0),
      tileSlot(std::size_t(tilesX) * std::size_t(tilesY) * std::size_t(tilesZ), -1),
      tileWet(tileSlot.size(), 0),
      reached(d.count(), false) {}

std::ptrdiff_t Stage2State::poolIndex(std::size_t v) const {
    const std::int32_t s = tileSlot[tileOf(*this, v)];
    if (s < 0) return -1;
    const Index3 p = dims.coord(v);
    return std::ptrdiff_t(std::size_t(s) * kTileVoxels) + (p.i % kTileSize) +
           kTileSize * ((p.j % kTileSize) + kTileSize * (p.k % kTileSize));
}

double Stage2State::at(const std::vector<double>& field, std::size_t v, double absent) const {
    const std::ptrdiff_t p = poolIndex(v);
    return p < 0 ? absent : field[std::size_t(p)];
}

double& Stage2State::ref(std::vector<double>& field, std::size_t v) {
    if (poolIndex(v) < 0) {
        activateTile(tileOf(*this, v));
        refreshTiles();
    }
    const std::size_t p = std::size_t(poolIndex(v));
    const std::size_t slot = p / kTileVoxels;
    nearSender[slot] = 1;  // a hand-set value is worked on by the next step: the whole tile is
    const Index3 t = tileCoord(*this, activeTiles[slot]);
    const int ni = std::min(kTileSize, dims.nx - t.i * kTileSize), nj = std::min(kTileSize, dims.ny - t.j * kTileSize),
              nk = std::min(kTileSize, dims.nz - t.k * kTileSize);
    for (int r = 0; r < 64; ++r)
        workMask[slot][std::size_t(r)] = (r & 7) < nj && (r >> 3) < nk ? std::uint8_t((1u << ni) - 1u) : 0;
    return field[p];
}

void Stage2State::activateTile(std::uint32_t tile) {
    if (tileSlot[tile] >= 0) return;
    tileSlot[tile] = std::int32_t(activeTiles.size());
    activeTiles.push_back(tile);
    wetNow.push_back(0);
    waterChanged.push_back(1);
    pressureTop.push_back(-1.0);
    nearSender.push_back(0);
    senderMask.push_back(TileMask{});
    workMask.push_back(TileMask{});
    previousMask.push_back(TileMask{});
    TileContents held = contentsOfTile(*this, tile);  // none yet, but a hand-made state may hold some
    tileWater.push_back(held.water);
    flowingMask.push_back(held.flowing);
    const std::size_t n = activeTiles.size() * kTileVoxels;
    for (std::vector<double>* f : {&norm, &scale, &incoming, &fc, &fa, &upShare, &drainedHere, &erodedHere})
        f->resize(n, 0.0);
    accept.resize(n, 1.0);
}

void Stage2State::recountWater() {
    tileWater.resize(activeTiles.size());
    flowingMask.resize(activeTiles.size());
    tbb::parallel_for(std::size_t(0), activeTiles.size(), [&](std::size_t slot) {
        const TileContents held = contentsOfTile(*this, activeTiles[slot]);
        tileWater[slot] = held.water;
        flowingMask[slot] = held.flowing;
    });
}

void Stage2State::refreshTiles() {
    neighbourBase.resize(activeTiles.size());
    for (std::size_t s = 0; s < activeTiles.size(); ++s)
        forEachTileAround(*this, activeTiles[s], [&](std::size_t n, std::int64_t tile) {
            const std::int32_t slot = tile < 0 ? -1 : tileSlot[std::size_t(tile)];
            neighbourBase[s][n] = slot < 0 ? -1 : std::int64_t(slot) * std::int64_t(kTileVoxels);
        });
}

namespace {

/// Marks a tile wet and activates it and its 26 neighbours; true if any was activated.
bool wetTile(Stage2State& st, std::uint32_t t) {
    const std::size_t before = st.activeTiles.size();
    st.activateTile(t);
    if (st.tileWet[t]) return st.activeTiles.size() != before;
    st.tileWet[t] = 1;
    forEachTileAround(st, t, [&](std::size_t, std::int64_t tile) {
        if (tile >= 0) st.activateTile(std::uint32_t(tile));
    });
    return st.activeTiles.size() != before;
}

}  // namespace

void activateWet(Stage2State& st) {
    for (std::size_t v = 0; v < st.water.size(); ++v)
        if (st.water[v] > 0) wetTile(st, tileOf(st, v));
    st.refreshTiles();
    st.recountWater();
}

void activateAll(Stage2State& st) {
    for (std::size_t t = 0; t < st.tileSlot.size(); ++t) wetTile(st, std::uint32_t(t));
    st.refreshTiles();
    st.recountWater();
}

std::size_t growActiveTiles(Stage2State& st) {
    const std::size_t before = st.activeTiles.size();
    const std::size_t slotsBefore = before;
    for (std::size_t s = 0; s < slotsBefore; ++s)
        if (st.wetNow[s] && !st.tileWet[st.activeTiles[s]]) wetTile(st, st.activeTiles[s]);
    if (st.activeTiles.size() != before) st.refreshTiles();
    return st.activeTiles.size() - before;
}

float porosityRate(float R, float R0, const Stage2Options& g) {
    constexpr int kSteps = 16;
    const double T = g.channelThreshold;
    double s;
    if (double(R0) >= T)
        s = R > R0 ? 1.0 : 0.0;
    else if (!(R > R0))
        s = 0.0;
    else if (R0 > 0)
        s = std::clamp(std::log(double(R) / double(R0)) / std::log(T / double(R0)), 0.0, 1.0);
    else
        s = double(R) >= T ? 1.0 : 0.0;
    const int step = int(std::floor(s * kSteps));
    if (step >= kSteps) return float(g.pRateChannel);
    if (step <= 0) return float(g.pRate);
    return float(g.pRate * std::pow(g.pRateChannel / g.pRate, double(step) / kSteps));
}

namespace {

/// The pressure rate of voxel v as its flags and porosity stand now (the rule `rateField`
/// documents). Erosion only raises porosity and adds flags, so a voxel's rate only falls.
float voxelRate(const Domain& dom, std::size_t v, const Stage2Options& g, const std::vector<std::uint8_t>& vadose) {
    const std::uint8_t f = dom.flags[v];
    if (!vadose.empty() && vadose[v] && !(f & kOpen)) return float(g.pRate);  // air-filled: no head
    // An inception horizon carries early flow: its rate is read from its porosity against the rock's
    // (the protochannel rule with the rock as the baseline), under either rule, until it is channel.
    const bool inception = !dom.inception.data.empty() && dom.inception[v];
    const float early = inception ? porosityRate(dom.porosity[v], dom.rockPorosity, g) : float(g.pRate);
    if (g.rateRule == RateRule::kChannelFlag) return f & kLowRate ? float(g.pRateChannel) : early;
    // [[rock.channel]] conduits are given open (the paper's synthetic protochannels of Figures 8–9);
    // stage-1 protochannels follow their porosity.
    if (f & (kChannel | kOpen | kFeatureChannel)) return float(g.pRateChannel);
    if (f & kProtochannel) return std::min(early, porosityRate(dom.porosity[v], dom.porosity0[v], g));
    return early;
}

/// After voxel v's porosity or flags changed: lowers its rate to `voxelRate` and lists it for the
/// pressure decrease when that is lower.
inline void lowerRate(const Domain& dom, const Stage2Options& g, const Stage2State& st, std::size_t v,
                      Grid3<float>& rate, std::vector<std::size_t>& newChannel) {
    const float r = voxelRate(dom, v, g, st.vadose);
    if (r < rate[v]) {
        rate[v] = r;
        newChannel.push_back(v);
    }
}

}  // namespace

Grid3<float> rateField(const Domain& dom, const Stage2Options& g, const std::vector<std::uint8_t>& vadose) {
    Grid3<float> rate(dom.dims, float(g.pRate));
    for (std::size_t v = 0; v < rate.size(); ++v) rate[v] = voxelRate(dom, v, g, vadose);
    return rate;
}

std::vector<bool> connectedSources(const Domain& dom) {
    return sourcesReached(dom, reachedFromSinks(dom, kConducting));
}

void reachFromSinks(const Domain& dom, Stage2State& st, const std::vector<int>& sinks) {
    st.reached.assign(dom.dims.count(), false);
    std::deque<std::size_t> queue;
    for (std::size_t si = 0; si < dom.sinkVoxels.size(); ++si)
        if (listed(sinks, si))
            for (std::size_t v : dom.sinkVoxels[si])
                if (!st.reached[v]) {
                    st.reached[v] = true;
                    queue.push_back(v);
                }
    spreadThrough(dom, kConducting, queue, st.reached);
}

std::vector<bool> extendReach(const Domain& dom, Stage2State& st, const std::vector<std::size_t>& newConducting) {
    const Dims& d = dom.dims;
    std::deque<std::size_t> queue;
    for (std::size_t c : newConducting) {
        if (st.reached[c]) continue;
        const Index3 p = d.coord(c);
        bool touches = false;
        for (const auto& o : allNeighbours()) {
            const int i = p.i + o.di, j = p.j + o.dj, k = p.k + o.dk;
            if (d.contains(i, j, k) && st.reached[d.index(i, j, k)]) {
                touches = true;
                break;
            }
        }
        if (!touches) continue;
        st.reached[c] = true;
        queue.push_back(c);
        spreadThrough(dom, kConducting, queue, st.reached);
    }
    return sourcesReached(dom, st.reached);
}

std::vector<Refill> refillLevels(const Domain& dom) {
    // The strongest source refills to full capacity, a weaker one in proportion to its pressure.
    double pmax = 0;
    for (double p : dom.sourcePressure) pmax = std::max(pmax, p);
    std::vector<Refill> refill;
    for (std::size_t si = 0; si < dom.sourceVoxels.size(); ++si)
        for (std::size_t v : dom.sourceVoxels[si]) {
            const double h = dom.sourcePressure[si] / pmax;
            refill.push_back({v, h, int(si), h});
        }
    return refill;
}

void headLevels(const Grid3<double>& P, double cap, std::vector<Refill>& levels) {
    for (Refill& r : levels) r.level = std::clamp(r.head - P[r.voxel] / cap, 0.0, 1.0);
}

double refillSources(const Domain& dom, const std::vector<Refill>& levels, Stage2State& st,
                     std::vector<double>* perSource) {
    double injected = 0;
    bool grown = false;
    for (const Refill& r : levels) {
        const std::size_t v = r.voxel;
        const double target = r.level * dom.porosity[v];
        if (st.water[v] < target) {
            injected += target - st.water[v];
            if (perSource) (*perSource)[std::size_t(r.source)] += target - st.water[v];
            // An inactive tile is activated below, and counts its water then.
            const std::int32_t slot = st.tileSlot[tileOf(st, v)];
            if (slot >= 0) st.tileWater[std::size_t(slot)].replace(st.water[v], target);
            st.water[v] = target;
        }
        if (st.water[v] > 0) grown = wetTile(st, tileOf(st, v)) || grown;
        const std::size_t slot = std::size_t(st.tileSlot[tileOf(st, v)]);
        st.waterChanged[slot] = 1;
        markFlowing(st, slot, v);
    }
    if (grown) st.refreshTiles();
    return injected;
}

void computeOffers(const Domain& dom, const Grid3<double>& P, TransportWeight weight, Stage2State& st) {
    const bool proportional = weight == TransportWeight::kProportional;
    const std::array<double, 26> invLength = invLengths();
    const std::vector<double>& water = st.water;
    const Dims& d = dom.dims;
    forEachTile(st, [&](const TileCtx& c) {
        // A tile whose water did not change since its last scan and holds none that could flow has no
        // senders (a sender always works on its own tile, which marks it changed). A tile that holds
        // such water is scanned again although it did not change: its voxels had no lower neighbour
        // with room, and a fall of pressure around them may have made one.
        if (!st.waterChanged[c.slot] && !anyBit(st.flowingMask[c.slot])) return;
        st.waterChanged[c.slot] = 0;
        TileMask& senders = st.senderMask[c.slot];
        // Only senders have a norm and a scale: the last ones go back to rest, then the voxels
        // holding water are weighed (a dry voxel sends nothing).
        forEachMasked(d, c, senders, [&](std::size_t, std::size_t p, int, int, int) { st.norm[p] = st.scale[p] = 0; });
        senders.fill(0);
        forEachMasked(d, c, st.flowingMask[c.slot], [&](std::size_t v, std::size_t p, int li, int lj, int lk) {
            const double w = water[v];
            st.norm[p] = 0;
            st.scale[p] = 0;
            if (w < kMinFlowingWater || (dom.flags[v] & kSink)) return;
            // Participants (Listing 1, lines 1–4) and their weights, gathered once.
            std::array<double, 26> num{}, freeCap{};
            const double pv = P[v];
            const double norm = pairedSum(d, c, li, lj, lk, v, [&](int sl, std::size_t u, std::int64_t) {
                const double pu = P[u];
                if (!(pu < pv)) return 0.0;
                const double fr = double(dom.porosity[u]) - water[u];
                if (!(fr > 0)) return 0.0;
                const double x = proportional ? (pv - pu) * invLength[std::size_t(sl)] : 1.0;
                num[std::size_t(sl)] = x;
                freeCap[std::size_t(sl)] = fr;
                return x;
            });
            if (!(norm > 0)) return;
            // Shares weight · free capacity; their total, in the same paired order.
            std::array<double, 26> share{};
            for (std::size_t sl = 0; sl < 26; ++sl) share[sl] = num[sl] != 0 ? (num[sl] / norm) * freeCap[sl] : 0.0;
            const double total = pairedSlotSum(share);
            st.norm[p] = norm;
            st.scale[p] = total > w ? w / total : 1.0;  // never more in total than the contents
            senders[std::size_t(lj + 8 * lk)] |= std::uint8_t(1u << li);
        });
    });
    // The voxels that can receive, send, flow or erode this iteration: the senders and their 26
    // neighbours (the sender masks dilated by one voxel, across tile borders).
    const std::size_t nSlots = st.activeTiles.size();
    // Tiles with a sender: a tile none of whose 27 neighbours (itself included) has one rests.
    std::vector<std::uint8_t> sends(nSlots, 0);
    for (std::size_t sl = 0; sl < nSlots; ++sl) sends[sl] = anyBit(st.senderMask[sl]) ? 1 : 0;
    tbb::parallel_for(std::size_t(0), nSlots, [&](std::size_t sl) {
        const auto& nb = st.neighbourBase[sl];
        if (std::none_of(nb.begin(), nb.end(),
                         [&](std::int64_t b) { return b >= 0 && sends[std::size_t(b) / kTileVoxels]; })) {
            st.workMask[sl].fill(0);
            st.nearSender[sl] = 0;
            return;
        }
        const TileCtx c = tileCtx(st, sl);
        // The sender rows around the tile, one voxel of halo on every side: row (a, b) for local
        // y = a − 1 and z = b − 1, as 10 bits for local x = −1 … 8 (bit x + 1).
        const auto rowOf = [&](int dx, int ty, int tz, int row) -> unsigned {
            const std::int64_t b = nb[std::size_t((dx + 1) + 3 * (ty + 1) + 9 * (tz + 1))];
            return b < 0 ? 0u : st.senderMask[std::size_t(b) / kTileVoxels][std::size_t(row)];
        };
        std::array<std::array<unsigned, 10>, 10> halo;
        for (int b = 0; b < 10; ++b)
            for (int a = 0; a < 10; ++a) {
                const int y = a - 1, z = b - 1;
                const int ty = y >> 3, tz = z >> 3, row = (y & 7) + 8 * (z & 7);
                halo[std::size_t(b)][std::size_t(a)] =
                    (rowOf(-1, ty, tz, row) >> 7) | (rowOf(0, ty, tz, row) << 1) | ((rowOf(1, ty, tz, row) & 1u) << 9);
            }
        // Dilated in y, then z, then x: a voxel works when a sender lies within one voxel.
        std::array<std::array<unsigned, 8>, 10> alongY;
        for (std::size_t b = 0; b < 10; ++b)
            for (std::size_t lj = 0; lj < 8; ++lj) alongY[b][lj] = halo[b][lj] | halo[b][lj + 1] | halo[b][lj + 2];
        TileMask& work = st.workMask[sl];
        bool any = false;
        const unsigned inside = c.ni >= 8 ? 0xffu : (1u << c.ni) - 1u;
        for (int r = 0; r < 64; ++r) {
            const int lj = r & 7, lk = r >> 3;
            unsigned m = 0;
            if (lj < c.nj && lk < c.nk) {
                const unsigned e = alongY[std::size_t(lk)][std::size_t(lj)] |
                                   alongY[std::size_t(lk + 1)][std::size_t(lj)] |
                                   alongY[std::size_t(lk + 2)][std::size_t(lj)];
                m = (e | (e << 1) | (e >> 1)) >> 1;  // bit li: senders at x = li − 1, li, li + 1
            }
            work[std::size_t(r)] = std::uint8_t(m & inside);
            any = any || work[std::size_t(r)];
        }
        st.nearSender[sl] = any ? 1 : 0;
    });
}

double offerOf(const Domain& dom, const Grid3<double>& P, TransportWeight weight, const Stage2State& st, std::size_t v,
               int slot) {
    const Slot& o = slots()[std::size_t(slot)];
    const Index3 p = dom.dims.coord(v);
    if (!dom.dims.contains(p.i + o.di, p.j + o.dj, p.k + o.dk)) return 0.0;
    const double nv = st.at(st.norm, v);
    if (!(nv > 0)) return 0.0;
    const std::size_t u = dom.dims.index(p.i + o.di, p.j + o.dj, p.k + o.dk);
    return offerValue(P[v], nv, st.at(st.scale, v), P[u], double(dom.porosity[u]) - st.water[u], o.invLength,
                      weight == TransportWeight::kProportional);
}

void computeAcceptance(const Domain& dom, const Grid3<double>& P, TransportWeight weight, Stage2State& st) {
    const bool proportional = weight == TransportWeight::kProportional;
    const std::array<double, 26> invLength = invLengths();
    const Dims& d = dom.dims;
    forEachTile(st, [&](const TileCtx& c) {
        const TileMask& work = st.workMask[c.slot];
        const TileMask& previous = st.previousMask[c.slot];
        // Voxels that worked last iteration and rest now: their transients back to rest.
        TileMask leaving{};
        for (std::size_t r = 0; r < 64; ++r) leaving[r] = std::uint8_t(previous[r] & ~work[r]);
        forEachMasked(d, c, leaving, [&](std::size_t, std::size_t p, int, int, int) {
            st.incoming[p] = st.fc[p] = st.fa[p] = st.upShare[p] = st.drainedHere[p] = st.erodedHere[p] = 0;
            st.accept[p] = 1;
        });
        if (!st.nearSender[c.slot]) return;  // no sender in or beside this tile: nothing to do
        const TileMask& senders = st.senderMask[c.slot];
        forEachMasked(d, c, work, [&](std::size_t u, std::size_t p, int li, int lj, int lk) {
            const double pu = P[u];
            const double fr = double(dom.porosity[u]) - st.water[u];
            // The offer reaching u from its neighbour v, recomputed from v's norm and scale.
            const double in = pairedSum(
                d, c, li, lj, lk, u,
                [&](int sl, std::size_t v, std::int64_t q) {
                    if (q < 0) return 0.0;
                    const double nv = st.norm[std::size_t(q)];
                    if (!(nv > 0)) return 0.0;
                    return offerValue(P[v], nv, st.scale[std::size_t(q)], pu, fr, invLength[std::size_t(sl)],
                                      proportional);
                },
                &senders);  // a voxel that does not send (norm 0) offers nothing
            st.incoming[p] = in;
            const double freeCap = (dom.flags[u] & kSink) ? in : fr;
            // Round-off in moveWater may leave a voxel an ulp over full (freeCap < 0); nobody
            // offers to a full voxel, so in = 0 there, and 0 / 0 must not be taken: with nothing
            // incoming there is nothing to refuse.
            st.accept[p] = in > 0 && in > freeCap ? std::max(0.0, freeCap) / in : 1.0;
        });
    });
}

std::pair<double, double> moveWater(const Domain& dom, const Grid3<double>& P, TransportWeight weight,
                                    Stage2State& st) {
    const bool proportional = weight == TransportWeight::kProportional;
    const std::array<double, 26> invLength = invLengths();
    const Dims& d = dom.dims;
    // f_c: what each sender's offers bring, times the receivers' acceptance (read-only water).
    forEachTile(st, [&](const TileCtx& c) {
        if (!st.nearSender[c.slot]) return;  // no sender in or beside this tile: nothing to do
        forEachMasked(d, c, st.workMask[c.slot], [&](std::size_t v, std::size_t p, int li, int lj, int lk) {
            const double nv = st.norm[p];
            if (!(nv > 0)) {
                st.fc[p] = 0;
                return;
            }
            const double pv = P[v], sc = st.scale[p];
            st.fc[p] = pairedSum(d, c, li, lj, lk, v, [&](int sl, std::size_t u, std::int64_t q) {
                const double offer = offerValue(pv, nv, sc, P[u], double(dom.porosity[u]) - st.water[u],
                                                invLength[std::size_t(sl)], proportional);
                return offer * (q < 0 ? 1.0 : st.accept[std::size_t(q)]);
            });
        });
    });
    // Per slot: Σ f_c and the water drained (order-free sums, added up below in any order).
    std::vector<ExactSum> movedIn(st.activeTiles.size()), drainedIn(st.activeTiles.size());
    forEachTile(st, [&](const TileCtx& c) {
        if (!st.nearSender[c.slot]) return;  // no sender in or beside this tile: nothing to do
        bool wet = st.wetNow[c.slot];
        st.waterChanged[c.slot] = 1;
        ExactSum& tileWater = st.tileWater[c.slot];
        ExactSum& moved = movedIn[c.slot];
        ExactSum& drained = drainedIn[c.slot];
        TileMask& flowing = st.flowingMask[c.slot];
        forEachMasked(d, c, st.workMask[c.slot], [&](std::size_t v, std::size_t p, int li, int lj, int lk) {
            const double before = st.water[v];
            st.water[v] += st.accept[p] * st.incoming[p] - st.fc[p];
            st.drainedHere[p] = 0;
            if (dom.flags[v] & kSink) {
                st.drainedHere[p] = st.water[v];
                drained.add(st.water[v]);
                st.water[v] = 0;
            }
            moved.add(st.fc[p]);
            tileWater.replace(before, st.water[v]);
            setFlowing(flowing, li, lj, lk, st.water[v]);
            wet = wet || st.water[v] > 0;
        });
        st.wetNow[c.slot] = wet ? 1 : 0;
    });
    ExactSum moved, drained;
    for (std::size_t s = 0; s < movedIn.size(); ++s) {
        moved += movedIn[s];
        drained += drainedIn[s];
    }
    return {moved.value(), drained.value()};
}

void blendFlow(const Domain& dom, const Grid3<double>& P, FlowBlending blending, Stage2State& st) {
    const bool split = blending == FlowBlending::kSplit;
    const Dims& d = dom.dims;
    if (split)
        forEachTile(st, [&](const TileCtx& c) {
            if (!st.nearSender[c.slot]) return;  // no sender in or beside this tile: nothing to do
            forEachMasked(d, c, st.workMask[c.slot], [&](std::size_t v, std::size_t p, int li, int lj, int lk) {
                if (st.fc[p] == 0) {
                    st.upShare[p] = 0;
                    return;
                }
                const double pv = P[v];
                const double up = pairedSum(d, c, li, lj, lk, v,
                                            [&](int, std::size_t u, std::int64_t) { return P[u] > pv ? 1.0 : 0.0; });
                st.upShare[p] = up > 0 ? st.fc[p] / up : 0.0;
            });
        });
    // Only senders have f_c (and a split share) above 0: the groups without one are skipped.
    forEachTile(st, [&](const TileCtx& c) {
        if (!st.nearSender[c.slot]) return;  // no sender in or beside this tile: nothing to do
        const TileMask& senders = st.senderMask[c.slot];
        forEachMasked(d, c, st.workMask[c.slot], [&](std::size_t v, std::size_t p, int li, int lj, int lk) {
            const double pv = P[v];
            if (split) {
                st.fa[p] = pairedSum(
                    d, c, li, lj, lk, v,
                    [&](int, std::size_t u, std::int64_t q) {
                        return q >= 0 && P[u] < pv ? st.upShare[std::size_t(q)] : 0.0;
                    },
                    &senders);
            } else {
                double strongest = 0;  // max is order-free: mirror symmetry and determinism hold
                pairedSum(
                    d, c, li, lj, lk, v,
                    [&](int, std::size_t u, std::int64_t q) {
                        if (q >= 0 && P[u] < pv) strongest = std::max(strongest, st.fc[std::size_t(q)]);
                        return 0.0;
                    },
                    &senders);
                st.fa[p] = strongest;
            }
        });
    });
}

namespace {

/// The channel rule of one voxel: flags it and records it; true if it became channel.
inline bool channelRule(Domain& dom, std::size_t v, float threshold, std::vector<std::size_t>& newConducting) {
    std::uint8_t& f = dom.flags[v];
    if (f & kChannel || !(dom.porosity[v] >= threshold && dom.porosity[v] > dom.porosity0[v])) return false;
    f |= kChannel;
    newConducting.push_back(v);
    return true;
}

}  // namespace

double erode(Domain& dom, const Stage2Options& g, Stage2State& st, Grid3<float>& rate,
             std::vector<std::size_t>& newChannel, std::vector<std::size_t>& newConducting) {
    const float threshold = float(g.channelThreshold);
    const Dims& d = dom.dims;
    std::vector<std::vector<std::size_t>> fresh(st.activeTiles.size()), conducting(st.activeTiles.size());
    std::vector<ExactSum> erodedIn(st.activeTiles.size());  // per slot, added up below in any order
    forEachTile(st, [&](const TileCtx& c) {
        const TileMask& work = st.workMask[c.slot];
        TileMask& previous = st.previousMask[c.slot];
        // f = 0 where nothing flows now (Eq. 1 erodes nothing): clear the flow of the last iteration once.
        TileMask leaving{};
        for (std::size_t r = 0; r < 64; ++r) leaving[r] = std::uint8_t(previous[r] & ~work[r]);
        forEachMasked(d, c, leaving, [&](std::size_t v, std::size_t, int, int, int) {
            if (!(dom.flags[v] & kOpen)) dom.flow[v] = 0.f;
        });
        previous = work;
        if (!st.nearSender[c.slot]) return;
        forEachMasked(d, c, work, [&](std::size_t v, std::size_t p, int, int, int) {
            st.erodedHere[p] = 0;
            if (dom.flags[v] & kNotEroded) return;
            const double flow = g.wa * st.fa[p] + st.fc[p];
            bool opened = false;
            if (flow > 0) {
                const float R = dom.porosity[v];
                const double dR = std::min(g.w0 * (g.m == 1.0 ? flow : std::pow(flow, g.m)), 1.0 - double(R));
                if (dR > 0) {
                    dom.porosity[v] = std::min(1.f, float(double(R) + dR));
                    st.erodedHere[p] = double(dom.porosity[v]) - double(R);
                    erodedIn[c.slot].add(st.erodedHere[p]);
                    opened = true;
                }
            }
            if (channelRule(dom, v, threshold, conducting[c.slot]) || opened)
                lowerRate(dom, g, st, v, rate, fresh[c.slot]);
            dom.flow[v] = float(flow);
        });
    });
    for (std::size_t s = 0; s < fresh.size(); ++s) {
        newChannel.insert(newChannel.end(), fresh[s].begin(), fresh[s].end());
        newConducting.insert(newConducting.end(), conducting[s].begin(), conducting[s].end());
        st.channelVoxels += long(conducting[s].size());
    }
    ExactSum eroded;
    for (const ExactSum& e : erodedIn) eroded += e;
    return eroded.value();
}

void startStage2(Domain& dom, const Stage2Options& g, Stage2State& st, Grid3<float>& rate) {
    const float threshold = float(g.channelThreshold);
    std::vector<std::size_t> newChannel, newConducting;
    st.channelVoxels = 0;
    for (std::size_t v = 0; v < dom.flags.size(); ++v) {
        if (dom.flags[v] & kChannel) ++st.channelVoxels;
        if (!(dom.flags[v] & kOpen) && channelRule(dom, v, threshold, newConducting))
            lowerRate(dom, g, st, v, rate, newChannel);
    }
    st.channelVoxels += long(newConducting.size());
    for (const auto& src : dom.sourceVoxels)
        for (std::size_t v : src) wetTile(st, tileOf(st, v));
    st.refreshTiles();
    reachFromSinks(dom, st);
}

std::size_t updatePressure(fastmarch::EikonalField& pressure, const Grid3<float>& rate,
                           const std::vector<std::size_t>& newChannel, double limit) {
    return newChannel.empty() && pressure.settled() ? 0 : pressure.decrease(rate, newChannel, limit);
}

double pressureNeeded(Stage2State& st, const Grid3<double>& pressure) {
    // Pressure only falls, so a tile's largest pressure taken when it was activated stays an upper
    // bound: each tile is scanned once.
    forEachTile(st, [&](const TileCtx& c) {
        if (st.pressureTop[c.slot] >= 0) return;
        double m = 0;
        forEachVoxel(st.dims, c, [&](std::size_t v, std::size_t, int, int, int) { m = std::max(m, pressure[v]); });
        st.pressureTop[c.slot] = m;
    });
    double m = 0;
    for (double x : st.pressureTop) m = std::max(m, x);  // max is order-free
    return m;
}

double pressureRead(const Domain& dom, const Stage2State& st, const Grid3<double>& pressure) {
    // The next iteration's senders are among the voxels holding at least kMinFlowingWater now (no
    // sink) and the sources (refilled first): the flowing voxels of every active tile, also those
    // that sent nothing this iteration (no lower neighbour had room; a fall of pressure may give
    // them one). Stored values are at least the true ones, so their largest bounds the true
    // pressure of every sender.
    std::vector<double> top(st.activeTiles.size(), 0.0);
    forEachTile(st, [&](const TileCtx& c) {
        double m = 0;
        forEachMasked(st.dims, c, st.flowingMask[c.slot], [&](std::size_t v, std::size_t, int, int, int) {
            if (!(dom.flags[v] & kSink)) m = std::max(m, pressure[v]);
        });
        top[c.slot] = m;
    });
    double m = 0;
    for (double x : top) m = std::max(m, x);  // max is order-free
    for (const auto& source : dom.sourceVoxels)
        for (std::size_t v : source) m = std::max(m, pressure[v]);
    return m;
}

std::pair<double, long> waterAndChannels(const Domain& dom, const Stage2State& st, const Grid3<double>& pressure,
                                         int iteration) {
    ExactSum total;
    for (const ExactSum& w : st.tileWater) total += w;
    const double stored = total.value();
    std::vector<std::uint8_t> bad(st.activeTiles.size(), 0);
    forEachTile(st, [&](const TileCtx& c) {
        if (!st.nearSender[c.slot]) return;  // nothing changed here this iteration
        bool finite = true;
        forEachMasked(st.dims, c, st.workMask[c.slot], [&](std::size_t v, std::size_t, int, int, int) {
            finite = finite && std::isfinite(st.water[v]) && std::isfinite(dom.flow[v]) && std::isfinite(pressure[v]);
        });
        bad[c.slot] = finite ? 0 : 1;
    });
    if (std::isfinite(stored) && std::find(bad.begin(), bad.end(), std::uint8_t(1)) == bad.end())
        return {stored, st.channelVoxels};
    // Name the quantity that went bad first, in cause-before-effect order, and its first voxel.
    const auto fail = [&](const char* name, std::size_t v, double x) {
        const Index3 p = dom.dims.coord(v);
        throw RuntimeError("stage 2, iteration " + std::to_string(iteration) + ": " + name + " became non-finite (" +
                           std::to_string(x) + ") at voxel (" + std::to_string(p.i) + ", " + std::to_string(p.j) +
                           ", " + std::to_string(p.k) + ")");
    };
    const auto check = [&](const char* name, auto&& value) {
        std::size_t first = st.water.size();  // the lowest voxel index where `value` is not finite
        for (std::size_t slot = 0; slot < st.activeTiles.size(); ++slot)
            forEachVoxel(st.dims, tileCtx(st, slot), [&](std::size_t v, std::size_t p, int, int, int) {
                if (v < first && !std::isfinite(value(v, p))) first = v;
            });
        if (first < st.water.size()) fail(name, first, value(first, std::size_t(st.poolIndex(first))));
    };
    check("accept", [&](std::size_t, std::size_t p) { return st.accept[p]; });
    check("incoming water", [&](std::size_t, std::size_t p) { return st.incoming[p]; });
    check("outflow f_c", [&](std::size_t, std::size_t p) { return st.fc[p]; });
    check("water", [&](std::size_t v, std::size_t) { return st.water[v]; });
    check("blended flow f_a", [&](std::size_t, std::size_t p) { return st.fa[p]; });
    check("pressure", [&](std::size_t v, std::size_t) { return pressure[v]; });
    check("porosity", [&](std::size_t v, std::size_t) { return double(dom.porosity[v]); });
    check("flow", [&](std::size_t v, std::size_t) { return double(dom.flow[v]); });
    throw RuntimeError("stage 2, iteration " + std::to_string(iteration) + ": state became non-finite");
}

std::vector<double> waterTableColumns(const Dims& d, const Hydrology& h, double level) {
    constexpr double kDegree = kPi / 180.0;
    const double slope = std::tan(h.dip * kDegree);
    const double sx = std::sin(h.dipDirection * kDegree), sy = std::cos(h.dipDirection * kDegree);
    const double cx = 0.5 * double(d.nx - 1), cy = 0.5 * double(d.ny - 1);
    std::vector<double> table(std::size_t(d.nx) * std::size_t(d.ny), level);
    if (slope != 0)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i)
                table[std::size_t(i) + std::size_t(d.nx) * std::size_t(j)] =
                    level - slope * ((double(i) - cx) * sx + (double(j) - cy) * sy);
    return table;
}

void gravityPotential(const Grid3<double>& P, const std::vector<double>& table, double cap, const Stage2Options& g,
                      const Stage2State& st, bool all, Grid3<double>& potential) {
    const Dims& d = P.dims;
    const double lateral = g.hydrology.lateral;
    const auto at = [&](std::size_t v, int i, int j, int k) {
        const double z = table[std::size_t(i) + std::size_t(d.nx) * std::size_t(j)];
        potential[v] = double(k) > z ? cap + g.pRate * (double(k) - z) + lateral * P[v] : P[v];
    };
    if (all) {
        tbb::parallel_for(0, d.nz, [&](int k) {
            for (int j = 0; j < d.ny; ++j)
                for (int i = 0; i < d.nx; ++i) at(d.index(i, j, k), i, j, k);
        });
        return;
    }
    forEachTile(st, [&](const TileCtx& c) {
        forEachVoxel(
            d, c, [&](std::size_t v, std::size_t, int li, int lj, int lk) { at(v, c.i0 + li, c.j0 + lj, c.k0 + lk); });
    });
}

}  // namespace stage2

using namespace stage2;

double stage2PressureCap(const Domain& dom, const Stage2Options& g) {
    // Automatic: the strongest source's head is 2 · pRate · (nx + ny + nz) whatever its `pressure`,
    // so only ratios of source pressures (and of rates) shape the result.
    if (!(g.pressureScale > 0)) return 2.0 * g.pRate * double(dom.dims.nx + dom.dims.ny + dom.dims.nz);
    double pmax = 0;
    for (double p : dom.sourcePressure) pmax = std::max(pmax, p);
    if (pmax <= 0) pmax = 1;
    return pmax * g.pressureScale;
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
    field.solve(dom.dims, rateField(dom, g), sinkSeeds(dom), stage2PressureCap(dom, g),
                fastmarch::Stencil::kAvalanche26);
    return field.value();
}

namespace {

/// One phase as runStage2 runs it.
struct PhasePlan {
    int iterations = 0;
    double waterTable = -1;
    std::vector<int> sinks, sources;  ///< 1-based; empty = all
    bool given = false;               ///< a `[[phase]]` entry (else the run's only phase)
};

std::vector<int> activeList(const std::vector<int>& list, std::size_t count) {
    std::vector<int> out;
    for (std::size_t n = 0; n < count; ++n)
        if (listed(list, n)) out.push_back(int(n + 1));
    return out;
}

/// The cave (channel voxels) above and below `table` (none: all below) into `prec`: counts,
/// bounding boxes and the mean count above per z-slice that holds any.
void caveAroundTable(const Domain& dom, const std::vector<double>* table, Stage2PhaseRecord& prec) {
    const Dims& d = dom.dims;
    const auto grow = [](std::array<int, 3>& lo, std::array<int, 3>& hi, long& count, const std::array<int, 3>& p) {
        for (std::size_t c = 0; c < 3; ++c) {
            lo[c] = count == 0 ? p[c] : std::min(lo[c], p[c]);
            hi[c] = count == 0 ? p[c] : std::max(hi[c], p[c]);
        }
        ++count;
    };
    long slices = 0;
    for (int k = 0; k < d.nz; ++k) {
        const long aboveBefore = prec.caveAbove;
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                if (!(dom.flags[d.index(i, j, k)] & kChannel)) continue;
                if (table && isVadose(d, *table, i, j, k))
                    grow(prec.aboveLo, prec.aboveHi, prec.caveAbove, {i, j, k});
                else
                    grow(prec.belowLo, prec.belowHi, prec.caveBelow, {i, j, k});
            }
        if (prec.caveAbove > aboveBefore) ++slices;
    }
    prec.aboveSliceMean = slices > 0 ? double(prec.caveAbove) / double(slices) : 0.0;
}

}  // namespace

Stage2Result runStage2(Domain& dom, const Stage2Options& g, const ProgressFn& progress, const SnapshotFn& snapshot,
                       const Stage2Checkpoints& checkpoints) {
    const Stopwatch t0;
    const Dims d = dom.dims;
    const std::size_t n = d.count();
    Carry c(d);
    Stage2Result& res = c.result;
    std::vector<Refill>& refill = c.refill;
    const std::vector<Refill> allRefill = refillLevels(dom);
    const bool byHead = g.inflow == SourceInflow::kHead;
    Grid3<float>& rate = c.rate;
    fastmarch::EikonalField& pressure = c.pressure;
    Stage2State& st = c.state;
    double& stored = c.stored;
    double secondsBefore = 0;  // a resumed run's time before it stopped

    // The phases: the `[[phase]]` entries, or one phase of `iterations` under `[hydrology]`'s table.
    std::vector<PhasePlan> plan;
    for (const Stage2Phase& ph : g.phases)
        plan.push_back(
            {ph.iterations, ph.waterTable >= 0 ? ph.waterTable : g.hydrology.waterTable, ph.sinks, ph.sources, true});
    if (plan.empty()) plan.push_back({g.iterations, g.hydrology.waterTable, {}, {}, false});
    int totalIterations = 0;
    // A site's surface stands for `[hydrology]`'s level where a phase gives none.
    const bool siteTable = g.hydrology.fromSite && !dom.siteWaterTable.empty();
    bool gravity = siteTable;
    for (const PhasePlan& ph : plan) {
        totalIterations += ph.iterations;
        gravity = gravity || ph.waterTable >= 0;
    }
    const bool phased = !g.phases.empty() || gravity;  // else the paper's model, unchanged

    // Sinks inactive in a phase neither drain nor hold the pressure at 0: their voxels lose the
    // sink flag and are marked inert (never eroded) until the end of the run. Their flags as given
    // are those of the prepared domain (startStage2 leaves sinks and sources alone), so a resumed
    // run takes them before the stored grids replace the domain's.
    std::vector<std::uint8_t> sinkFlags;  // the flags of the sinks' voxels as given, in voxel order
    if (phased)
        for (const auto& sink : dom.sinkVoxels)
            for (std::size_t v : sink) sinkFlags.push_back(dom.flags[v]);

    // The record of phase `index` of the plan as it starts after iteration `first`: what identifies
    // the phase (its first iteration, table and active terminals).
    const auto phaseStart = [&](std::size_t index, int first) {
        const PhasePlan& ph = plan[index];
        Stage2PhaseRecord r;
        r.firstIteration = first + 1;
        r.waterTable = ph.waterTable >= 0 ? ph.waterTable : -1.0;
        r.fromSite = siteTable && ph.waterTable < 0;
        r.sinks = activeList(ph.sinks, dom.sinkVoxels.size());
        r.sources = activeList(ph.sources, dom.sourceVoxels.size());
        return r;
    };

    // The phase a resumed run continues: the one holding the iteration its state was saved after
    // (the phases before it are done and recorded in the state).
    std::size_t firstPhase = 0;
    if (checkpoints.resume) {
        decodeCarry(*checkpoints.resume, checkpoints.resumeName, c, dom);
        const auto foreign = [&] {
            return InputError(checkpoints.resumeName + ": a stage-2 state that does not belong to this scenario");
        };
        if (c.iteration > totalIterations || res.sourceConnectedIteration.size() != dom.sourceVoxels.size())
            throw foreign();
        int start = 0;  // iterations before phase firstPhase
        while (start + plan[firstPhase].iterations < c.iteration) start += plan[firstPhase++].iterations;
        // Each phase record as this scenario's phases make it (what a phase sets up is derived
        // again below from these; a state of other phases would not continue bit for bit).
        const auto matches = [&](const Stage2PhaseRecord& r, std::size_t index, int first) {
            const Stage2PhaseRecord want = phaseStart(index, first);
            return r.firstIteration == want.firstIteration && r.waterTable == want.waterTable &&
                   r.fromSite == want.fromSite && r.sinks == want.sinks && r.sources == want.sources;
        };
        if (!phased) {
            if (!res.phases.empty() || c.phase.firstIteration != 0) throw foreign();
        } else {
            if (res.phases.size() != firstPhase || !matches(c.phase, firstPhase, start)) throw foreign();
            int first = 0;
            for (std::size_t k = 0; k < firstPhase; ++k) {
                if (!matches(res.phases[k], k, first) || res.phases[k].iterations != plan[k].iterations)
                    throw foreign();
                first += plan[k].iterations;
            }
        }
        secondsBefore = res.seconds;
    } else {
        res.pressureCap = stage2PressureCap(dom, g);
        res.sourceConnectedIteration.assign(dom.sourceVoxels.size(), std::nullopt);
        refill = allRefill;
        res.sourceInjected.assign(dom.sourceVoxels.size(), 0.0);
        rate = rateField(dom, g);
        startStage2(dom, g, st, rate);
        const Stopwatch tp;
        pressure.solve(d, rate, sinkSeeds(dom), res.pressureCap, fastmarch::Stencil::kAvalanche26);
        res.pressureSeconds += tp.seconds();
    }
    std::vector<std::size_t> changed, conducting;
    // Water and the settled pressure field into the domain.
    const auto publish = [&] {
        const Stopwatch tp;
        pressure.settle(rate);  // the sweeps that waited beyond the water
        res.pressureSeconds += tp.seconds();
        // The iterations check the pressure where the water reads it; the settled field is checked
        // whole here, so a non-finite value beyond the water is reported too.
        for (std::size_t v = 0; v < n; ++v) {
            dom.water[v] = float(st.water[v]);
            const double pv = pressure.value()[v];
            if (!std::isfinite(pv)) {
                const Index3 p = d.coord(v);
                throw RuntimeError("stage 2: pressure became non-finite (" + std::to_string(pv) + ") at voxel (" +
                                   std::to_string(p.i) + ", " + std::to_string(p.j) + ", " + std::to_string(p.k) + ")");
            }
            dom.pressure[v] = float(pv);
        }
    };

    const auto restoreSinks = [&] {
        std::size_t at = 0;
        for (const auto& sink : dom.sinkVoxels)
            for (std::size_t v : sink) dom.flags[v] = sinkFlags[at++];
    };
    Grid3<double> potential;
    std::vector<double> table;
    if (gravity) potential = Grid3<double>(d, 0.0);

    int it = c.iteration;  // 0, or the iteration a checkpoint was taken after
    int phaseEnd = 0;
    Stage2PhaseRecord& prec = c.phase;
    for (std::size_t phaseIndex = 0; phaseIndex < plan.size(); ++phaseIndex) {
        const PhasePlan& ph = plan[phaseIndex];
        phaseEnd += ph.iterations;
        if (phaseIndex < firstPhase) continue;  // done before the checkpoint
        // A resumed run continues its first phase: the state holds what the phase's start set up
        // (flags of the sinks, refill levels, rates, pressure, reach), all but the table below.
        const bool continued = checkpoints.resume && phaseIndex == firstPhase;
        const bool fromSite = siteTable && ph.waterTable < 0;  // this phase's table is the site's surface
        const bool hasTable = ph.waterTable >= 0 || fromSite;
        if (phased && !continued) {  // without phases the record stays empty
            prec = phaseStart(phaseIndex, it);
            prec.channelVoxelsStart = st.channelVoxels;
        }
        if (phased) {
            // The phase's terminals, pressure and connectivity.
            if (ph.given && !continued) {
                std::size_t at = 0;
                for (std::size_t si = 0; si < dom.sinkVoxels.size(); ++si)
                    for (std::size_t v : dom.sinkVoxels[si]) {
                        const std::uint8_t given = sinkFlags[at++];
                        dom.flags[v] = listed(ph.sinks, si)
                                           ? given
                                           : std::uint8_t((given & ~std::uint8_t(kSink)) | std::uint8_t(kInert));
                    }
                refill.clear();
                for (const Refill& r : allRefill)
                    if (listed(ph.sources, std::size_t(r.source))) refill.push_back(r);
                if (phaseIndex > 0 || !ph.sinks.empty()) {
                    if (!gravity) {  // with a table the front is solved below, once the table is known
                        const Stopwatch tp;
                        rate = rateField(dom, g);
                        pressure.solve(d, rate, sinkSeeds(dom, ph.sinks), res.pressureCap,
                                       fastmarch::Stencil::kAvalanche26);
                        res.pressureSeconds += tp.seconds();
                    }
                    reachFromSinks(dom, st, ph.sinks);  // only the active sinks are searched from
                    std::fill(st.pressureTop.begin(), st.pressureTop.end(), -1.0);
                }
                std::fill(st.waterChanged.begin(), st.waterChanged.end(), std::uint8_t(1));
            }
            if (gravity) {
                table = fromSite ? dom.siteWaterTable
                                 : waterTableColumns(d, g.hydrology, hasTable ? ph.waterTable : double(d.nz));
                // The phase's pressure front: vadose voxels (air-filled) carry no head and keep p_rate,
                // so an abandoned upper passage does not short-circuit the phreatic zone to a spring.
                const Stopwatch tp;
                st.vadose.assign(n, 0);
                for (int k = 0; k < d.nz; ++k)
                    for (int j = 0; j < d.ny; ++j)
                        for (int i = 0; i < d.nx; ++i)
                            if (isVadose(d, table, i, j, k)) st.vadose[d.index(i, j, k)] = 1;
                if (!continued) {
                    rate = rateField(dom, g, st.vadose);
                    pressure.solve(d, rate, sinkSeeds(dom, ph.sinks), res.pressureCap,
                                   fastmarch::Stencil::kAvalanche26);
                    std::fill(st.pressureTop.begin(), st.pressureTop.end(), -1.0);
                }
                res.pressureSeconds += tp.seconds();
                // Every iteration writes the potential of the active tiles before any step reads it,
                // and no step reads it elsewhere: the whole grid from the current pressure is as
                // good as the phase's start for a resumed run.
                gravityPotential(pressure.value(), table, res.pressureCap, g, st, true, potential);
            }
        }

        while (it < phaseEnd) {
            ++it;
            Stage2Record rec;
            rec.iteration = it;
            const double storedBefore = stored;
            const Grid3<double>& P = pressure.value();

            const Stopwatch tt;
            if (byHead) headLevels(P, res.pressureCap, refill);
            rec.injected = refillSources(dom, refill, st, &res.sourceInjected);
            if (gravity) gravityPotential(P, table, res.pressureCap, g, st, false, potential);
            const Grid3<double>& T = gravity ? potential : P;  // what drives the water
            computeOffers(dom, T, g.weight, st);
            computeAcceptance(dom, T, g.weight, st);
            std::tie(rec.flow, rec.drained) = moveWater(dom, T, g.weight, st);
            res.transportSeconds += tt.seconds();

            const Stopwatch te;
            blendFlow(dom, T, g.blending, st);
            changed.clear();
            conducting.clear();
            rec.eroded = erode(dom, g, st, rate, changed, conducting);
            growActiveTiles(st);
            for (std::size_t sl = 0; sl < st.activeTiles.size(); ++sl)
                if (st.nearSender[sl])
                    for (std::uint8_t b : st.workMask[sl]) res.workedVoxelIterations += double(__builtin_popcount(b));
            res.erosionSeconds += te.seconds();

            // Pressure: propagate the decreases caused by new channel voxels.
            {
                const Stopwatch tp;
                const double needed =
                    gravity ? pressureNeeded(st, pressure.value()) : pressureRead(dom, st, pressure.value());
                rec.pressureUpdates = long(updatePressure(pressure, rate, changed, needed));
                res.pressureSeconds += tp.seconds();
            }

            // Bookkeeping.
            std::tie(stored, rec.channelVoxels) = waterAndChannels(dom, st, P, it);
            rec.stored = stored;
            rec.balanceError = std::abs((stored - storedBefore) - (rec.injected - rec.drained));
            res.totalInjected += rec.injected;
            res.totalDrained += rec.drained;
            if (phased) {
                prec.injected += rec.injected;
                prec.drained += rec.drained;
                prec.eroded += rec.eroded;
            }
            const std::vector<bool> conn = extendReach(dom, st, conducting);
            for (std::size_t si = 0; si < conn.size(); ++si) {
                if (conn[si]) {
                    ++rec.sourcesConnected;
                    if (!res.sourceConnectedIteration[si]) res.sourceConnectedIteration[si] = it;
                }
            }
            if (rec.sourcesConnected > 0 && !res.breakthroughIteration) res.breakthroughIteration = it;
            if (phased && rec.sourcesConnected > 0 && !prec.breakthroughIteration) prec.breakthroughIteration = it;
            res.history.push_back(rec);
            res.iterations = it;
            c.iteration = it;

            if (snapshot && std::find(g.snapshots.begin(), g.snapshots.end(), it) != g.snapshots.end()) {
                publish();  // the whole field for the picture
                snapshot(it, dom);
            }
            if (checkpoints.save && checkpoints.every > 0 && it % checkpoints.every == 0 && it < totalIterations) {
                res.seconds = secondsBefore + t0.seconds();
                checkpoints.save(it, encodeCarry(c, dom));
            }
            reportProgress(progress, "stage 2", it, totalIterations);
        }
        if (phased) {
            prec.iterations = ph.iterations;
            prec.channelVoxelsEnd = st.channelVoxels;
            caveAroundTable(dom, hasTable ? &table : nullptr, prec);
            res.phases.push_back(prec);
        }
    }
    if (phased) restoreSinks();

    res.activeTiles = long(st.activeTiles.size());
    res.tiles = long(st.tileSlot.size());
    publish();
    const double net = stored - (res.totalInjected - res.totalDrained);
    res.waterBalanceRelError = res.totalInjected > 0 ? std::abs(net) / res.totalInjected : 0.0;
    if (!(res.waterBalanceRelError < 1e-6)) {
        throw RuntimeError("stage 2: water not conserved (relative error " + std::to_string(res.waterBalanceRelError) +
                           ")");
    }
    res.seconds = secondsBefore + t0.seconds();
    return std::move(res);
}

}  // namespace cavesim

/// @file stage2_steps.h
/// @brief The named steps of one stage-2 iteration (paper §3.2, Listing 1, Eq. 1–2), each a free
/// function on the domain and a `Stage2State`, so each can be tested on a grid of a few voxels
/// against numbers computed by hand. `runStage2` (stage2.h) calls them in this order:
///
///  1. `refillSources`      sources refill to their level × R: the head above the field pressure
///                          (`headLevels`), or pressure / largest pressure
///  2. `computeOffers`      Listing 1 lines 1–9: each voxel's offer to each lower neighbour
///  3. `computeAcceptance`  a receiver offered more than its free capacity takes the same
///                          fraction of every offer
///  4. `moveWater`          the accepted water moves; f_c = what left a voxel; sinks drain
///  5. `blendFlow`          Eq. 2: f_a from the downhill neighbours ("max" or "split")
///  6. `erode`              Eq. 1: R += min(w0 · f^m, 1 − R), f = wa · f_a + f_c; new channels
///  7. `updatePressure`     decreases propagated from the voxels that became channel
///  8. bookkeeping          `waterAndChannels` (totals, the finite check) and
///                          `connectedSources` (sources joined to a sink)
///
/// Under a water table (`[hydrology]`, `[[phase]]`), steps 2–5 read the potential of
/// `gravityPotential` instead of the pressure: vadose water runs down under gravity.
///
/// Units: water and porosity in voxel-capacity units (a voxel of porosity R holds at most R);
/// pressure in the scenario's pressure units. All indices are voxel (index) space.
/// Every sum over neighbours pairs the −x and +x neighbour first (so an x-mirrored state gives
/// x-mirrored sums bit for bit); every voxel's update reads only the previous state (so the result
/// is the same for any thread count).
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "core/exact_sum.h"
#include "core/grid.h"
#include "fastmarch/fast_marching.h"
#include "sim/domain.h"
#include "sim/options.h"

namespace cavesim::stage2 {

/// Stage 2 works on tiles of 8 × 8 × 8 voxels (the last tile along an axis may be cut by the grid).
constexpr int kTileSize = 8;
constexpr std::size_t kTileVoxels = 512;
/// One bit per voxel of a tile: byte lj + 8·lk, bit li.
using TileMask = std::array<std::uint8_t, 64>;

/// The working state of stage 2 besides the domain. The water contents are dense (8 bytes a
/// voxel); everything else a step computes lives only on the **active tiles**: the tiles that
/// have held water and their 26 neighbour tiles (water moves at most one voxel per iteration, so
/// no voxel outside them can send, receive, flow or erode). Tiles are activated as water reaches
/// them and never deactivated, so the cost of an iteration follows the region the water reached,
/// not the block. Per-voxel transients of active tiles are indexed `slot · 512 + local`, where
/// `slot` is the tile's position in `activeTiles` and `local = li + 8·(lj + 8·lk)`.
struct Stage2State {
    explicit Stage2State(const Dims& dims);

    Dims dims;
    int tilesX = 0, tilesY = 0, tilesZ = 0;  ///< tiles along each axis
    std::vector<double> water;               ///< contents W of each voxel (dense)
    /// 1 where the voxel lies above the phase's water table (empty without a table): an air-filled
    /// passage carries no head, so the pressure front crosses such a voxel (not source or sink) at
    /// `p_rate` whatever its porosity or flags (`rateField`; docs/model.md, "Water table and gravity").
    std::vector<std::uint8_t> vadose;

    std::vector<std::int32_t> tileSlot;      ///< per tile of the grid: its slot, −1 when inactive
    std::vector<std::uint32_t> activeTiles;  ///< slot → tile id (ti + tilesX·(tj + tilesY·tk)), in activation order
    std::vector<std::uint8_t> tileWet;       ///< per tile of the grid: has held water (its neighbours are active)
    /// per slot: pool base (slot · 512) of the 27 tiles around it, index (dx+1) + 3(dy+1) + 9(dz+1); −1 inactive
    std::vector<std::array<std::int64_t, 27>> neighbourBase;
    std::vector<std::uint8_t> wetNow;        ///< per slot: holds water after the last moveWater
    std::vector<std::uint8_t> waterChanged;  ///< per slot: water changed since computeOffers last scanned it
    std::vector<double> pressureTop;         ///< per slot: an upper bound of its pressure (−1: not yet taken)
    std::vector<std::uint8_t> nearSender;    ///< per slot: some voxel of the tile works this iteration
    std::vector<TileMask> senderMask;        ///< per slot: voxels that send this iteration
    std::vector<TileMask> workMask;          ///< per slot: senders and their 26 neighbours (only these do work)
    std::vector<TileMask> previousMask;      ///< per slot: workMask of the last iteration
    /// per slot: the voxels holding at least 1e-9 of water (sinks included), the only ones that can
    /// send; kept up to date wherever water changes, so finding the senders reads no dry voxel
    std::vector<TileMask> flowingMask;
    /// per slot: the water of its voxels, an order-free sum kept up to date by every step that
    /// changes water (refillSources, moveWater), so the total needs no walk over the tiles
    std::vector<ExactSum> tileWater;

    // Per-voxel transients of the active tiles (slot · 512 + local).
    std::vector<double> norm;         ///< Σ weights of a sender's participants; 0 for a voxel that sends nothing
    std::vector<double> scale;        ///< min(1, W / Σ shares) of a sender
    std::vector<double> incoming;     ///< Σ of the offers a voxel received this iteration
    std::vector<double> accept;       ///< fraction of every offer a voxel accepts, [0, 1]
    std::vector<double> fc;           ///< f_c: water that left a voxel this iteration
    std::vector<double> fa;           ///< f_a of Eq. 2
    std::vector<double> upShare;      ///< "split" blending: f_c / number of uphill neighbours
    std::vector<double> drainedHere;  ///< water a sink voxel drained this iteration
    std::vector<double> erodedHere;   ///< ΔR of a voxel this iteration

    long channelVoxels = 0;     ///< voxels flagged channel
    std::vector<bool> reached;  ///< joined to a sink through channel, source and sink voxels

    /// Pool index of voxel v, or −1 when its tile is inactive.
    std::ptrdiff_t poolIndex(std::size_t v) const;
    /// A transient of voxel v (`absent` when its tile is inactive: the value every step leaves there).
    double at(const std::vector<double>& field, std::size_t v, double absent = 0.0) const;
    /// A transient of voxel v for writing (tests); activates its tile and marks it near a sender.
    double& ref(std::vector<double>& field, std::size_t v);
    /// Activates a tile (by tile id): transients with their resting values (accept 1, the rest 0).
    void activateTile(std::uint32_t tile);
    /// Updates `neighbourBase` after tiles were activated.
    void refreshTiles();
    /// Sums `tileWater` and marks `flowingMask` again from `water` (after water was set by hand, or
    /// restored).
    void recountWater();
};

/// Activates every tile holding water, and the tiles around them (a full-grid scan: for tests and
/// hand-made states; runStage2 grows the active tiles incrementally).
void activateWet(Stage2State& state);
/// Activates every tile of the grid (tests).
void activateAll(Stage2State& state);
/// After moveWater: tiles that hold water for the first time activate their 26 neighbour tiles.
/// Returns the number of tiles activated.
std::size_t growActiveTiles(Stage2State& state);

/// The 26 neighbour directions in the order every stage-2 sum uses: groups (dj, dk) with dk then
/// dj from −1 to 1, and in each group −x, +x, then x = 0 (absent for the centre group).
struct Slot {
    int di, dj, dk;
    double invLength;  ///< 1 / |offset|
    int opposite;      ///< the slot of the reverse direction
};
const std::array<Slot, 26>& slots();

/// A source voxel and the level it refills to, as a fraction of its porosity.
struct Refill {
    std::size_t voxel = 0;
    double level = 0;  ///< [0, 1]
    int source = 0;    ///< scenario index
    double head = 0;   ///< the source's pressure / the largest source pressure
};

/// Each source voxel's refill entry, level = head = its source's pressure / the largest source
/// pressure (`SourceInflow::kLevel`; the starting point of `headLevels`).
std::vector<Refill> refillLevels(const Domain& domain);

/// `SourceInflow::kHead`: each level becomes clamp(head − P(v) / cap, 0, 1): the source's head above
/// the field pressure at the voxel, as a fraction of the largest head `cap` (stage2PressureCap).
/// A channel that lowers the pressure at a source raises its inflow; only ratios of pressures enter.
void headLevels(const Grid3<double>& pressure, double cap, std::vector<Refill>& levels);

/// Step 1: every source voxel with contents below level × R is filled to it; returns the water
/// added, and adds each source's share to `perSource` (scenario order) when it is given.
double refillSources(const Domain& domain, const std::vector<Refill>& levels, Stage2State& state,
                     std::vector<double>* perSource = nullptr);

/// The pressure rate of one voxel (not a source or sink) with porosity R and initial porosity R0
/// under `RateRule::kPorosity`: s = (R − R0) / (threshold − R0) clamped to [0, 1] (1 when R0 is at
/// or above the threshold and R > R0), taken down to a multiple of 1/16, and
/// rate = pRate · (pRateChannel / pRate)^s; exactly pRateChannel at s = 1.
float porosityRate(float R, float R0, const Stage2Options& options);

/// Step 2 (Listing 1): for every voxel v holding water (at least 1e-9) and not a sink, each
/// lower-pressure neighbour u with free capacity R_u − W_u > 0 gets the offer
/// scale · weight(v→u) / Σ weight · (R_u − W_u), weight = (P_v − P_u) / |v − u| (proportional) or 1
/// (uniform), scale = min(1, W_v / Σ shares): never more in total than v holds.
/// Offers are not stored: a sender keeps its `norm` and `scale`, and every offer is recomputed
/// from them and the receiver's state where it is needed (`offerOf`), with the same arithmetic.
void computeOffers(const Domain& domain, const Grid3<double>& pressure, TransportWeight weight, Stage2State& state);

/// The offer voxel v makes this iteration to its neighbour in direction `slot` (after
/// computeOffers; 0 outside the grid).
double offerOf(const Domain& domain, const Grid3<double>& pressure, TransportWeight weight, const Stage2State& state,
               std::size_t v, int slot);

/// Step 3 (needs the pressure and weight to recompute the offers): incoming(u) = Σ offers to u; accept(u) = min(1, free
/// capacity / incoming) (a sink accepts everything; with nothing incoming, 1 — also for a voxel an ulp over full, whose
/// free capacity is slightly negative).
void computeAcceptance(const Domain& domain, const Grid3<double>& pressure, TransportWeight weight, Stage2State& state);

/// Step 4: moves the accepted water, sets f_c (water that left each voxel) and drains the sinks.
/// Returns {Σ f_c, water drained}, both order-free sums (ExactSum).
std::pair<double, double> moveWater(const Domain& domain, const Grid3<double>& pressure, TransportWeight weight,
                                    Stage2State& state);

/// Step 5 (Eq. 2): f_a of each voxel from its lower-pressure neighbours: the largest f_c among
/// them (kMax), or the sum of the shares f_c / (number of their uphill neighbours) (kSplit).
void blendFlow(const Domain& domain, const Grid3<double>& pressure, FlowBlending blending, Stage2State& state);

/// Step 6 (Eq. 1): for every voxel that is neither source nor sink, f = wa · f_a + f_c and
/// R += min(w0 · f^m, 1 − R); domain.flow = f. A voxel whose porosity reaches the channel
/// threshold (and exceeds its initial porosity) becomes channel. A voxel that opened or became
/// channel takes the rate `rateField`'s rule gives it now (pRateChannel on a channel, the porosity
/// rate on a protochannel) in `rate` when that is lower, and its index is appended to `newChannel`
/// (tile by tile); every voxel newly flagged channel is appended to `newConducting` and counted
/// in `state.channelVoxels`.
/// Only active tiles are visited (elsewhere f = 0 and porosity does not change). Returns Σ ΔR, an
/// order-free sum (ExactSum).
double erode(Domain& domain, const Stage2Options& options, Stage2State& state, Grid3<float>& rate,
             std::vector<std::size_t>& newChannel, std::vector<std::size_t>& newConducting);

/// Before the first iteration (one sweep of the grid, the only one of stage 2): counts the channel
/// voxels, flags every voxel that already meets the channel rule (porosity ≥ threshold and above
/// its initial value; after prepareStage2 only protochannels opened past the threshold) and
/// lowers its rate, activates the tiles around the sources, and marks what is joined to a sink.
void startStage2(Domain& domain, const Stage2Options& options, Stage2State& state, Grid3<float>& rate);

/// Step 7: the pressure after the voxels in `newChannel` took the channel rate (rates only fall,
/// so pressure only falls): the decrease re-propagated from them through `pressure`. Returns the
/// number of voxels whose pressure changed.
/// Only values up to `limit` are made final (pressureRead, or pressureNeeded with a water table:
/// bounds of every pressure the next iteration depends on); the rest of the sweep waits in `pressure`
/// until it is needed or settled (EikonalField::decrease). Returns the number of voxels whose
/// pressure changed in this call.
std::size_t updatePressure(fastmarch::EikonalField& pressure, const Grid3<float>& rate,
                           const std::vector<std::size_t>& newChannel,
                           double limit = std::numeric_limits<double>::infinity());

/// An upper bound of the true pressure of every voxel the next iteration reads: the largest
/// pressure stored on each active tile when it was first asked (pressure only falls).
double pressureNeeded(Stage2State& state, const Grid3<double>& pressure);

/// An upper bound of the true pressure of every voxel whose pressure decides what the next
/// iteration does without a water table: the largest stored pressure of its senders (voxels
/// holding water, sources). A neighbour above the bound is not offered water whether its stored
/// value is final or not (stored values only exceed the true ones), so only values up to the bound
/// need be final.
double pressureRead(const Domain& dom, const Stage2State& state, const Grid3<double>& pressure);

/// Sources joined to a sink through channel voxels (26-connected through channel, source and
/// sink voxels), in source order. A breadth-first search over the whole grid: the reference for
/// tests; runStage2 uses the incremental `extendReach`.
std::vector<bool> connectedSources(const Domain& domain);

/// Marks as reached everything joined to a sink in `sinks` (1-based; empty = all) through channel,
/// source and sink voxels, from scratch (startStage2 and each phase of runStage2 call it once).
void reachFromSinks(const Domain& domain, Stage2State& state, const std::vector<int>& sinks = {});

/// Incremental connectivity: the conducting voxels only grow, so after `newConducting` joined them
/// only what a new voxel touches can become reached: a search from each new voxel that touches a
/// reached one. Returns the sources (in order) with a reached voxel.
std::vector<bool> extendReach(const Domain& domain, Stage2State& state, const std::vector<std::size_t>& newConducting);

/// Step 8: Σ water (the order-free sum of the tiles' `tileWater`: there is no water outside the
/// active tiles) and `state.channelVoxels`, with the finite check: water anywhere (a non-finite
/// value makes its tile's sum bad), flow and pressure where something worked this iteration (the
/// work masks of the tiles near a sender; nothing else changed flow, and these are the pressures
/// the water reads). A failure throws RuntimeError naming the iteration, the quantity that went
/// bad first (acceptance, incoming water, f_c, water, f_a, pressure, porosity, flow) and its first
/// voxel on the active tiles.
std::pair<double, long> waterAndChannels(const Domain& domain, const Stage2State& state, const Grid3<double>& pressure,
                                         int iteration);

/// The water table's height z (voxel index units) at the centre of each column, index i + nx · j: a
/// plane through `level` at the centre column ((nx − 1) / 2, (ny − 1) / 2) that falls at
/// tan(hydrology.dip) towards `hydrology.dipDirection` (degrees clockwise from +y).
std::vector<double> waterTableColumns(const Dims& dims, const Hydrology& hydrology, double level);

/// True if voxel (i, j, k) is vadose under the table `table` (from waterTableColumns): its centre
/// lies above the table.
inline bool isVadose(const Dims& dims, const std::vector<double>& table, int i, int j, int k) {
    return double(k) > table[std::size_t(i) + std::size_t(dims.nx) * std::size_t(j)];
}

/// The vadose rule (docs/model.md, "Water table and gravity"): the potential that drives the
/// transport, blending and erosion steps in place of the pressure. Phreatic voxels (centre at or
/// below the table): Φ = P, the paper's pressure. Vadose voxels: Φ = cap + pRate · (k − table) +
/// lateral · P — water is not pressurised there and runs downhill: every vadose voxel lies above
/// every phreatic one (P ≤ cap), one voxel down is always lower (by at least pRate · (1 − lateral)),
/// and on a level floor water drifts towards lower field pressure, the sinks. Written on the
/// active tiles, or (all) on the whole grid. Units: pressure units; k and table in voxels.
void gravityPotential(const Grid3<double>& pressure, const std::vector<double>& table, double cap,
                      const Stage2Options& options, const Stage2State& state, bool all, Grid3<double>& potential);

/// The pressure rate field of a domain: pRateChannel on channel, source and sink voxels; elsewhere
/// `porosityRate` (RateRule::kPorosity), or pRateChannel on protochannels and pRate on the rest
/// (RateRule::kChannelFlag). On an inception horizon (`Domain::inception`) a voxel that is not
/// channel, source or sink takes at most porosityRate(R, rock porosity), under either rule. Where
/// `vadose` (Stage2State::vadose; empty = none) is 1, a voxel that is neither source nor sink takes
/// pRate whatever its porosity or flags: an air-filled passage carries no head.
Grid3<float> rateField(const Domain& domain, const Stage2Options& options,
                       const std::vector<std::uint8_t>& vadose = {});

}  // namespace cavesim::stage2

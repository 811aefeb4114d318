/// @file stage2_steps.h
/// @brief The named steps of one stage-2 iteration (paper §3.2, Listing 1, Eq. 1–2), each a free
/// function on the domain and a `Stage2State`, so each can be tested on a grid of a few voxels
/// against numbers computed by hand. `runStage2` (stage2.h) calls them in this order:
///
///  1. `refillSources`      sources refill to their level (pressure / largest pressure) × R
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
/// Units: water and porosity in voxel-capacity units (a voxel of porosity R holds at most R);
/// pressure in the scenario's pressure units. All indices are voxel (index) space.
/// Every sum over neighbours pairs the −x and +x neighbour first (so an x-mirrored state gives
/// x-mirrored sums bit for bit); every voxel's update reads only the previous state (so the result
/// is the same for any thread count).
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/grid.h"
#include "fastmarch/fast_marching.h"
#include "sim/domain.h"
#include "sim/options.h"

namespace cavesim::stage2 {

/// The working state of stage 2 besides the domain: water in double precision and the per-step
/// arrays, all of the domain's size.
struct Stage2State {
    explicit Stage2State(const Dims& dims);

    std::vector<double> water;     ///< contents W of each voxel
    std::vector<double> incoming;  ///< Σ of the offers a voxel received this iteration
    std::vector<double> accept;    ///< fraction of every offer a voxel accepts, [0, 1]
    std::vector<double> fc;        ///< f_c: water that left a voxel this iteration
    std::vector<double> fa;        ///< f_a of Eq. 2
    std::vector<double> upShare;   ///< "split" blending: f_c / number of uphill neighbours
    /// offer(s, v): what voxel v offers its neighbour in direction slot s (slot-major).
    std::vector<double> offerStore;
    std::vector<std::uint8_t> hadOffers;  ///< v's offers may be non-zero
    /// Per row (j, k): some contents, some offers, some outflow. Rows far from any water skip work.
    std::vector<std::uint8_t> wetRow, offerRow, flowRow;

    double* offer(int slot) { return offerStore.data() + std::size_t(slot) * water.size(); }
    const double* offer(int slot) const { return offerStore.data() + std::size_t(slot) * water.size(); }
};

/// The 26 neighbour directions in the order every stage-2 sum uses: groups (dj, dk) with dk then
/// dj from −1 to 1, and in each group −x, +x, then x = 0 (absent for the centre group).
struct Slot {
    int di, dj, dk;
    double invLength;  ///< 1 / |offset|
    int opposite;      ///< the slot of the reverse direction
};
const std::array<Slot, 26>& slots();

/// A source voxel and the level it refills to, as a fraction of its porosity.
using Refill = std::pair<std::size_t, double>;

/// Each source voxel's refill level: its source's pressure / the largest source pressure.
std::vector<Refill> refillLevels(const Domain& domain);

/// Step 1: every source voxel with contents below level × R is filled to it; returns the water
/// added.
double refillSources(const Domain& domain, const std::vector<Refill>& levels, Stage2State& state);

/// Step 2 (Listing 1): for every voxel v holding water (at least 1e-9) and not a sink, each
/// lower-pressure neighbour u with free capacity R_u − W_u > 0 gets the offer
/// scale · weight(v→u) / Σ weight · (R_u − W_u), weight = (P_v − P_u) / |v − u| (proportional) or 1
/// (uniform), scale = min(1, W_v / Σ shares): never more in total than v holds.
void computeOffers(const Domain& domain, const Grid3<double>& pressure, TransportWeight weight, Stage2State& state);

/// Step 3: incoming(u) = Σ offers to u; accept(u) = min(1, free capacity / incoming) (a sink
/// accepts everything; with nothing incoming, 1 — also for a voxel an ulp over full, whose free
/// capacity is slightly negative).
void computeAcceptance(const Domain& domain, Stage2State& state);

/// Step 4: moves the accepted water, sets f_c (water that left each voxel) and drains the sinks.
/// Returns {Σ f_c, water drained}.
std::pair<double, double> moveWater(const Domain& domain, Stage2State& state);

/// Step 5 (Eq. 2): f_a of each voxel from its lower-pressure neighbours: the largest f_c among
/// them (kMax), or the sum of the shares f_c / (number of their uphill neighbours) (kSplit).
void blendFlow(const Domain& domain, const Grid3<double>& pressure, FlowBlending blending, Stage2State& state);

/// Step 6 (Eq. 1): for every voxel that is neither source nor sink, f = wa · f_a + f_c and
/// R += min(w0 · f^m, 1 − R); domain.flow = f. A voxel whose porosity reaches the channel
/// threshold (and exceeds its initial porosity) becomes channel; its pressure rate drops to
/// pRateChannel in `rate`, and its index is appended to `newChannel`. Returns Σ ΔR.
double erode(Domain& domain, const Stage2Options& options, const Stage2State& state, Grid3<float>& rate,
             std::vector<std::size_t>& newChannel);

/// Step 7: the pressure after the voxels in `newChannel` took the channel rate (rates only fall,
/// so pressure only falls): the decrease re-propagated from them through `pressure`. Returns the
/// number of voxels whose pressure changed.
std::size_t updatePressure(fastmarch::EikonalField& pressure, const Grid3<float>& rate,
                           const std::vector<std::size_t>& newChannel);

/// Sources joined to a sink through channel voxels (26-connected through channel, source and
/// sink voxels), in source order.
std::vector<bool> connectedSources(const Domain& domain);

/// Step 8: Σ water and the number of channel voxels, with the finite check: non-finite water,
/// flow or pressure throws RuntimeError naming the iteration, the quantity that went bad first
/// (acceptance, incoming water, f_c, water, f_a, pressure, porosity, flow) and its first voxel.
std::pair<double, long> waterAndChannels(const Domain& domain, const Stage2State& state,
                                         const Grid3<double>& pressure, int iteration);

/// The pressure rate field of a domain: pRateChannel on channel, protochannel, source and sink
/// voxels, pRate elsewhere.
Grid3<float> rateField(const Domain& domain, const Stage2Options& options);

}  // namespace cavesim::stage2

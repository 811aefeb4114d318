/// @file stage2.h
/// @brief Stage 2 of Pytel & Mann (JCGT 2015, §3.2, §5, Listing 1, Eq. 1–2): channel growth and linkage.
///
/// One iteration:
///  1. **Pressure front** (the "avalanche"): sinks hold P = 0; pressure rises by at most
///     `pRate` per voxel of rock and `pRateChannel` per voxel of channel, capped at the source
///     pressure. Solved by fast marching from the sinks; afterwards only decreases are propagated
///     from voxels whose rate fell (erosion only lowers rates, so pressure only drops).
///  2. **Water transport** (Listing 1, 26 neighbours): each voxel offers water to lower-pressure
///     neighbours with free capacity, a share weight(ΔP)·(capacity − contents) each, never more
///     than it holds. Made order-free and deterministic as a two-phase Jacobi step: all offers are
///     computed from the state at the start of the iteration; a receiver offered more than its free
///     capacity accepts the same fraction of every offer. Sources refill, sinks drain; each
///     iteration's balance is recorded (`Stage2Record::balanceError`) and the whole run's is
///     checked at the end (relative error below 1e-6, else RuntimeError).
///  3. **Flow blending** (Eq. 2): f_a of a voxel from the f_c of its lower-pressure neighbours —
///     the largest of them (`FlowBlending::kMax`, the default), or the sum of the shares each
///     passes, f_c split equally over its uphill neighbours (`kSplit`); f = w_a·f_a + f_c.
///  4. **Erosion** (Eq. 1): R += min(w_0·f^m, 1 − R); capacity follows R.
///  5. **Bookkeeping**: a voxel eroded to `channelThreshold` becomes channel (and takes the
///     channel pressure rate); breakthrough = the first iteration a channel joins a source to a sink.
///
/// The steps are named functions in sim/stage2_steps.h, each tested against hand-computed numbers.
/// They work only where water is: on the 8³ tiles water reached (and their neighbours), and there
/// only on the senders and their 26 neighbours; the pressure decrease is propagated only as far as
/// those voxels read it (docs/model.md, "Where stage 2 works").
/// Every sum over neighbours pairs the −x and +x neighbour first, so an x-mirrored scenario gives
/// an x-mirrored result bit for bit; every voxel's update reads only the previous state, so the
/// result is the same for any thread count.
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/progress.h"
#include "sim/domain.h"
#include "sim/options.h"

namespace cavesim {

/// Totals of one stage-2 iteration. Water and volume in voxel units (porosity × voxels).
struct Stage2Record {
    int iteration = 0;
    double injected = 0;       ///< water added at sources
    double drained = 0;        ///< water removed at sinks
    double stored = 0;         ///< water in the domain after the iteration
    double flow = 0;           ///< Σ f_c: water moved this iteration
    double eroded = 0;         ///< Σ ΔR this iteration
    long channelVoxels = 0;    ///< voxels flagged channel after the iteration
    long pressureUpdates = 0;  ///< voxels whose pressure changed this iteration
    int sourcesConnected = 0;  ///< sources joined to a sink through channel voxels
    double balanceError = 0;   ///< |Δstored − (injected − drained)| this iteration
};

/// Totals of one base-level phase (`[[phase]]`, or the single phase of a run with a water table).
/// Volumes in voxels (the report converts them to m³).
struct Stage2PhaseRecord {
    int firstIteration = 0;  ///< the phase's first iteration (1-based, run order)
    int iterations = 0;      ///< iterations the phase ran
    /// voxels: the table's height at the centre column; −1 none (also for a site's surface: `fromSite`)
    double waterTable = -1;
    bool fromSite = false;                     ///< the table was `[site] water_table`
    std::vector<int> sinks, sources;           ///< active terminals, 1-based scenario order
    std::optional<int> breakthroughIteration;  ///< first iteration of the phase with a source joined to an active sink
    long channelVoxelsStart = 0;               ///< channel voxels when the phase began
    long channelVoxelsEnd = 0;                 ///< channel voxels when it ended
    long caveBelow = 0, caveAbove = 0;         ///< channel voxels at or below / above the phase's table at its end
    /// voxels: bounding box (lo, hi per axis, inclusive) of the channel voxels above the table at the
    /// phase's end; lo > hi when there are none
    std::array<int, 3> aboveLo{0, 0, 0}, aboveHi{-1, -1, -1};
    std::array<int, 3> belowLo{0, 0, 0}, belowHi{-1, -1, -1};  ///< the same, at or below the table
    double aboveSliceMean = 0;  ///< channel voxels above the table per z-slice that holds any (a plan-view width)
    double injected = 0, drained = 0, eroded = 0;  ///< water and porosity totals of the phase
};

struct Stage2Result {
    int iterations = 0;
    std::optional<int> breakthroughIteration;                  ///< first iteration with a source joined to a sink
    std::vector<std::optional<int>> sourceConnectedIteration;  ///< per source, scenario order
    double waterBalanceRelError = 0;  ///< |stored_end − stored_0 − (injected − drained)| / injected
    double totalInjected = 0, totalDrained = 0;
    std::vector<double> sourceInjected;  ///< water injected by each source over the run, scenario order
    double pressureCap = 0;              ///< the source pressure used as cap
    std::vector<Stage2Record> history;
    double seconds = 0;
    double pressureSeconds = 0, transportSeconds = 0, erosionSeconds = 0;
    double workedVoxelIterations = 0;  ///< Σ over iterations of the voxels that worked (senders and their neighbours)
    long activeTiles = 0;              ///< 8³ tiles the water reached, with their neighbours, at the end
    long tiles = 0;                    ///< 8³ tiles of the block
    /// per phase, in order; empty without `[hydrology]` and `[[phase]]` (the paper's model)
    std::vector<Stage2PhaseRecord> phases;
};

/// Called after the iterations listed in `[stage2] snapshots` (and never otherwise).
using SnapshotFn = std::function<void(int iteration, const Domain& domain)>;

/// Checkpoints of stage 2: its whole state between two iterations as bytes
/// (sim/stage2_checkpoint.h), to continue a stopped run bit for bit.
struct Stage2Checkpoints {
    int every = 0;  ///< iterations between checkpoints; 0: none
    /// Called after every `every`-th iteration except the last (after its snapshot) with the
    /// iteration and the state's bytes.
    std::function<void(int iteration, const std::string& state)> save;
    /// Not null: continue from these bytes (a state `save` received, for this domain after
    /// `prepareStage2`) with the iteration after theirs, instead of starting.
    const std::string* resume = nullptr;
    std::string resumeName;  ///< names `resume`'s source in messages
};

/// The interim step between the stages (paper §4): porosity back to its initial values,
/// protochannel voxels raised to `options.protochannelPorosity`, sources set to
/// `options.sourcePorosity` and sinks opened (porosity 1: they are the inlets and outlets);
/// water, flow, pressure and channel flags cleared. Protochannel voxels keep their flag and so the
/// channel pressure rate. Also used for stage-2-only runs, whose protochannels come from
/// `[[rock.channel]]`.
void prepareStage2(Domain& domain, const Stage2Options& options);

/// The stage-2 pressure cap, the head of the strongest source: the largest source pressure ×
/// `options.pressureScale`, or, when that is 0, 2 · pRate · (nx + ny + nz) (whatever the source
/// pressures: only their ratios matter then).
double stage2PressureCap(const Domain& domain, const Stage2Options& options);

/// Runs the stage-2 iterations on a prepared domain: `options.iterations`, or the `options.phases`
/// in order, each with its water table and active terminals (inactive sinks neither drain nor hold
/// the pressure at 0 and are not eroded; inactive sources do not refill). The flags of the
/// terminals are as given again when it returns.
/// @throw RuntimeError if water conservation or finiteness is violated (a bug, never user input)
/// With `checkpoints`, saves its state every so many iterations, or continues from a saved state:
/// the result is the same bits either way.
/// @throw InputError when `checkpoints.resume` is not a state of this domain and these phases
///        (damaged bytes, or a state of another scenario)
Stage2Result runStage2(Domain& domain, const Stage2Options& options, const ProgressFn& progress = {},
                       const SnapshotFn& snapshot = {}, const Stage2Checkpoints& checkpoints = {});

/// Recomputes the pressure of the current domain from scratch (used by tests and by the
/// incremental-update check): same rule as inside runStage2.
Grid3<double> solvePressureFull(const Domain& domain, const Stage2Options& options);

}  // namespace cavesim

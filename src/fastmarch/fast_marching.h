/// @file fast_marching.h
/// @brief Fast marching on the voxel grid (Sethian 1996): first-order Godunov upwind update over
/// the 6 face neighbours, a binary heap ordering the narrow band (the 26-neighbour avalanche
/// stencil uses a bucket queue where the buckets can be as narrow as its smallest edge cost).
///
/// Two uses in cavesim (Pytel & Mann, JCGT 2015):
///  - `marchLabelled`: several labelled fronts race in one queue; every voxel takes the label of
///    the front that reaches it first (stage 1 pressure zones, paper §3.1).
///  - `EikonalField`: the stage-2 pressure front (paper §3.2), P(x) = min(cap, arrival time)
///    with per-voxel rise rate = slowness, solved once and then updated incrementally when rates
///    only fall (the "avalanche": decrease-only re-propagation from the changed voxels).
///
/// All positions are linear voxel indices of a `Dims` box (index space, unit spacing). Ties are
/// broken by value, then by voxel index, so results do not depend on insertion order; the update
/// pairs −x with +x first so an x-mirrored input gives an x-mirrored result bit for bit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "core/bytes.h"
#include "core/grid.h"
#include "core/progress.h"

namespace cavesim::fastmarch {

/// A front's starting voxel: its initial value and (for `marchLabelled`) its label.
struct Seed {
    std::size_t voxel = 0;  ///< linear index into the Dims box
    double value = 0.0;     ///< initial arrival value, ≥ 0
    int label = 0;          ///< front label, ≥ 0 (index into `labelSpeed`)
};

/// Arrival times and winning labels; voxels never reached have time +inf and label −1.
struct LabelledArrival {
    Grid3<double> time;
    Grid3<std::int32_t> label;
};

/// Several fronts march at once through a shared slowness field, in one queue: front `l` moves with
/// speed `labelSpeed[l] / slowness(x)` (its arrival time solves |∇T| = slowness / labelSpeed[l]),
/// and each voxel joins the front with the smallest arrival time (ties: the lower label), each
/// front's time being that of the front marched alone over the whole grid (first-order Godunov,
/// 6 neighbours): the per-front minimum. With uniform slowness the zones are the multiplicatively
/// weighted Voronoi cells: a bisector plane for equal speeds, an Apollonius sphere for unequal
/// ones, which the faster front crosses. A voxel keeps a time per front that reaches it; front `l`
/// stops propagating at a voxel where a front at least as fast settled three of `l`'s steps
/// earlier (it cannot win beyond). Exact where front `l` propagates; a time beside a zone boundary
/// may differ from the lone march in the last digits (it can take in, with a tiny weight, `l`'s
/// time from where `l` stopped), so labels may differ only at near-ties (docs/model.md "Zones").
/// Cost O(voxels · log voxels) plus the overlap: a band of about 1.5 voxels per side of a boundary
/// for equal speeds, the weaker zones crossed by the faster fronts for unequal ones. Serial, and
/// ordered by (time, voxel, label), so the result does not depend on the thread count, and an
/// input mirrored in x, y or z (slowness and seeds, each seed keeping its label) gives the
/// mirrored result.
/// @param dims        the grid
/// @param slowness    per-voxel slowness, > 0, or +inf for impassable; nullptr = 1 everywhere
/// @param seeds       starting voxels with their starting times (finite, ≥ 0); a voxel listed
///                    twice for one label keeps the smaller time; a seed's time stays its
///                    label's time there, and another label arriving earlier takes the voxel
/// @param labelSpeed  speed factor of each label, > 0
/// @param progress    called with `progressPhase`, the voxels settled so far (by their winning
///                    front) and the grid's voxel count, every 2^20 settled voxels (empty = none); it
///                    may throw `Cancelled` to stop the march
/// @param progressPhase the phase name passed to `progress`
/// @throw cavesim::InternalError on a seed outside the grid, a negative label, a label without
///        speed or a seed time that is negative or not finite
LabelledArrival marchLabelled(const Dims& dims, const Grid3<float>* slowness, const std::vector<Seed>& seeds,
                              const std::vector<double>& labelSpeed, const ProgressFn& progress = {},
                              const std::string& progressPhase = "fast marching");

/// How a voxel's value is computed from its neighbours.
enum class Stencil {
    /// First-order Godunov upwind update over the 6 face neighbours (classic fast marching).
    kFace6,
    /// One step from any of the 26 neighbours y at cost slowness(x) · |x − y| (lengths 1, √2,
    /// √3): T(x) = min_y T(y) + slowness(x)·|x − y|. This is the stage-2 "avalanche" rule of the
    /// paper (§3.2: pressure rises from a neighbour by at most rate · distance) exactly, solved
    /// as Dijkstra on the 26-neighbour graph. Unlike kFace6 it lets a channel that is only edge-
    /// or corner-connected carry low pressure; in open rock it overestimates Euclidean distance
    /// by at most 8 % in a plane (13 % in space), the price of the 26-neighbour metric.
    kAvalanche26,
};

/// Solution of |∇T| = slowness from seeds, capped at `cap`: T(x) = min(cap, min over paths of
/// Σ slowness · length) in the first-order upwind discretisation chosen by `Stencil`.
class EikonalField {
public:
    /// Full solve. `slowness` > 0 everywhere (finite); seeds hold their `value`.
    void solve(const Dims& dims, const Grid3<float>& slowness, const std::vector<Seed>& seeds, double cap,
               Stencil stencil = Stencil::kFace6);

    /// Incremental update after the slowness of the voxels in `changed` has decreased (and nowhere
    /// increased): values only fall. Re-propagates from the changed voxels and their neighbours
    /// with a label-correcting heap sweep; equals a fresh `solve` up to round-off.
    ///
    /// With a finite `limit` the sweep stops at values above it: every voxel whose value is at
    /// most `limit` is then final, every other one may still be too high, and the rest of the sweep
    /// waits (pending) for the next call or `settle`. Values computed in several such steps are the
    /// same bits as in one step (each is the minimum over paths of the same rounded path costs).
    /// @return the number of voxels whose value changed in this call
    std::size_t decrease(const Grid3<float>& slowness, const std::vector<std::size_t>& changed,
                         double limit = std::numeric_limits<double>::infinity());

    /// Completes a limited `decrease`: afterwards every value is final.
    /// @return the number of voxels whose value changed
    std::size_t settle(const Grid3<float>& slowness);

    /// True when no limited sweep is pending (every value is final).
    bool settled() const { return pending_.empty() && buckets_.count == 0 && windows_.count == 0; }

    /// The avalanche stencil's queue: entries (value, voxel) bucketed by value.
    struct Buckets {
        std::vector<std::vector<std::pair<double, std::size_t>>> bucket;
        double width = 1.0;         ///< value range of one bucket
        std::size_t lowest = 0;     ///< no entry lies in a bucket below this
        std::size_t count = 0;      ///< entries (pending ones between calls)
        std::size_t compacted = 0;  ///< count after the last clean-up
    };

    /// The avalanche sweep's second queue: entries of voxels without light steps (see the .cpp),
    /// by window — a run of `span` buckets — in one list per worker slot, in any order (a window's
    /// entries are taken all at once). Together with `Buckets` it holds the queue.
    struct Windows {
        std::vector<std::vector<std::vector<std::pair<double, std::size_t>>>> slot;  ///< [worker][window]
        std::size_t span = 1;                                                        ///< buckets per window
        std::size_t lowest = 0;     ///< no entry lies in a window below this
        std::size_t count = 0;      ///< entries (pending ones between calls)
        std::size_t compacted = 0;  ///< count after the last clean-up
    };

    const Grid3<double>& value() const { return value_; }
    double cap() const { return cap_; }

    /// Appends everything the field carries from one call to the next (values, seeds, the stencil,
    /// the queue with the pending part of a limited sweep) to `out`: a field restored from these
    /// bytes returns the same bits from every later call (checkpoints). The bucket queue is written
    /// as its current entries (stale ones lower nothing), each in the bucket of its value, ordered
    /// by (value, voxel): the same bytes for any thread count. The format is unchanged, so older
    /// files, which also hold stale entries in push order, load as before.
    void save(ByteWriter& out) const;
    /// Replaces this field by one `save` wrote for a grid of `dims`.
    /// @throw InputError (from `in`) on bytes that are not such a field: sizes, voxel indices and
    ///        queue bookkeeping are all checked before use
    void restore(ByteReader& in, const Dims& dims);

private:
    /// Bucket queue: the heavy step cost (`largest`, the largest slowness in `slowness`, s per
    /// voxel), the flags and the window span from `slowness` (the windows empty).
    void prepareSweep(const Grid3<float>& slowness, double largest);

    Dims dims_;
    double cap_ = 0.0;
    Stencil stencil_ = Stencil::kFace6;
    Grid3<double> value_;
    std::vector<std::uint8_t> seed_;                       ///< 1 where a seed holds its value
    std::vector<std::uint8_t> touched_;                    ///< scratch of `decrease`, all 0 between calls
    std::vector<std::pair<double, std::size_t>> pending_;  ///< heap entries above the last limit
    std::size_t pendingCompacted_ = 0;                     ///< size of pending_ after its last clean-up
    Buckets buckets_;                                      ///< kAvalanche26: the queue; pending entries between calls
    bool useBuckets_ = false;                              ///< the queue is `buckets_` (else a heap)
    Windows windows_;                                      ///< kAvalanche26: the queue's entries without light steps
    double heavy_ = 0.0;               ///< bucket queue: steps costing this or more wait and run batched
    std::vector<std::uint8_t> flags_;  ///< bucket queue: per voxel, may have a light step / seed / on a face
                                       ///< (empty after `restore`: rebuilt by the next call)
};

/// The first-order Godunov upwind update of one voxel from the values of its face neighbours
/// (+inf where unknown), with local slowness `f`. Exposed for tests.
double upwindUpdate(double ax, double ay, double az, double f);

}  // namespace cavesim::fastmarch

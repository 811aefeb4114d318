/// @file fast_marching.cpp
/// @brief Fast marching: Godunov upwind update, labelled fronts, capped eikonal with incremental
/// decrease-only updates.
#include "fastmarch/fast_marching.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <string>
#include <type_traits>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/check.h"

namespace cavesim::fastmarch {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Min-heap of (value, voxel); equal values pop in voxel order, so runs are reproducible.
using HeapEntry = std::pair<double, std::size_t>;
/// The same operations and order as std::priority_queue with std::greater, with its vector open
/// (EikonalField keeps pending entries between calls).
struct MinHeap {
    std::vector<HeapEntry> c;
    bool empty() const { return c.empty(); }
    const HeapEntry& top() const { return c.front(); }
    void push(const HeapEntry& e) {
        c.push_back(e);
        std::push_heap(c.begin(), c.end(), std::greater<HeapEntry>());
    }
    void pop() {
        std::pop_heap(c.begin(), c.end(), std::greater<HeapEntry>());
        c.pop_back();
    }
    /// No entry left is below this.
    double bound() const { return c.front().first; }
};

/// Entries in buckets of values [b·width, (b+1)·width): a bucket queue (Dial). With a width at
/// most the smallest edge cost, nothing popped from a bucket can lower another entry of the same
/// bucket, so a bucket may be drained in any order and each voxel settles once, as with a heap,
/// at O(1) per push and pop. With a wider bucket a voxel may be lowered again within its bucket;
/// the sweep is label-correcting either way and ends at the same values (each value is the
/// minimum over paths of the same rounded path costs, whatever the order).
struct BucketQueue {
    EikonalField::Buckets& q;
    bool empty() const { return q.count == 0; }
    std::size_t index(double v) const {
        const double b = v / q.width;
        return b >= double(q.bucket.size() - 1) ? q.bucket.size() - 1 : std::size_t(b);
    }
    void push(const HeapEntry& e) {
        const std::size_t b = index(e.first);
        q.bucket[b].push_back(e);
        q.lowest = std::min(q.lowest, b);
        ++q.count;
    }
    const HeapEntry& top() {
        while (q.bucket[q.lowest].empty()) {
            // A drained bucket gives its memory back: the buckets together hold only the front.
            if (q.bucket[q.lowest].capacity() > 64) std::vector<HeapEntry>().swap(q.bucket[q.lowest]);
            ++q.lowest;
        }
        return q.bucket[q.lowest].back();
    }
    void pop() {
        q.bucket[q.lowest].pop_back();
        --q.count;
    }
    double bound() {
        top();
        return double(q.lowest) * q.width;
    }
};

/// Smallest value of the two neighbours along one axis; −x and +x (or −y/+y, −z/+z) are combined
/// by std::min, which is symmetric, so mirrored inputs give mirrored results.
template <typename Get>
void axisMinima(const Dims& d, const Index3& p, const Get& get, double& ax, double& ay, double& az) {
    ax = std::min(p.i > 0 ? get(d.index(p.i - 1, p.j, p.k)) : kInf,
                  p.i + 1 < d.nx ? get(d.index(p.i + 1, p.j, p.k)) : kInf);
    ay = std::min(p.j > 0 ? get(d.index(p.i, p.j - 1, p.k)) : kInf,
                  p.j + 1 < d.ny ? get(d.index(p.i, p.j + 1, p.k)) : kInf);
    az = std::min(p.k > 0 ? get(d.index(p.i, p.j, p.k - 1)) : kInf,
                  p.k + 1 < d.nz ? get(d.index(p.i, p.j, p.k + 1)) : kInf);
}

/// The value of voxel r from all its neighbours' current values (the full update rule).
template <typename Get>
double fullUpdate(const Dims& d, const Index3& p, const Get& get, double f, Stencil stencil, double cap) {
    double u = std::numeric_limits<double>::infinity();
    if (stencil == Stencil::kAvalanche26) {
        for (const auto& o : allNeighbours()) {
            const int i = p.i + o.di, j = p.j + o.dj, k = p.k + o.dk;
            if (d.contains(i, j, k)) u = std::min(u, get(d.index(i, j, k)) + f * o.length);
        }
    } else {
        double ax, ay, az;
        axisMinima(d, p, get, ax, ay, az);
        u = upwindUpdate(ax, ay, az, f);
    }
    return std::min(cap, u);
}

/// Label-correcting sweep shared by `solve` and `decrease`: pops the smallest tentative value and
/// re-evaluates its neighbours: the Godunov update of each face neighbour from the current values
/// of all its face neighbours (kFace6), or one step from the popped voxel to each of its 26
/// neighbours (kAvalanche26: Dijkstra on the 26-neighbour graph). With heap order this is fast marching (each voxel
/// settles once when values only fall); it also repairs a field whose slowness fell locally without touching the rest.
template <typename Queue>
std::size_t relax(const Dims& d, const Grid3<float>& slowness, const std::vector<std::uint8_t>& seed, double cap,
                  Stencil stencil, Grid3<double>& value, Queue& heap, std::vector<std::uint8_t>* touched,
                  std::vector<std::size_t>* touchedList = nullptr, double limit = kInf) {
    std::size_t changes = 0;
    const auto get = [&](std::size_t n) { return value[n]; };
    const bool diagonal = stencil == Stencil::kAvalanche26;
    // Linear offsets of the 26 neighbours: a voxel off the block's faces needs no bounds checks.
    std::array<std::ptrdiff_t, 26> offset{};
    for (std::size_t n = 0; n < 26; ++n) {
        const NeighbourOffset& o = allNeighbours()[n];
        offset[n] = o.di + std::ptrdiff_t(d.nx) * (o.dj + std::ptrdiff_t(d.ny) * o.dk);
    }
    const auto lower = [&](std::size_t r, double u) {
        if (u < value[r]) {
            value[r] = u;
            heap.push({u, r});
            if (touched && !(*touched)[r]) {
                (*touched)[r] = 1;
                if (touchedList) touchedList->push_back(r);
                ++changes;
            }
        }
    };
    while (!heap.empty() && heap.bound() <= limit) {
        const double v = heap.top().first;  // named, not bound: the lambda below captures it (C++17)
        const std::size_t q = heap.top().second;
        heap.pop();
        if (v != value[q]) continue;  // stale entry
        const Index3 p = d.coord(q);
        if (diagonal && p.i > 0 && p.j > 0 && p.k > 0 && p.i + 1 < d.nx && p.j + 1 < d.ny && p.k + 1 < d.nz) {
            // Interior fast path: the same neighbours in the same order, without coordinates.
            for (std::size_t n = 0; n < 26; ++n) {
                const std::size_t r = std::size_t(std::ptrdiff_t(q) + offset[n]);
                if (seed[r] || value[r] <= v) continue;  // only larger values can be lowered by q
                lower(r, std::min(cap, v + double(slowness[r]) * allNeighbours()[n].length));
            }
            continue;
        }
        const auto visit = [&](const NeighbourOffset& o) {
            const int i = p.i + o.di, j = p.j + o.dj, k = p.k + o.dk;
            if (!d.contains(i, j, k)) return;
            const std::size_t r = d.index(i, j, k);
            if (seed[r] || value[r] <= v) return;  // only larger values can be lowered by q
            double u;
            if (diagonal) {
                u = std::min(cap, v + double(slowness[r]) * o.length);
            } else {
                double ax, ay, az;
                axisMinima(d, {i, j, k}, get, ax, ay, az);
                u = std::min(cap, upwindUpdate(ax, ay, az, slowness[r]));
            }
            lower(r, u);
        };
        if (diagonal) {
            for (const auto& o : allNeighbours()) visit(o);
        } else {
            for (const auto& o : faceNeighbours()) visit(o);
        }
    }
    return changes;
}

/// Linear offsets of the 26 neighbours in `allNeighbours()` order.
std::array<std::ptrdiff_t, 26> neighbourOffsets(const Dims& d) {
    std::array<std::ptrdiff_t, 26> offset{};
    for (std::size_t n = 0; n < 26; ++n) {
        const NeighbourOffset& o = allNeighbours()[n];
        offset[n] = o.di + std::ptrdiff_t(d.nx) * (o.dj + std::ptrdiff_t(d.ny) * o.dk);
    }
    return offset;
}

/// Calls fn(r, n) for each neighbour r of voxel q inside the grid, n its `allNeighbours()` slot.
template <typename Fn>
inline void forEachNeighbour(const Dims& d, const std::array<std::ptrdiff_t, 26>& offset, std::size_t q, Fn&& fn) {
    const Index3 p = d.coord(q);
    if (p.i > 0 && p.j > 0 && p.k > 0 && p.i + 1 < d.nx && p.j + 1 < d.ny && p.k + 1 < d.nz) {
        for (std::size_t n = 0; n < 26; ++n) fn(std::size_t(std::ptrdiff_t(q) + offset[n]), n);
        return;
    }
    for (std::size_t n = 0; n < 26; ++n) {
        const NeighbourOffset& o = allNeighbours()[n];
        if (d.contains(p.i + o.di, p.j + o.dj, p.k + o.dk)) fn(std::size_t(std::ptrdiff_t(q) + offset[n]), n);
    }
}

/// Held voxels below this count take their heavy steps on the calling thread.
constexpr std::size_t kParallelHeld = 4096;

/// The avalanche sweep (kAvalanche26) on the bucket queue with its **heavy steps batched**, the
/// same values and the same count of changed voxels as `relax`, bit for bit, on any number of
/// threads. A step into voxel r costs slowness(r) · |step|; a step is *heavy* when that is at
/// least `heavy` and *light* otherwise. A popped voxel takes its light steps at once (in bucket
/// order, as `relax` does) and holds its heavy steps back: they lower values to at least
/// (its value + heavy), so they can wait until the sweep reaches that value. Then all held voxels
/// take their heavy steps together, in parallel: each lowering is an atomic minimum, and a
/// voxel's final value is the minimum over the same candidate values whatever the order. With
/// `heavy` the rock's rate, a batch holds every voxel of the front within one rock step — the whole
/// shell the front crosses — while the few light steps along channels stay in bucket order.
/// `lightNear[q]` is 1 where q may have a light step (0 only if it certainly has none).
std::size_t relaxBatched(const Dims& d, const Grid3<float>& slowness, const std::vector<std::uint8_t>& seed, double cap,
                         double heavy, const std::vector<std::uint8_t>& lightNear, Grid3<double>& value,
                         BucketQueue& queue, std::vector<std::uint8_t>* touched, std::vector<std::size_t>* touchedList,
                         double limit) {
    std::size_t changes = 0;
    const std::array<std::ptrdiff_t, 26> offset = neighbourOffsets(d);
    const auto lower = [&](std::size_t r, double u) {
        if (u < value[r]) {
            value[r] = u;
            queue.push({u, r});
            if (touched && !(*touched)[r]) {
                (*touched)[r] = 1;
                if (touchedList) touchedList->push_back(r);
                ++changes;
            }
        }
    };
    std::vector<HeapEntry> held;  // popped (value, voxel) whose heavy steps wait
    double heldMin = kInf;
    const std::size_t last = queue.q.bucket.size() - 1;

    // One held voxel's heavy steps on one thread.
    const auto heavySerial = [&](const HeapEntry& e) {
        const double v = e.first;
        forEachNeighbour(d, offset, e.second, [&](std::size_t r, std::size_t n) {
            if (seed[r] || value[r] <= v) return;
            const double c = double(slowness[r]) * allNeighbours()[n].length;
            if (c >= heavy) lower(r, std::min(cap, v + c));
        });
    };
    struct Local {
        std::vector<HeapEntry> lowered;
        std::vector<std::size_t> firstTouched;
    };
    tbb::enumerable_thread_specific<Local> locals;
    const std::size_t workers =
        std::min<std::size_t>(std::size_t(tbb::this_task_arena::max_concurrency()),
                              tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
    const auto flush = [&] {
        if (held.size() < kParallelHeld || workers < 2) {
            for (const HeapEntry& e : held)
                if (e.first == value[e.second]) heavySerial(e);
        } else {
            double* val = value.data.data();
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, held.size(), 512),
                              [&](const tbb::blocked_range<std::size_t>& range) {
                                  Local& local = locals.local();
                                  for (std::size_t h = range.begin(); h != range.end(); ++h) {
                                      const double v = held[h].first;
                                      // A held voxel lowered again since it was popped is held again.
                                      double now;
                                      __atomic_load(val + held[h].second, &now, __ATOMIC_RELAXED);
                                      if (v != now) continue;
                                      forEachNeighbour(d, offset, held[h].second, [&](std::size_t r, std::size_t n) {
                                          if (seed[r]) return;
                                          double cur;
                                          __atomic_load(val + r, &cur, __ATOMIC_RELAXED);
                                          if (cur <= v) return;
                                          const double c = double(slowness[r]) * allNeighbours()[n].length;
                                          if (c < heavy) return;
                                          double u = std::min(cap, v + c);
                                          while (u < cur) {
                                              if (__atomic_compare_exchange(val + r, &cur, &u, false, __ATOMIC_RELAXED,
                                                                            __ATOMIC_RELAXED)) {
                                                  local.lowered.push_back({u, r});
                                                  if (touched && !__atomic_exchange_n(&(*touched)[r], std::uint8_t(1),
                                                                                      __ATOMIC_RELAXED))
                                                      local.firstTouched.push_back(r);
                                                  break;
                                              }
                                          }
                                      });
                                  }
                              });
            // Into the queue: only the entries still current (the others are stale already).
            for (Local& local : locals) {
                for (const HeapEntry& e : local.lowered)
                    if (e.first == value[e.second]) queue.push(e);
                changes += local.firstTouched.size();
                if (touchedList)
                    touchedList->insert(touchedList->end(), local.firstTouched.begin(), local.firstTouched.end());
                local.lowered.clear();
                local.firstTouched.clear();
            }
        }
        held.clear();
        heldMin = kInf;
    };

    for (;;) {
        if (queue.empty() || queue.bound() > limit) {
            if (held.empty()) break;
            flush();  // may refill buckets at or below the limit
            continue;
        }
        // A held step lowers to at least fl(heldMin + heavy) (rounding is monotone), which lies in
        // a bucket above the one about to be popped unless `index` says otherwise: then the held
        // steps go first. The last bucket holds all values beyond it, in any order.
        if (!held.empty() && (queue.index(heldMin + heavy) <= queue.q.lowest || queue.q.lowest == last)) {
            flush();
            continue;
        }
        const HeapEntry e = queue.top();
        queue.pop();
        const double v = e.first;
        const std::size_t q = e.second;
        if (v != value[q]) continue;  // stale entry
        if (lightNear[q])
            forEachNeighbour(d, offset, q, [&](std::size_t r, std::size_t n) {
                if (seed[r] || value[r] <= v) return;
                const double c = double(slowness[r]) * allNeighbours()[n].length;
                if (c < heavy) lower(r, std::min(cap, v + c));
            });
        held.push_back(e);
        heldMin = std::min(heldMin, v);
    }
    return changes;
}

/// Sets lightNear[q] for every neighbour q of voxel c that has a light step into c.
void markLightNear(const Dims& d, const Grid3<float>& slowness, double heavy, std::size_t c,
                   std::vector<std::uint8_t>& lightNear) {
    const std::array<std::ptrdiff_t, 26> offset = neighbourOffsets(d);
    forEachNeighbour(d, offset, c, [&](std::size_t q, std::size_t n) {
        if (double(slowness[c]) * allNeighbours()[n].length < heavy) lightNear[q] = 1;
    });
}

}  // namespace

double upwindUpdate(double ax, double ay, double az, double f) {
    double a[3] = {ax, ay, az};
    std::sort(a, a + 3);
    if (!(a[0] < kInf) || !(f < kInf)) return kInf;
    // One-sided update first; add an axis while the solution stays above that axis's value.
    double u = a[0] + f;
    double sum = a[0], sumSq = a[0] * a[0];
    for (int m = 2; m <= 3; ++m) {
        if (!(u > a[m - 1])) break;
        sum += a[m - 1];
        sumSq += a[m - 1] * a[m - 1];
        // m·u² − 2·sum·u + sumSq − f² = 0, larger root.
        const double disc = sum * sum - m * (sumSq - f * f);
        if (disc < 0) break;  // cannot happen when a[m-1] < u; kept for round-off safety
        u = (sum + std::sqrt(disc)) / m;
    }
    return u;
}

void EikonalField::solve(const Dims& dims, const Grid3<float>& slowness, const std::vector<Seed>& seeds, double cap,
                         Stencil stencil) {
    CAVESIM_CHECK(slowness.dims == dims, "EikonalField::solve: slowness grid has other dims");
    dims_ = dims;
    cap_ = cap;
    stencil_ = stencil;
    value_ = Grid3<double>(dims, cap);
    seed_.assign(dims.count(), 0);
    pending_.clear();
    for (const Seed& s : seeds) {
        CAVESIM_CHECK(s.voxel < dims.count(), "EikonalField::solve: seed voxel " + std::to_string(s.voxel) +
                                                  " outside a grid of " + std::to_string(dims.count()));
        const double v = std::min(cap, s.value);
        if (!seed_[s.voxel] || v < value_[s.voxel]) value_[s.voxel] = v;
        seed_[s.voxel] = 1;
    }
    // The seeds into the queue, then the whole sweep.
    const auto run = [&](auto& queue) {
        for (std::size_t n = 0; n < seed_.size(); ++n)
            if (seed_[n]) queue.push({value_[n], n});
        if constexpr (std::is_same_v<std::decay_t<decltype(queue)>, BucketQueue>)
            relaxBatched(dims_, slowness, seed_, cap_, heavy_, lightNear_, value_, queue, nullptr, nullptr, kInf);
        else
            relax(dims_, slowness, seed_, cap_, stencil_, value_, queue, nullptr);
    };
    useBuckets_ = false;
    buckets_ = Buckets{};
    if (stencil == Stencil::kAvalanche26) {
        // A bucket queue when buckets as wide as the smallest edge cost (the smallest slowness
        // times 1) cover [0, cap] with at most 2^21 of them; a heap otherwise.
        float smallest = std::numeric_limits<float>::infinity();
        for (float x : slowness.data) smallest = std::min(smallest, x);
        const double count = cap / double(smallest);
        if (smallest > 0 && std::isfinite(count) && count < double(1 << 21)) {
            useBuckets_ = true;
            buckets_.width = double(smallest);
            buckets_.bucket.resize(std::size_t(count) + 2);
            buckets_.lowest = buckets_.bucket.size() - 1;
            // Heavy steps: those into voxels of the largest slowness (the rock), or costlier.
            heavy_ = 0;
            for (float x : slowness.data) heavy_ = std::max(heavy_, double(x));
            lightNear_.assign(dims.count(), 0);
            for (std::size_t c = 0; c < dims.count(); ++c)
                if (double(slowness[c]) * std::sqrt(3.0) < heavy_) markLightNear(dims, slowness, heavy_, c, lightNear_);
            BucketQueue queue{buckets_};
            run(queue);
            return;
        }
    }
    MinHeap heap;
    run(heap);
}

std::size_t EikonalField::decrease(const Grid3<float>& slowness, const std::vector<std::size_t>& changed,
                                   double limit) {
    // `touched_` stays allocated between calls and only the entries set here are cleared again, so
    // the cost follows the voxels that change, not the grid.
    std::vector<std::uint8_t>& touched = touched_;
    if (touched.size() != dims_.count()) touched.assign(dims_.count(), 0);
    std::vector<std::size_t> touchedList;
    std::size_t changes = 0;
    const auto get = [&](std::size_t n) { return value_[n]; };
    const auto run = [&](auto& queue) {
        for (std::size_t q : changed) {
            if (q >= value_.size() || seed_[q]) continue;
            const double u = fullUpdate(dims_, dims_.coord(q), get, slowness[q], stencil_, cap_);
            if (u < value_[q]) {
                value_[q] = u;
                queue.push({u, q});
                if (!touched[q]) {
                    touched[q] = 1;
                    touchedList.push_back(q);
                    ++changes;
                }
            }
        }
        if constexpr (std::is_same_v<std::decay_t<decltype(queue)>, BucketQueue>) {
            for (std::size_t c : changed)
                if (c < value_.size()) markLightNear(dims_, slowness, heavy_, c, lightNear_);
            changes += relaxBatched(dims_, slowness, seed_, cap_, heavy_, lightNear_, value_, queue, &touched,
                                    &touchedList, limit);
        } else {
            changes += relax(dims_, slowness, seed_, cap_, stencil_, value_, queue, &touched, &touchedList, limit);
        }
        for (std::size_t q : touchedList) touched[q] = 0;
    };
    // Entries above the limit wait for a later call. Stale ones (their voxel fell since) and
    // duplicates are dropped when they pile up, so the pending entries stay near the size of the
    // front they stand for.
    const auto current = [&](std::vector<HeapEntry>& entries) {
        std::vector<HeapEntry> keep;
        for (const HeapEntry& e : entries)
            if (e.first == value_[e.second] && !touched[e.second]) {
                touched[e.second] = 1;
                keep.push_back(e);
            }
        for (const HeapEntry& e : keep) touched[e.second] = 0;
        entries.swap(keep);
    };
    if (useBuckets_) {
        BucketQueue queue{buckets_};
        run(queue);
        if (buckets_.count > std::max<std::size_t>(std::size_t(1) << 16, 2 * buckets_.compacted)) {
            buckets_.count = 0;
            for (std::size_t b = buckets_.lowest; b < buckets_.bucket.size(); ++b) {
                current(buckets_.bucket[b]);
                buckets_.count += buckets_.bucket[b].size();
            }
            buckets_.compacted = buckets_.count;
        }
        return changes;
    }
    MinHeap heap;
    heap.c.swap(pending_);
    run(heap);
    if (heap.c.size() > std::max<std::size_t>(std::size_t(1) << 16, 2 * pendingCompacted_)) {
        current(heap.c);
        std::make_heap(heap.c.begin(), heap.c.end(), std::greater<HeapEntry>());
        pendingCompacted_ = heap.c.size();
    }
    pending_.swap(heap.c);
    return changes;
}

std::size_t EikonalField::settle(const Grid3<float>& slowness) {
    return decrease(slowness, {}, kInf);
}

namespace {

void putEntries(ByteWriter& out, const std::vector<HeapEntry>& entries) {
    out.put(std::uint64_t(entries.size()));
    for (const HeapEntry& e : entries) {
        out.put(e.first);
        out.put(std::uint64_t(e.second));
    }
}

void getEntries(ByteReader& in, std::vector<HeapEntry>& entries, const char* what, std::size_t voxels) {
    const std::uint64_t n = in.get<std::uint64_t>(what);
    if (n > in.left() / 16) in.fail(std::string("ends inside ") + what);
    entries.resize(std::size_t(n));
    for (HeapEntry& e : entries) {
        e.first = in.get<double>(what);
        const std::uint64_t v = in.get<std::uint64_t>(what);
        if (v >= voxels) in.fail("a queued voxel outside the grid");
        if (!(e.first >= 0) || !std::isfinite(e.first)) in.fail("a queued value that is not a finite number >= 0");
        e.second = std::size_t(v);
    }
}

}  // namespace

void EikonalField::save(ByteWriter& out) const {
    out.put(std::uint32_t(dims_.nx));
    out.put(std::uint32_t(dims_.ny));
    out.put(std::uint32_t(dims_.nz));
    out.put(cap_);
    out.put(std::uint8_t(stencil_));
    out.putVector(value_.data);
    out.putVector(seed_);
    putEntries(out, pending_);
    out.put(std::uint64_t(pendingCompacted_));
    out.put(std::uint8_t(useBuckets_ ? 1 : 0));
    out.put(buckets_.width);
    out.put(std::uint64_t(buckets_.lowest));
    out.put(std::uint64_t(buckets_.count));
    out.put(std::uint64_t(buckets_.compacted));
    out.put(std::uint64_t(buckets_.bucket.size()));
    std::uint64_t filled = 0;
    for (const auto& b : buckets_.bucket) filled += b.empty() ? 0 : 1;
    out.put(filled);
    for (std::size_t b = 0; b < buckets_.bucket.size(); ++b)
        if (!buckets_.bucket[b].empty()) {
            out.put(std::uint64_t(b));
            putEntries(out, buckets_.bucket[b]);
        }
}

void EikonalField::restore(ByteReader& in, const Dims& dims) {
    const std::uint32_t nx = in.get<std::uint32_t>("the pressure grid size"),
                        ny = in.get<std::uint32_t>("the pressure grid size"),
                        nz = in.get<std::uint32_t>("the pressure grid size");
    if (!(Dims{int(nx), int(ny), int(nz)} == dims)) in.fail("a pressure field on another grid");
    EikonalField f;
    f.dims_ = dims;
    f.cap_ = in.get<double>("the pressure cap");
    const std::uint8_t stencil = in.get<std::uint8_t>("the stencil");
    if (stencil > std::uint8_t(Stencil::kAvalanche26)) in.fail("an unknown stencil");
    f.stencil_ = Stencil(stencil);
    f.value_.dims = dims;
    in.getVector(f.value_.data, "the pressure values", dims.count());
    if (!(f.cap_ >= 0) || !std::isfinite(f.cap_)) in.fail("a pressure cap that is not a finite number >= 0");
    for (double v : f.value_.data)
        if (!(v >= 0) || !(v <= f.cap_)) in.fail("a pressure value outside [0, cap]");
    in.getVector(f.seed_, "the pressure seeds", dims.count());
    getEntries(in, f.pending_, "the pending sweep", dims.count());
    if (!std::is_heap(f.pending_.begin(), f.pending_.end(), std::greater<HeapEntry>()))
        in.fail("a pending sweep that is not a heap");
    f.pendingCompacted_ = std::size_t(in.get<std::uint64_t>("the pending sweep"));
    const std::uint8_t buckets = in.get<std::uint8_t>("the queue kind");
    if (buckets > 1) in.fail("an unknown queue kind");
    f.useBuckets_ = buckets == 1;
    f.buckets_.width = in.get<double>("the bucket width");
    f.buckets_.lowest = std::size_t(in.get<std::uint64_t>("the bucket queue"));
    f.buckets_.count = std::size_t(in.get<std::uint64_t>("the bucket queue"));
    f.buckets_.compacted = std::size_t(in.get<std::uint64_t>("the bucket queue"));
    const std::uint64_t nBuckets = in.get<std::uint64_t>("the bucket queue");
    const std::uint64_t filled = in.get<std::uint64_t>("the bucket queue");
    if (nBuckets > (std::uint64_t(1) << 22) || filled > nBuckets || (f.useBuckets_ && nBuckets == 0) ||
        !(f.buckets_.width > 0) || f.buckets_.lowest > nBuckets || (nBuckets > 0 && f.buckets_.lowest >= nBuckets))
        in.fail("an inconsistent bucket queue");
    f.buckets_.bucket.resize(std::size_t(nBuckets));
    std::size_t count = 0;
    std::uint64_t previous = 0;
    for (std::uint64_t k = 0; k < filled; ++k) {
        const std::uint64_t b = in.get<std::uint64_t>("a bucket index");
        if (b >= nBuckets || (k > 0 && b <= previous) || b < f.buckets_.lowest) in.fail("a misplaced bucket");
        previous = b;
        getEntries(in, f.buckets_.bucket[std::size_t(b)], "a bucket", dims.count());
        if (f.buckets_.bucket[std::size_t(b)].empty()) in.fail("an empty bucket listed");
        count += f.buckets_.bucket[std::size_t(b)].size();
    }
    if (count != f.buckets_.count) in.fail("a bucket queue whose count does not match its entries");
    *this = std::move(f);
}

LabelledArrival marchLabelled(const Dims& dims, const Grid3<float>* slowness, const std::vector<Seed>& seeds,
                              const std::vector<double>& labelSpeed) {
    CAVESIM_CHECK(!slowness || slowness->dims == dims, "marchLabelled: slowness grid has other dims");
    for (double s : labelSpeed)
        CAVESIM_CHECK(s > 0 && std::isfinite(s), "marchLabelled: label speeds must be > 0, got " + std::to_string(s));
    for (const Seed& s : seeds) {
        CAVESIM_CHECK(s.voxel < dims.count(), "marchLabelled: seed voxel " + std::to_string(s.voxel) +
                                                  " outside a grid of " + std::to_string(dims.count()));
        CAVESIM_CHECK(s.label >= 0 && std::size_t(s.label) < labelSpeed.size(),
                      "marchLabelled: seed label " + std::to_string(s.label) + " has no speed");
    }
    LabelledArrival out{Grid3<double>(dims, kInf), Grid3<std::int32_t>(dims, -1)};
    // One front per label through the whole grid, then the earliest arrival wins (ties: lower
    // label). The fronts are independent, so a batch of them marches in parallel, one per worker;
    // merging in label order keeps the result the same for any thread count.
    const std::size_t nLabels = labelSpeed.size();
    const std::size_t batch = std::max<std::size_t>(1, std::size_t(tbb::this_task_arena::max_concurrency()));
    std::vector<Grid3<double>> times(std::min(batch, nLabels));
    std::vector<std::uint8_t> marched(nLabels, 0);
    for (std::size_t first = 0; first < nLabels; first += batch) {
        const std::size_t count = std::min(batch, nLabels - first);
        tbb::parallel_for(std::size_t(0), count, [&](std::size_t k) {
            const std::size_t label = first + k;
            Grid3<double>& time = times[k];
            time = Grid3<double>(dims, kInf);
            std::vector<std::uint8_t> isSeed(dims.count(), 0);
            MinHeap heap;
            for (const Seed& s : seeds) {
                if (std::size_t(s.label) != label) continue;
                time[s.voxel] = isSeed[s.voxel] ? std::min(time[s.voxel], s.value) : s.value;
                isSeed[s.voxel] = 1;
            }
            bool any = false;
            for (std::size_t n = 0; n < dims.count(); ++n)
                if (isSeed[n]) {
                    heap.push({time[n], n});
                    any = true;
                }
            if (!any) return;
            marched[label] = 1;
            const float inv = float(1.0 / labelSpeed[label]);
            Grid3<float> labelSlowness(dims);
            for (std::size_t n = 0; n < dims.count(); ++n) labelSlowness[n] = (slowness ? (*slowness)[n] : 1.0f) * inv;
            relax(dims, labelSlowness, isSeed, kInf, Stencil::kFace6, time, heap, nullptr);
        });
        for (std::size_t k = 0; k < count; ++k) {
            if (!marched[first + k]) continue;
            const Grid3<double>& time = times[k];
            for (std::size_t n = 0; n < dims.count(); ++n)
                if (time[n] < out.time[n]) {  // strict: on a tie the lower label, merged first, keeps the voxel
                    out.time[n] = time[n];
                    out.label[n] = std::int32_t(first + k);
                }
        }
    }
    return out;
}

}  // namespace cavesim::fastmarch

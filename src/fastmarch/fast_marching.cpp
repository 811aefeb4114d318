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

#if defined(__linux__)
#include <sys/mman.h>
#endif

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

/// The bucket of value v (the last one holds everything beyond).
std::size_t bucketIndex(const EikonalField::Buckets& q, double v) {
    const double b = v / q.width;
    return b >= double(q.bucket.size() - 1) ? q.bucket.size() - 1 : std::size_t(b);
}

/// Entries in buckets of values [b·width, (b+1)·width): a bucket queue (Dial). With a width at
/// most the smallest edge cost, nothing popped from a bucket can lower another entry of the same
/// bucket, so a bucket may be drained in any order and each voxel settles once, as with a heap,
/// at O(1) per push and pop. With a wider bucket a voxel may be lowered again within its bucket;
/// the sweep is label-correcting either way and ends at the same values (each value is the
/// minimum over paths of the same rounded path costs, whatever the order).
struct BucketQueue {
    EikonalField::Buckets& q;
    bool empty() const { return q.count == 0; }
    std::size_t index(double v) const { return bucketIndex(q, v); }
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
};

/// Smallest value of the two neighbours along one axis; −x and +x (or −y/+y, −z/+z) are combined
/// by std::min, which is symmetric, so mirrored inputs give mirrored results.
template <typename Get>
void axisMinima(const Dims& d, const Index3& p, const Get& get, double& ax, double& ay, double& az) {
    const std::size_t r = d.index(p), sy = std::size_t(d.nx), sz = std::size_t(d.nx) * std::size_t(d.ny);
    ax = std::min(p.i > 0 ? get(r - 1) : kInf, p.i + 1 < d.nx ? get(r + 1) : kInf);
    ay = std::min(p.j > 0 ? get(r - sy) : kInf, p.j + 1 < d.ny ? get(r + sy) : kInf);
    az = std::min(p.k > 0 ? get(r - sz) : kInf, p.k + 1 < d.nz ? get(r + sz) : kInf);
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

/// Linear offsets of the 26 neighbours in `allNeighbours()` order.
std::array<std::ptrdiff_t, 26> neighbourOffsets(const Dims& d) {
    std::array<std::ptrdiff_t, 26> offset{};
    for (std::size_t n = 0; n < 26; ++n) {
        const NeighbourOffset& o = allNeighbours()[n];
        offset[n] = o.di + std::ptrdiff_t(d.nx) * (o.dj + std::ptrdiff_t(d.ny) * o.dk);
    }
    return offset;
}

/// Label-correcting sweep shared by `solve` and `decrease`: pops the smallest tentative value and
/// re-evaluates its neighbours: the Godunov update of each face neighbour from the current values
/// of all its face neighbours (kFace6), or one step from the popped voxel to each of its 26
/// neighbours (kAvalanche26: Dijkstra on the 26-neighbour graph). With heap order this is fast marching (each voxel
/// settles once when values only fall); it also repairs a field whose slowness fell locally without touching the rest.
/// A voxel it lowers is flagged in `touched` (when given) and, the first time, appended to `touchedList`.
/// (On the bucket queue the sweep is `relaxBatched`.)
void relax(const Dims& d, const Grid3<float>& slowness, const std::vector<std::uint8_t>& seed, double cap,
           Stencil stencil, Grid3<double>& value, MinHeap& heap, std::vector<std::uint8_t>* touched,
           std::vector<std::size_t>* touchedList = nullptr, double limit = kInf) {
    const auto get = [&](std::size_t n) { return value[n]; };
    const bool diagonal = stencil == Stencil::kAvalanche26;
    // Linear offsets of the 26 neighbours: a voxel off the block's faces needs no bounds checks.
    const std::array<std::ptrdiff_t, 26> offset = neighbourOffsets(d);
    const auto lower = [&](std::size_t r, double u) {
        if (u < value[r]) {
            value[r] = u;
            heap.push({u, r});
            if (touched && !(*touched)[r]) {
                (*touched)[r] = 1;
                if (touchedList) touchedList->push_back(r);
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
}

/// Calls fn(r, n) for each neighbour r of voxel q inside the grid, n its `allNeighbours()` slot;
/// `onFace` says q lies on a face of the block (else no bounds checks are needed).
template <typename Fn>
inline void forEachNeighbour(const Dims& d, const std::array<std::ptrdiff_t, 26>& offset, std::size_t q, bool onFace,
                             Fn&& fn) {
    if (!onFace) {
        for (std::size_t n = 0; n < 26; ++n) fn(std::size_t(std::ptrdiff_t(q) + offset[n]), n);
        return;
    }
    const Index3 p = d.coord(q);
    for (std::size_t n = 0; n < 26; ++n) {
        const NeighbourOffset& o = allNeighbours()[n];
        if (d.contains(p.i + o.di, p.j + o.dj, p.k + o.dk)) fn(std::size_t(std::ptrdiff_t(q) + offset[n]), n);
    }
}

/// Asks the kernel to back a large array with 2 MB pages (now, where it can: MADV_COLLAPSE):
/// the sweep reads a voxel's 3×3 rows of neighbours, each in another 4 KB page, so with small
/// pages most reads of a large block also miss the TLB. A hint only: nothing else changes, and
/// where the kernel declines, nothing at all.
void adviseHugePages(const void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    constexpr std::uintptr_t kHuge = std::uintptr_t(1) << 21;
    const std::uintptr_t begin = (reinterpret_cast<std::uintptr_t>(data) + kHuge - 1) & ~(kHuge - 1);
    const std::uintptr_t end = (reinterpret_cast<std::uintptr_t>(data) + bytes) & ~(kHuge - 1);
    if (end <= begin) return;
    void* p = reinterpret_cast<void*>(begin);
    if (madvise(p, end - begin, MADV_HUGEPAGE) != 0) return;
    constexpr int kCollapse = 25;  // MADV_COLLAPSE (Linux 6.1), not in older headers
    (void)madvise(p, end - begin, kCollapse);
#else
    (void)data;
    (void)bytes;
#endif
}

/// Per-voxel flags of the bucket-queue sweep (`EikonalField::flags_`).
constexpr std::uint8_t kLightNear = 1;  ///< the voxel may have a light step (0: certainly none)
constexpr std::uint8_t kSeed = 2;       ///< a seed: holds its value
constexpr std::uint8_t kOnFace = 4;     ///< on a face of the block: some neighbours lie outside

/// Sets kLightNear on every neighbour q of voxel c that has a light step into c (`offset`: from
/// `neighbourOffsets`; kOnFace of c already set).
void markLightNear(const Dims& d, const std::array<std::ptrdiff_t, 26>& offset, const Grid3<float>& slowness,
                   double heavy, std::size_t c, std::vector<std::uint8_t>& flags) {
    forEachNeighbour(d, offset, c, (flags[c] & kOnFace) != 0, [&](std::size_t q, std::size_t n) {
        if (double(slowness[c]) * allNeighbours()[n].length < heavy) flags[q] |= kLightNear;
    });
}

/// The flags of every voxel; `heavy` = the largest slowness.
void buildFlags(const Dims& d, const Grid3<float>& slowness, const std::vector<std::uint8_t>& seed, double heavy,
                std::vector<std::uint8_t>& flags) {
    flags.assign(d.count(), 0);
    const std::array<std::ptrdiff_t, 26> offset = neighbourOffsets(d);
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                const std::size_t c = d.index(i, j, k);
                if (i == 0 || j == 0 || k == 0 || i + 1 == d.nx || j + 1 == d.ny || k + 1 == d.nz) flags[c] |= kOnFace;
                if (seed[c]) flags[c] |= kSeed;
                if (double(slowness[c]) * std::sqrt(3.0) < heavy) markLightNear(d, offset, slowness, heavy, c, flags);
            }
}

/// Buckets per window: a heavy step from a value in a window's first bucket lands beyond the
/// window (one bucket is left for the rounding of the sum and of the bucket index).
std::size_t windowSpan(double heavy, double width) {
    const double s = std::floor(heavy / width) - 1.0;
    return s >= 1.0 ? std::size_t(std::min(s, double(1 << 22))) : 1;
}

/// Sorts entries by voxel index (LSD radix sort, 11 bits a pass): the heavy steps of a batch then
/// walk the grid in memory order.
void sortByVoxel(std::vector<HeapEntry>& a, std::vector<HeapEntry>& tmp, std::size_t voxels) {
    if (a.size() < 512) {
        std::sort(a.begin(), a.end(), [](const HeapEntry& x, const HeapEntry& y) { return x.second < y.second; });
        return;
    }
    int bits = 1;
    while (bits < 64 && (std::size_t(1) << bits) < voxels) ++bits;
    tmp.resize(a.size());
    constexpr int kBits = 11;
    for (int shift = 0; shift < bits; shift += kBits) {
        std::array<std::size_t, (1 << kBits) + 1> count{};
        for (const HeapEntry& e : a) ++count[((e.second >> shift) & ((1 << kBits) - 1)) + 1];
        for (std::size_t b = 1; b < count.size(); ++b) count[b] += count[b - 1];
        for (const HeapEntry& e : a) tmp[count[(e.second >> shift) & ((1 << kBits) - 1)]++] = e;
        a.swap(tmp);
    }
}

/// Windows are used from this many buckets each (`relaxBatched`).
constexpr std::size_t kMinSpan = 8;

/// Held batches below this count take their heavy steps on the calling thread.
constexpr std::size_t kParallelHeld = 4096;

/// The avalanche sweep (kAvalanche26) on the bucket queue with its **heavy steps batched**: the
/// same values and the same changed voxels (`touchedList`) as `relax`, bit for bit, on any number of
/// threads. A step into voxel r costs slowness(r) · |step|; a step is *heavy* when that is at
/// least `heavy` (the rock's rate) and *light* otherwise. A heavy step from value v lowers to at
/// least v + heavy, beyond the *window* of `span` buckets that holds v; so the sweep goes a window
/// at a time: first the voxels that may have light steps, popped in bucket order (the `Buckets`),
/// taking their light steps at once, as `relax` does; then the heavy steps of all the window's
/// voxels together — those popped and every entry of voxels without light steps, which wait in
/// the window's lists (`Windows`) without being ordered — sorted by voxel index and in parallel:
/// each lowering is an atomic minimum, and a voxel's final value is the minimum over the same
/// candidate values whatever the order. A sweep limited to buckets up to the limit takes exactly
/// the entries `relax` would pop. Where a value still lands in a window already swept (only when a
/// step's rounding or a light step of a voxel whose flags changed puts it there) the sweep goes
/// back to that window: it stays label-correcting, so the values are the same.
void relaxBatched(const Dims& d, const Grid3<float>& slowness, double cap, double heavy,
                  const std::vector<std::uint8_t>& flags, Grid3<double>& value, EikonalField::Buckets& fine,
                  EikonalField::Windows& win, std::vector<std::uint8_t>* touched, std::vector<std::size_t>* touchedList,
                  double limit) {
    BucketQueue queue{fine};
    const std::size_t nb = fine.bucket.size();
    const std::size_t span = win.span;
    const std::size_t nw = (nb + span - 1) / span;
    const std::size_t slots = std::max<std::size_t>(1, std::size_t(tbb::this_task_arena::max_concurrency()));
    // Windows of a few buckets only would cost more memory (a list per window and worker) than
    // they save: then every entry goes through the buckets.
    const bool windows = span >= kMinSpan;
    if (windows) {
        if (win.slot.size() < slots) win.slot.resize(slots);
        for (auto& s : win.slot)
            if (s.size() != nw) s.resize(nw);
    }
    const std::size_t workers =
        std::min<std::size_t>(slots, tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
    const std::array<std::ptrdiff_t, 26> offset = neighbourOffsets(d);
    std::array<double, 26> length{};
    for (std::size_t n = 0; n < 26; ++n) length[n] = allNeighbours()[n].length;
    const float* slow = slowness.data.data();
    const std::uint8_t* flag = flags.data();
    double* val = value.data.data();

    // Pushes from the calling thread: voxels with light steps into the buckets, others into their window.
    const auto push = [&](double u, std::size_t r) {
        if (!windows || (flag[r] & kLightNear)) {
            queue.push({u, r});
            return;
        }
        const std::size_t w = queue.index(u) / span;
        win.slot[0][w].push_back({u, r});
        win.lowest = std::min(win.lowest, w);
        ++win.count;
    };
    const auto touch = [&](std::size_t r) {
        if (touched && !(*touched)[r]) {
            (*touched)[r] = 1;
            if (touchedList) touchedList->push_back(r);
        }
    };
    struct alignas(128) Slot {         // one cache line pair per worker: no false sharing
        std::vector<HeapEntry> light;  // lowered voxels with light steps (into the buckets afterwards)
        std::vector<std::size_t> firstTouched;
        std::size_t pushed = 0;  // entries put into this slot's windows
        std::size_t lowest = std::numeric_limits<std::size_t>::max();
        std::vector<HeapEntry> part, scratch;  // this worker's chunk of the batch, sorted
    };
    std::vector<Slot> local(slots);
    // The batch walks the grid in memory order, but a shell's voxels are not adjacent in memory:
    // the 3×3 rows of a voxel a few items ahead are fetched while this one is done.
    constexpr std::size_t kAhead = 4;
    const std::ptrdiff_t row = d.nx, plane = std::ptrdiff_t(d.nx) * d.ny;
    const std::ptrdiff_t total = std::ptrdiff_t(d.count());
    const auto prefetch = [&](std::size_t q) {
        for (std::ptrdiff_t dk = -plane; dk <= plane; dk += plane)
            for (std::ptrdiff_t dj = -row; dj <= row; dj += row) {
                const std::ptrdiff_t r = std::ptrdiff_t(q) + dk + dj;
                if (r < 0 || r >= total) continue;
                __builtin_prefetch(val + r, 1);
                __builtin_prefetch(slow + r);
                __builtin_prefetch(flag + r);
            }
    };
    std::vector<HeapEntry> batch, scratch;

    for (;;) {
        // The lowest window holding an entry.
        std::size_t bl = nb;
        if (!queue.empty()) {
            queue.top();
            bl = fine.lowest;
        }
        std::size_t wl = nw;
        if (win.count > 0) {
            const auto filled = [&](std::size_t w) {
                for (const auto& s : win.slot)
                    if (!s[w].empty()) return true;
                return false;
            };
            while (win.lowest < nw && !filled(win.lowest)) ++win.lowest;
            wl = win.lowest;
        }
        const std::size_t w = std::min(bl < nb ? bl / span : nw, wl);
        if (w >= nw) break;
        const std::size_t first = w * span;
        std::size_t end = std::min(first + span, nb);
        while (end > first && !(double(end - 1) * fine.width <= limit)) --end;  // buckets `relax` would pop
        if (end == first) break;
        if (end <= bl && end < std::min(first + span, nb)) {
            // Limited: does the window hold an entry at or below the limit?
            bool any = false;
            for (const auto& s : win.slot)
                for (const HeapEntry& e : s[w]) any = any || queue.index(e.first) < end;
            if (!any) break;
        }

        // 1. The voxels that may have light steps, in bucket order; they are held for step 2.
        batch.clear();
        for (std::size_t b = std::max(first, bl); b < end; ++b) {
            std::vector<HeapEntry>& bucket = fine.bucket[b];
            while (!bucket.empty()) {
                const HeapEntry e = bucket.back();
                bucket.pop_back();
                --fine.count;
                const double v = e.first;
                const std::size_t q = e.second;
                if (v != val[q]) continue;  // stale entry
                if (flag[q] & kLightNear)
                    forEachNeighbour(d, offset, q, (flag[q] & kOnFace) != 0, [&](std::size_t r, std::size_t n) {
                        if ((flag[r] & kSeed) || val[r] <= v) return;
                        const double c = double(slow[r]) * length[n];
                        if (c >= heavy) return;
                        const double u = std::min(cap, v + c);
                        if (u < val[r]) {
                            val[r] = u;
                            push(u, r);
                            touch(r);
                        }
                    });
                batch.push_back(e);
            }
            // A drained bucket gives its memory back: the buckets together hold only the front.
            if (bucket.capacity() > 64) std::vector<HeapEntry>().swap(bucket);
        }
        if (fine.lowest < end) fine.lowest = std::min(end, nb - 1);

        // 2. Every step of the window's voxels: those held and those waiting in the window's lists
        // (a voxel without light steps has only heavy ones; a held one's light steps lower nothing now).
        const bool whole = end == std::min(first + span, nb);
        for (auto& s : win.slot) {
            if (!windows) break;
            std::vector<HeapEntry>& list = s[w];
            if (whole) {
                batch.insert(batch.end(), list.begin(), list.end());
                win.count -= list.size();
                if (list.capacity() > 64)
                    std::vector<HeapEntry>().swap(list);
                else
                    list.clear();
            } else {
                std::size_t kept = 0;
                for (const HeapEntry& e : list)
                    if (queue.index(e.first) < end)
                        batch.push_back(e);
                    else
                        list[kept++] = e;
                win.count -= list.size() - kept;
                list.resize(kept);
            }
        }
        if (batch.empty()) continue;
        // A step lowers r where v + cost < value[r]; v + cost ≥ cap never does (values are at most
        // cap), so min(cap, ·) of `relax` changes nothing, and neither does its test value[r] ≤ v.
        if (batch.size() < kParallelHeld || workers < 2) {
            sortByVoxel(batch, scratch, d.count());
            for (std::size_t h = 0; h < batch.size(); ++h) {
                if (h + kAhead < batch.size()) prefetch(batch[h + kAhead].second);
                const double v = batch[h].first;
                const std::size_t q = batch[h].second;
                if (v != val[q]) continue;  // stale, or lowered again since it was popped (then it waits again)
                forEachNeighbour(d, offset, q, (flag[q] & kOnFace) != 0, [&](std::size_t r, std::size_t n) {
                    const double u = v + double(slow[r]) * length[n];
                    if (u < val[r] && !(flag[r] & kSeed)) {
                        val[r] = u;
                        push(u, r);
                        touch(r);
                    }
                });
            }
            continue;
        }
        // In parallel: many chunks per worker (a worker the system stops holds little back), each a range of voxel
        // indices (so the workers mostly write different parts of the grid) with about equal counts: one counting pass
        // into bins of the index's top bits; each chunk is then sorted by voxel on its own.
        const std::size_t chunks = workers * 16;
        constexpr std::size_t kBins = 1024;
        std::size_t shift = 0;
        while ((d.count() - 1) >> shift >= kBins) ++shift;
        std::array<std::size_t, kBins + 1> binStart{};
        for (const HeapEntry& e : batch) ++binStart[(e.second >> shift) + 1];
        for (std::size_t b = 1; b <= kBins; ++b) binStart[b] += binStart[b - 1];
        std::vector<std::size_t> cut(chunks + 1, batch.size());
        cut[0] = 0;
        for (std::size_t c = 1, b = 0; c < chunks; ++c) {
            while (b < kBins && binStart[b] < batch.size() * c / chunks) ++b;
            cut[c] = binStart[b];
        }
        scratch.resize(batch.size());
        {
            std::array<std::size_t, kBins + 1> next = binStart;
            for (const HeapEntry& e : batch) scratch[next[e.second >> shift]++] = e;
        }
        tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t chunk) {
            const std::size_t me = std::size_t(tbb::this_task_arena::current_thread_index());
            Slot& sl = local[me];
            std::vector<std::vector<HeapEntry>>* lists = windows ? &win.slot[me] : nullptr;
            sl.part.assign(scratch.begin() + std::ptrdiff_t(cut[chunk]),
                           scratch.begin() + std::ptrdiff_t(cut[chunk + 1]));
            sortByVoxel(sl.part, sl.scratch, d.count());
            const std::vector<HeapEntry>& part = sl.part;
            for (std::size_t h = 0; h < part.size(); ++h) {
                if (h + kAhead < part.size()) prefetch(part[h + kAhead].second);
                const double v = part[h].first;
                const std::size_t q = part[h].second;
                double now;
                __atomic_load(val + q, &now, __ATOMIC_RELAXED);
                if (v != now) continue;
                forEachNeighbour(d, offset, q, (flag[q] & kOnFace) != 0, [&](std::size_t r, std::size_t n) {
                    double cur;
                    __atomic_load(val + r, &cur, __ATOMIC_RELAXED);
                    double u = v + double(slow[r]) * length[n];
                    if (!(u < cur) || (flag[r] & kSeed)) return;
                    while (u < cur) {
                        if (__atomic_compare_exchange(val + r, &cur, &u, false, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) {
                            if (!windows || (flag[r] & kLightNear)) {
                                sl.light.push_back({u, r});
                            } else {
                                const std::size_t to = queue.index(u) / span;
                                (*lists)[to].push_back({u, r});
                                ++sl.pushed;
                                sl.lowest = std::min(sl.lowest, to);
                            }
                            if (touched && !__atomic_load_n(&(*touched)[r], __ATOMIC_RELAXED) &&
                                !__atomic_exchange_n(&(*touched)[r], std::uint8_t(1), __ATOMIC_RELAXED))
                                sl.firstTouched.push_back(r);
                            break;
                        }
                    }
                });
            }
        });
        // The slots' lowered voxels with light steps into the buckets: only the entries still current.
        for (Slot& sl : local) {
            for (const HeapEntry& e : sl.light)
                if (e.first == val[e.second]) queue.push(e);
            win.count += sl.pushed;
            win.lowest = std::min(win.lowest, sl.lowest);
            if (touchedList) touchedList->insert(touchedList->end(), sl.firstTouched.begin(), sl.firstTouched.end());
            sl.light.clear();
            sl.firstTouched.clear();
            sl.pushed = 0;
            sl.lowest = std::numeric_limits<std::size_t>::max();
        }
    }
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

void EikonalField::prepareSweep(const Grid3<float>& slowness, double largest) {
    // Heavy steps: those into voxels of the largest slowness (the rock), or costlier.
    heavy_ = largest;
    buildFlags(dims_, slowness, seed_, heavy_, flags_);
    adviseHugePages(flags_.data(), flags_.size());
    adviseHugePages(value_.data.data(), value_.size() * sizeof(double));
    adviseHugePages(slowness.data.data(), slowness.data.size() * sizeof(float));
    windows_ = Windows{};
    windows_.span = windowSpan(heavy_, buckets_.width);
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
            relaxBatched(dims_, slowness, cap_, heavy_, flags_, value_, buckets_, windows_, nullptr, nullptr, kInf);
        else
            relax(dims_, slowness, seed_, cap_, stencil_, value_, queue, nullptr);
    };
    useBuckets_ = false;
    buckets_ = Buckets{};
    windows_ = Windows{};
    flags_.clear();
    if (stencil == Stencil::kAvalanche26) {
        // A bucket queue when buckets as wide as the smallest edge cost (the smallest slowness
        // times 1) cover [0, cap] with at most 2^21 of them; a heap otherwise.
        float smallest = std::numeric_limits<float>::infinity(), largest = 0;
        for (float x : slowness.data) {
            smallest = std::min(smallest, x);
            largest = std::max(largest, x);
        }
        const double width = std::min(double(smallest), double(largest) / double(kMinSpan + 2));
        const double count = cap / width;
        if (smallest > 0 && std::isfinite(count) && count < double(1 << 21)) {
            useBuckets_ = true;
            buckets_.width = width;
            buckets_.bucket.resize(std::size_t(count) + 2);
            buckets_.lowest = buckets_.bucket.size() - 1;
            prepareSweep(slowness, largest);
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
    if (touched.size() != dims_.count()) {
        touched.assign(dims_.count(), 0);
        adviseHugePages(touched.data(), touched.size());
    }
    std::vector<std::size_t> touchedList;  // the voxels this call changed, each once
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
                }
            }
        }
        if constexpr (std::is_same_v<std::decay_t<decltype(queue)>, BucketQueue>) {
            const std::array<std::ptrdiff_t, 26> offset = neighbourOffsets(dims_);
            for (std::size_t c : changed)
                if (c < value_.size()) markLightNear(dims_, offset, slowness, heavy_, c, flags_);
            relaxBatched(dims_, slowness, cap_, heavy_, flags_, value_, buckets_, windows_, &touched, &touchedList,
                         limit);
        } else {
            relax(dims_, slowness, seed_, cap_, stencil_, value_, queue, &touched, &touchedList, limit);
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
        if (flags_.size() != dims_.count()) {  // after `restore`
            float largest = 0;
            for (float x : slowness.data) largest = std::max(largest, x);
            prepareSweep(slowness, largest);
        }
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
        if (windows_.count > std::max<std::size_t>(std::size_t(1) << 16, 2 * windows_.compacted)) {
            windows_.count = 0;
            for (auto& slot : windows_.slot)
                for (std::size_t w = windows_.lowest; w < slot.size(); ++w) {
                    current(slot[w]);
                    windows_.count += slot[w].size();
                }
            windows_.compacted = windows_.count;
        }
        return touchedList.size();
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
    return touchedList.size();
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
    // The queue in one form whatever the thread count and the order of pushes: its current
    // entries (stale ones lower nothing) from the buckets and the windows, each in the bucket of
    // its value, ordered by (value, voxel) within a bucket.
    std::vector<std::pair<std::size_t, HeapEntry>> entries;  // (bucket, entry)
    const auto add = [&](const std::vector<HeapEntry>& list) {
        for (const HeapEntry& e : list)
            if (e.first == value_[e.second]) entries.push_back({bucketIndex(buckets_, e.first), e});
    };
    for (std::size_t b = std::min(buckets_.lowest, buckets_.bucket.size()); b < buckets_.bucket.size(); ++b)
        add(buckets_.bucket[b]);
    for (const auto& slot : windows_.slot)
        for (std::size_t w = windows_.lowest; w < slot.size(); ++w) add(slot[w]);
    std::sort(entries.begin(), entries.end());
    entries.erase(std::unique(entries.begin(), entries.end()), entries.end());
    std::size_t lowest = buckets_.bucket.empty() ? 0 : buckets_.bucket.size() - 1;
    if (!entries.empty()) lowest = entries.front().first;
    out.put(std::uint64_t(lowest));
    out.put(std::uint64_t(entries.size()));
    out.put(std::uint64_t(entries.size()));
    out.put(std::uint64_t(buckets_.bucket.size()));
    std::uint64_t filled = 0;
    for (std::size_t k = 0; k < entries.size(); ++k) filled += k == 0 || entries[k].first != entries[k - 1].first;
    out.put(filled);
    std::vector<HeapEntry> bucket;
    for (std::size_t k = 0; k < entries.size(); ++k) {
        bucket.push_back(entries[k].second);
        if (k + 1 == entries.size() || entries[k + 1].first != entries[k].first) {
            out.put(std::uint64_t(entries[k].first));
            putEntries(out, bucket);
            bucket.clear();
        }
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
    f.windows_.span = 1;  // the windows are made by the next call (`prepareSweep`): all entries wait in the buckets
    *this = std::move(f);
}

LabelledArrival marchLabelled(const Dims& dims, const Grid3<float>* slowness, const std::vector<Seed>& seeds,
                              const std::vector<double>& labelSpeed, const ProgressFn& progress,
                              const std::string& progressPhase) {
    CAVESIM_CHECK(!slowness || slowness->dims == dims, "marchLabelled: slowness grid has other dims");
    for (double s : labelSpeed)
        CAVESIM_CHECK(s > 0 && std::isfinite(s), "marchLabelled: label speeds must be > 0, got " + std::to_string(s));
    for (const Seed& s : seeds) {
        CAVESIM_CHECK(s.voxel < dims.count(), "marchLabelled: seed voxel " + std::to_string(s.voxel) +
                                                  " outside a grid of " + std::to_string(dims.count()));
        CAVESIM_CHECK(s.label >= 0 && std::size_t(s.label) < labelSpeed.size(),
                      "marchLabelled: seed label " + std::to_string(s.label) + " has no speed");
        CAVESIM_CHECK(s.value >= 0 && std::isfinite(s.value),
                      "marchLabelled: seed values must be finite and >= 0, got " + std::to_string(s.value));
    }
    LabelledArrival out{Grid3<double>(dims, kInf), Grid3<std::int32_t>(dims, -1)};
    // One queue for all fronts, keeping each front's own times (the per-front minimum, as if each
    // marched alone over the block). A (voxel, label) entry holds label l's time at the voxel; a
    // voxel's best entry is in `out` (time, and the label with the flags below), any others in a
    // list (`pool`, its head per voxel in the hash map `headKey`/`headVal`). The dense entry is
    // always the voxel's best (time, label), so it settles first and is the winner. Front l's
    // update at a voxel is the Godunov update from l's own times at the face neighbours
    // (settled or not, as in a lone march), whatever label holds them, at the slowness of l (the
    // float product of a front marched alone), so wherever l propagates its times are those of
    // its own march, bit for bit. Front l stops at a voxel y where it is dominated: some label m
    // with speed >= l's has settled y with T_m(y) + margin <= T_l(y), margin = kDominanceSteps
    // times l's largest finite one-voxel cost at y and its face neighbours; from there l creates
    // no entries, only lowers those of l that its neighbours already have. Beyond y, m reaches
    // everything at least as early as l does, so l cannot win there; and a voxel z that l wins
    // does not take l's time from a dominated neighbour y: T_l(y) < T_l(z) <= T_m(z) <= T_m(y) +
    // (m's cost at z) would need the margin under one step. Three steps, not one: a first-order
    // update depends (a little) on every voxel between it and the source along monotone lattice
    // paths, not only near its ray, so near a boundary a front's time can take in its time from
    // where it stopped; with three steps the shipped scenarios give the lone marches' outputs
    // byte for byte and random tests the same labels (docs/model.md "Zones"). Popping follows
    // (time, voxel, label) and the march is serial, so the result does not depend on the thread
    // count.
    constexpr double kDominanceSteps = 3.0;
    constexpr std::int32_t kSettled = std::int32_t(1) << 30;  // the entry has been popped
    constexpr std::int32_t kSeed = std::int32_t(1) << 29;     // a seed: its time stays
    constexpr std::int32_t kMore = std::int32_t(1) << 28;     // dense code only: the voxel has a list
    constexpr std::int32_t kLabelMask = kMore - 1;
    CAVESIM_CHECK(labelSpeed.size() < std::size_t(kMore), "marchLabelled: too many labels");
    std::vector<float> inverseSpeed(labelSpeed.size());
    for (std::size_t l = 0; l < labelSpeed.size(); ++l) inverseSpeed[l] = float(1.0 / labelSpeed[l]);
    Grid3<double>& time = out.time;
    Grid3<std::int32_t>& code = out.label;
    struct Extra {
        double time;
        std::int32_t code;
        std::int32_t next;
    };
    std::vector<Extra> pool;
    // Open-addressed map voxel -> first list entry (voxels with more than one label only).
    std::vector<std::uint64_t> headKey(1024, ~std::uint64_t(0));
    std::vector<std::int32_t> headVal(1024, -1);
    std::size_t headCount = 0;
    const auto slotOf = [&](std::uint64_t key) {
        const std::size_t mask = headKey.size() - 1;
        std::size_t h = std::size_t((key * 0x9E3779B97F4A7C15ull) >> 20) & mask;
        while (headKey[h] != key && headKey[h] != ~std::uint64_t(0)) h = (h + 1) & mask;
        return h;
    };
    const auto headOf = [&](std::size_t n) -> std::int32_t& {
        std::size_t h = slotOf(n);
        if (headKey[h] == ~std::uint64_t(0)) {
            if (2 * (headCount + 1) > headKey.size()) {
                std::vector<std::uint64_t> oldKey(headKey.size() * 2, ~std::uint64_t(0));
                std::vector<std::int32_t> oldVal(headVal.size() * 2, -1);
                oldKey.swap(headKey);
                oldVal.swap(headVal);
                for (std::size_t s = 0; s < oldKey.size(); ++s)
                    if (oldKey[s] != ~std::uint64_t(0)) {
                        const std::size_t t = slotOf(oldKey[s]);
                        headKey[t] = oldKey[s];
                        headVal[t] = oldVal[s];
                    }
                h = slotOf(n);
            }
            headKey[h] = n;
            ++headCount;
        }
        return headVal[h];
    };
    struct Ref {
        double* time;
        std::int32_t* code;
    };
    const auto find = [&](std::size_t n, std::int32_t l) -> Ref {
        const std::int32_t c = code[n];
        if (c < 0) return {nullptr, nullptr};
        if ((c & kLabelMask) == l) return {&time[n], &code[n]};
        if (!(c & kMore)) return {nullptr, nullptr};
        for (std::int32_t e = headOf(n); e >= 0; e = pool[std::size_t(e)].next)
            if ((pool[std::size_t(e)].code & kLabelMask) == l)
                return {&pool[std::size_t(e)].time, &pool[std::size_t(e)].code};
        return {nullptr, nullptr};
    };
    const auto timeOf = [&](std::size_t n, std::int32_t l) {
        const Ref r = find(n, l);
        return r.time ? *r.time : kInf;
    };
    struct Entry {
        double time;
        std::size_t voxel;
        std::int32_t label;
        bool operator>(const Entry& o) const {
            return time != o.time ? time > o.time : voxel != o.voxel ? voxel > o.voxel : label > o.label;
        }
    };
    std::vector<Entry> heap;
    const auto push = [&](double t, std::size_t n, std::int32_t l) {
        heap.push_back({t, n, l});
        std::push_heap(heap.begin(), heap.end(), std::greater<Entry>());
    };
    // Sets label l's time at voxel n to t (creating the entry), keeping the best pair in `out`.
    const auto put = [&](std::size_t n, std::int32_t l, double t, std::int32_t flags) {
        Ref r = find(n, l);
        if (!r.time) {
            if (code[n] < 0) {
                time[n] = t;
                code[n] = l | flags;
                return;
            }
            std::int32_t& head = headOf(n);
            pool.push_back({t, l | flags, head});
            CAVESIM_CHECK(pool.size() < std::size_t(std::numeric_limits<std::int32_t>::max()),
                          "marchLabelled: too many entries");
            head = std::int32_t(pool.size() - 1);
            code[n] |= kMore;
            r = {&pool.back().time, &pool.back().code};
        } else {
            *r.time = t;
            *r.code |= flags;
        }
        if (r.code == &code[n]) return;
        // A list entry better than the unsettled dense one trades places with it.
        const std::int32_t d = code[n];
        if (d & kSettled) return;
        if (t < time[n] || (t == time[n] && l < (d & kLabelMask))) {
            std::swap(*r.time, time[n]);
            const std::int32_t moved = *r.code;
            *r.code = d & ~kMore;
            code[n] = moved | kMore;
        }
    };
    for (const Seed& s : seeds) {
        const Ref r = find(s.voxel, s.label);
        if (!r.time || s.value < *r.time) put(s.voxel, s.label, s.value, kSeed);
    }
    for (const Seed& s : seeds)
        if (*find(s.voxel, s.label).time == s.value) heap.push_back({s.value, s.voxel, s.label});
    // Ascending, without duplicates: a vector sorted ascending is a heap for std::greater.
    std::sort(heap.begin(), heap.end(), [](const Entry& a, const Entry& b) { return b > a; });
    heap.erase(std::unique(heap.begin(), heap.end(),
                           [](const Entry& a, const Entry& b) {
                               return a.time == b.time && a.voxel == b.voxel && a.label == b.label;
                           }),
               heap.end());
    const std::size_t sx = 1, sy = std::size_t(dims.nx), sz = std::size_t(dims.nx) * std::size_t(dims.ny);
    const auto cost = [&](std::size_t n, std::int32_t l) {
        return (slowness ? (*slowness)[n] : 1.0f) * inverseSpeed[std::size_t(l)];
    };
    // Label l at voxel q (time v) is dominated by a settled label of at least its speed.
    const auto dominated = [&](std::size_t q, const Index3& p, std::int32_t l, double v) {
        double best = kInf;
        const auto consider = [&](double t, std::int32_t c) {
            const std::int32_t m = c & kLabelMask;
            if ((c & kSettled) && m != l && labelSpeed[std::size_t(m)] >= labelSpeed[std::size_t(l)])
                best = std::min(best, t);
        };
        consider(time[q], code[q]);
        if (code[q] & kMore)
            for (std::int32_t e = headOf(q); e >= 0; e = pool[std::size_t(e)].next)
                consider(pool[std::size_t(e)].time, pool[std::size_t(e)].code);
        if (!(best < v)) return false;
        float step = 0;
        const auto widen = [&](std::size_t n) {
            const float f = cost(n, l);
            if (f < std::numeric_limits<float>::infinity()) step = std::max(step, f);
        };
        widen(q);
        if (p.i > 0) widen(q - sx);
        if (p.i + 1 < dims.nx) widen(q + sx);
        if (p.j > 0) widen(q - sy);
        if (p.j + 1 < dims.ny) widen(q + sy);
        if (p.k > 0) widen(q - sz);
        if (p.k + 1 < dims.nz) widen(q + sz);
        return best + kDominanceSteps * double(step) <= v;
    };
    constexpr std::size_t kProgressEvery = std::size_t(1) << 20;  // settled voxels between reports
    const long total = long(dims.count());
    std::size_t won = 0;  // voxels settled by their winning front
    while (!heap.empty()) {
        const Entry e = heap.front();
        std::pop_heap(heap.begin(), heap.end(), std::greater<Entry>());
        heap.pop_back();
        const std::size_t q = e.voxel;
        const std::int32_t l = e.label;
        const double v = e.time;
        const Ref self = find(q, l);
        if ((*self.code & kSettled) || v != *self.time) continue;  // settled already, or a stale entry
        *self.code |= kSettled;
        if (self.code == &code[q] && ++won % kProgressEvery == 0)
            reportProgress(progress, progressPhase, long(won), total);
        const Index3 p = dims.coord(q);
        const bool stop = self.code != &code[q] && dominated(q, p, l, v);
        const auto visit = [&](std::size_t r, int i, int j, int k) {
            const Ref target = find(r, l);
            if (stop && !target.time) return;
            if (target.time && ((*target.code & (kSettled | kSeed)) || *target.time <= v)) return;
            const auto own = [&](std::size_t n) { return timeOf(n, l); };  // label l's times
            double ax, ay, az;
            axisMinima(dims, {i, j, k}, own, ax, ay, az);
            const double u = upwindUpdate(ax, ay, az, cost(r, l));
            if (target.time ? u < *target.time : u < kInf) {
                put(r, l, u, 0);
                push(u, r, l);
            }
        };
        if (p.i > 0) visit(q - sx, p.i - 1, p.j, p.k);
        if (p.i + 1 < dims.nx) visit(q + sx, p.i + 1, p.j, p.k);
        if (p.j > 0) visit(q - sy, p.i, p.j - 1, p.k);
        if (p.j + 1 < dims.ny) visit(q + sy, p.i, p.j + 1, p.k);
        if (p.k > 0) visit(q - sz, p.i, p.j, p.k - 1);
        if (p.k + 1 < dims.nz) visit(q + sz, p.i, p.j, p.k + 1);
    }
    for (std::int32_t& c : code.data)
        if (c >= 0) c &= kLabelMask;
    return out;
}

}  // namespace cavesim::fastmarch

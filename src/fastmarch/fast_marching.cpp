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
#include <utility>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/check.h"

namespace cavesim::fastmarch {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Min-heap of (value, voxel); equal values pop in voxel order, so runs are reproducible.
using HeapEntry = std::pair<double, std::size_t>;
using MinHeap = std::priority_queue<HeapEntry, std::vector<HeapEntry>, std::greater<HeapEntry>>;

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
std::size_t relax(const Dims& d, const Grid3<float>& slowness, const std::vector<std::uint8_t>& seed, double cap,
                  Stencil stencil, Grid3<double>& value, MinHeap& heap, std::vector<std::uint8_t>* touched) {
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
                ++changes;
            }
        }
    };
    while (!heap.empty()) {
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
    MinHeap heap;
    for (const Seed& s : seeds) {
        CAVESIM_CHECK(s.voxel < dims.count(), "EikonalField::solve: seed voxel " + std::to_string(s.voxel) +
                                                  " outside a grid of " + std::to_string(dims.count()));
        const double v = std::min(cap, s.value);
        if (!seed_[s.voxel] || v < value_[s.voxel]) value_[s.voxel] = v;
        seed_[s.voxel] = 1;
    }
    for (std::size_t n = 0; n < seed_.size(); ++n)
        if (seed_[n]) heap.push({value_[n], n});
    relax(dims_, slowness, seed_, cap_, stencil_, value_, heap, nullptr);
}

std::size_t EikonalField::decrease(const Grid3<float>& slowness, const std::vector<std::size_t>& changed) {
    MinHeap heap;
    std::vector<std::uint8_t> touched(dims_.count(), 0);
    std::size_t changes = 0;
    const auto get = [&](std::size_t n) { return value_[n]; };
    for (std::size_t q : changed) {
        if (q >= value_.size() || seed_[q]) continue;
        const double u = fullUpdate(dims_, dims_.coord(q), get, slowness[q], stencil_, cap_);
        if (u < value_[q]) {
            value_[q] = u;
            heap.push({u, q});
            if (!touched[q]) {
                touched[q] = 1;
                ++changes;
            }
        }
    }
    return changes + relax(dims_, slowness, seed_, cap_, stencil_, value_, heap, &touched);
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

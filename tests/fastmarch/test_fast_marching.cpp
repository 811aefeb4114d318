// Fast marching against exact answers: distance from a point and a plane, bisector and
// Apollonius boundaries of labelled fronts, caps, incremental updates, mirror symmetry.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <queue>
#include <random>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include "core/error.h"
#include "fastmarch/fast_marching.h"

namespace cavesim::fastmarch {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

Grid3<float> ones(const Dims& d) {
    return Grid3<float>(d, 1.0f);
}

TEST(UpwindUpdate, OneTwoThreeAxes) {
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_DOUBLE_EQ(upwindUpdate(0, inf, inf, 1), 1.0);
    // Two equal neighbours at 0: u = 1/sqrt(2).
    EXPECT_NEAR(upwindUpdate(0, 0, inf, 1), 1.0 / std::sqrt(2.0), 1e-15);
    EXPECT_NEAR(upwindUpdate(0, 0, 0, 1), 1.0 / std::sqrt(3.0), 1e-15);
    // A far neighbour is ignored: a1 >= a0 + f.
    EXPECT_DOUBLE_EQ(upwindUpdate(0, 5, inf, 1), 1.0);
    EXPECT_EQ(upwindUpdate(inf, inf, inf, 1), inf);
}

TEST(Eikonal, PlaneDistanceIsExact) {
    const Dims d{20, 7, 9};
    std::vector<Seed> seeds;
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j) seeds.push_back({d.index(0, j, k), 0.0, 0});
    EikonalField f;
    f.solve(d, ones(d), seeds, 1e9);
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) EXPECT_NEAR(f.value().at(i, j, k), double(i), 1e-12);
}

TEST(Eikonal, PointDistanceFirstOrder) {
    const Dims d{41, 41, 41};
    const Index3 c{20, 20, 20};
    EikonalField f;
    f.solve(d, ones(d), {{d.index(c), 0.0, 0}}, 1e9);
    double maxRelNear = 0, maxRel = 0;  // 5 <= r < 10, and r >= 15
    for (std::size_t n = 0; n < d.count(); ++n) {
        const Index3 p = d.coord(n);
        const double r =
            std::sqrt(double((p.i - c.i) * (p.i - c.i) + (p.j - c.j) * (p.j - c.j) + (p.k - c.k) * (p.k - c.k)));
        if (r < 5) continue;
        const double t = f.value()[n];
        EXPECT_GE(t, r - 1e-9);  // the first-order scheme overestimates the distance
        if (r < 10) maxRelNear = std::max(maxRelNear, (t - r) / r);
        if (r >= 15) maxRel = std::max(maxRel, (t - r) / r);
    }
    // First-order error of the 6-neighbour scheme from a point: largest off the axes and near the
    // point, shrinking with distance.
    EXPECT_LT(maxRel, 0.15);
    EXPECT_LT(maxRel, maxRelNear);
}

TEST(Eikonal, SlownessScalesAndCapBinds) {
    const Dims d{30, 1, 1};
    Grid3<float> s(d, 0.5f);
    EikonalField f;
    f.solve(d, s, {{0, 0.0, 0}}, 10.0);
    for (int i = 0; i < 30; ++i) EXPECT_NEAR(f.value().at(i, 0, 0), std::min(10.0, 0.5 * i), 1e-12);
}

class EikonalStencils : public ::testing::TestWithParam<Stencil> {};
INSTANTIATE_TEST_SUITE_P(Eikonal, EikonalStencils, ::testing::Values(Stencil::kFace6, Stencil::kAvalanche26));

TEST_P(EikonalStencils, IncrementalDecreaseEqualsFullSolve) {
    const Stencil stencil = GetParam();
    const Dims d{24, 18, 10};
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<float> u(0.2f, 2.0f);
    Grid3<float> s(d);
    for (auto& x : s.data) x = u(rng);
    const std::vector<Seed> seeds{{d.index(23, 9, 0), 0.0, 0}, {d.index(23, 10, 0), 0.0, 0}};
    EikonalField inc;
    inc.solve(d, s, seeds, 40.0, stencil);
    for (int round = 0; round < 30; ++round) {
        std::vector<std::size_t> changed;
        std::uniform_int_distribution<std::size_t> pick(0, d.count() - 1);
        for (int c = 0; c < 25; ++c) {
            const std::size_t q = pick(rng);
            s[q] *= 0.1f;
            changed.push_back(q);
        }
        const Grid3<double> before = inc.value();
        inc.decrease(s, changed);
        EikonalField full;
        full.solve(d, s, seeds, 40.0, stencil);
        for (std::size_t n = 0; n < d.count(); ++n) {
            ASSERT_NEAR(inc.value()[n], full.value()[n], 1e-9) << "round " << round << " voxel " << n;
            ASSERT_LE(inc.value()[n], before[n]);  // only decreases
        }
    }
}

// Decreases limited to a value (the rest pending) give, where they are final, the same bits as
// unlimited ones, and after settle() the same bits everywhere.
// Both queues: a bucket queue (cap 200: 10^4 buckets of the smallest slowness) and a heap (cap
// 10^9: too many buckets).
TEST(Eikonal, LimitedDecreaseIsFinalBelowTheLimitAndSettlesToTheSameBits) {
    for (double cap : {200.0, 1e9}) {
        const Dims d{24, 18, 10};
        std::mt19937_64 rng(5);
        std::uniform_real_distribution<float> u(0.2f, 2.0f);
        Grid3<float> s(d);
        for (auto& x : s.data) x = u(rng);
        const std::vector<Seed> seeds{{d.index(23, 9, 0), 0.0, 0}};
        EikonalField whole, limited;
        whole.solve(d, s, seeds, cap, Stencil::kAvalanche26);
        limited.solve(d, s, seeds, cap, Stencil::kAvalanche26);
        std::uniform_int_distribution<std::size_t> pick(0, d.count() - 1);
        for (int round = 0; round < 20; ++round) {
            std::vector<std::size_t> changed;
            for (int c = 0; c < 10; ++c) {
                const std::size_t q = pick(rng);
                s[q] *= 0.1f;
                changed.push_back(q);
            }
            whole.decrease(s, changed);
            const double limit = 2.0 + 0.5 * round;
            limited.decrease(s, changed, limit);
            for (std::size_t n = 0; n < d.count(); ++n) {
                if (whole.value()[n] <= limit) {
                    ASSERT_EQ(limited.value()[n], whole.value()[n]) << round << " " << n;
                }
                ASSERT_GE(limited.value()[n], whole.value()[n]);  // elsewhere at most too high
            }
        }
        EXPECT_FALSE(limited.settled());
        limited.settle(s);
        EXPECT_TRUE(limited.settled());
        EXPECT_EQ(limited.value().data, whole.value().data);
        EikonalField fresh;  // and a full solve with the final slowness gives the same bits
        fresh.solve(d, s, seeds, cap, Stencil::kAvalanche26);
        EXPECT_EQ(fresh.value().data, whole.value().data);
    }
}

/// Dijkstra on the 26-neighbour graph with a binary heap, written out plainly: the values the
/// avalanche stencil must give (each the minimum over paths of the same rounded path costs).
std::vector<double> referenceAvalanche(const Dims& d, const Grid3<float>& s, const std::vector<Seed>& seeds,
                                       double cap) {
    std::vector<double> t(d.count(), cap);
    std::vector<std::uint8_t> isSeed(d.count(), 0);
    using E = std::pair<double, std::size_t>;
    std::priority_queue<E, std::vector<E>, std::greater<E>> heap;
    for (const Seed& q : seeds) {
        t[q.voxel] = std::min(cap, q.value);
        isSeed[q.voxel] = 1;
        heap.push({t[q.voxel], q.voxel});
    }
    while (!heap.empty()) {
        const auto [v, q] = heap.top();
        heap.pop();
        if (v != t[q]) continue;
        const Index3 p = d.coord(q);
        for (const auto& o : allNeighbours()) {
            if (!d.contains(p.i + o.di, p.j + o.dj, p.k + o.dk)) continue;
            const std::size_t r = d.index(p.i + o.di, p.j + o.dj, p.k + o.dk);
            const double u = std::min(cap, v + double(s[r]) * o.length);
            if (!isSeed[r] && u < t[r]) {
                t[r] = u;
                heap.push({u, r});
            }
        }
    }
    return t;
}

// The stage-2 case at a size where the held heavy steps run in parallel (rock 0.5, channels
// 0.001 growing a few voxels per call, limited decreases): the values and the count of changed
// voxels of every call are the same bits with one thread and with two, and equal a plain
// Dijkstra after every call where final and after settle() everywhere.
TEST(Eikonal, BatchedHeavyStepsGiveTheSameBitsOnAnyThreadCount) {
    const Dims d{80, 80, 40};
    const double cap = 2.0 * 0.5 * (80 + 80 + 40);
    std::vector<Seed> seeds;
    for (int k = 0; k < 8; ++k)
        for (int j = 36; j < 44; ++j) seeds.push_back({d.index(79, j, k), 0.0, 0});
    struct Run {
        std::vector<std::vector<double>> values;
        std::vector<std::size_t> changes;
        std::vector<std::string> saved;  // the field's checkpoint bytes after every limited call
    };
    const auto run = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        Grid3<float> s(d, 0.5f);
        std::mt19937_64 rng(3);
        std::uniform_int_distribution<int> step(-1, 1);
        Index3 tip{70, 40, 4};
        EikonalField f;
        f.solve(d, s, seeds, cap, Stencil::kAvalanche26);
        Run out;
        out.values.push_back(f.value().data);
        for (int call = 0; call < 24; ++call) {
            std::vector<std::size_t> changed;
            for (int c = 0; c < 6; ++c) {  // the channel grows away from the sink
                tip = {std::clamp(tip.i - 1 + step(rng), 1, d.nx - 2), std::clamp(tip.j + step(rng), 1, d.ny - 2),
                       std::clamp(tip.k + step(rng), 1, d.nz - 2)};
                if (s[d.index(tip)] > 0.001f) {
                    s[d.index(tip)] = 0.001f;
                    changed.push_back(d.index(tip));
                }
            }
            out.changes.push_back(f.decrease(s, changed, call % 3 == 2 ? kInfinity : 20.0 + call));
            out.values.push_back(f.value().data);
            if (call % 3 != 2) {
                std::string bytes;
                ByteWriter w(bytes);
                f.save(w);
                out.saved.push_back(bytes);
            }
            if (call == 10) {  // continue from a restored copy: the later calls give the same bits
                ByteReader r(out.saved.back().data(), out.saved.back().size(), "field");
                EikonalField g;
                g.restore(r, d);
                f = std::move(g);
            }
        }
        out.changes.push_back(f.settle(s));
        out.values.push_back(f.value().data);
        const std::vector<double> expect = referenceAvalanche(d, s, seeds, cap);
        EXPECT_EQ(f.value().data, expect) << threads << " thread(s)";
        return out;
    };
    const Run one = run(1), two = run(2);
    // Two workers in an arena of 2, also where the machine has one core.
    Run arena;
    tbb::task_arena(2).execute([&] { arena = run(2); });
    for (const Run* other : std::vector<const Run*>{&two, &arena}) {
        EXPECT_EQ(one.changes, other->changes);
        ASSERT_EQ(one.values.size(), other->values.size());
        for (std::size_t c = 0; c < one.values.size(); ++c) ASSERT_EQ(one.values[c], other->values[c]) << "call " << c;
        EXPECT_EQ(one.saved, other->saved);  // the pending queue, too, whatever the thread count
    }
    EXPECT_GT(one.changes.front(), 1000u);  // the calls do move a large front
}

TEST(Eikonal, AvalancheStepsCarryLowValuesAlongADiagonalChannel) {
    // A channel of slowness 0.001 that is only edge-connected (a diagonal staircase in x–z), in rock
    // of slowness 0.05. Face-neighbour fast marching must leave the channel at every step; the
    // avalanche stencil (paper §3.2: rise from any neighbour by at most rate · distance) follows it.
    const Dims d{20, 1, 20};
    Grid3<float> s(d, 0.05f);
    for (int t = 0; t < 20; ++t) s.at(t, 0, t) = 0.001f;
    const std::vector<Seed> seeds{{d.index(0, 0, 0), 0.0, 0}};
    EikonalField face, avalanche;
    face.solve(d, s, seeds, 1e9, Stencil::kFace6);
    avalanche.solve(d, s, seeds, 1e9, Stencil::kAvalanche26);
    for (int t = 1; t < 20; ++t)
        EXPECT_NEAR(avalanche.value().at(t, 0, t), double(0.001f) * std::sqrt(2.0) * t, 1e-12) << t;
    EXPECT_GT(face.value().at(19, 0, 19), 10 * avalanche.value().at(19, 0, 19));
    // In uniform rock the avalanche stencil gives the 26-neighbour (in a plane: 8-neighbour)
    // path length: exact along axes and diagonals, never below the Euclidean distance and at most
    // 8.3 % above it in a plane (worst at 22.5°).
    Grid3<float> ones(d, 1.0f);
    avalanche.solve(d, ones, seeds, 1e9, Stencil::kAvalanche26);
    face.solve(d, ones, seeds, 1e9, Stencil::kFace6);
    for (int k = 0; k < d.nz; ++k)
        for (int i = 0; i < d.nx; ++i) {
            const double exact = std::hypot(double(i), double(k));
            const int lo = std::min(i, k), hi = std::max(i, k);
            EXPECT_NEAR(avalanche.value().at(i, 0, k), lo * std::sqrt(2.0) + (hi - lo), 1e-9);
            EXPECT_LE(avalanche.value().at(i, 0, k), exact * 1.083 + 1e-12);
            EXPECT_GE(avalanche.value().at(i, 0, k), exact - 1e-12);
        }
}

TEST(Eikonal, MirrorSymmetricBitwise) {
    const Dims d{17, 5, 9};
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<float> u(0.3f, 1.7f);
    Grid3<float> s(d);
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i <= d.nx / 2; ++i) s.at(i, j, k) = s.at(d.nx - 1 - i, j, k) = u(rng);
    EikonalField f;
    f.solve(d, s, {{d.index(8, 2, 0), 0.0, 0}}, 1e9);
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) ASSERT_EQ(f.value().at(i, j, k), f.value().at(d.nx - 1 - i, j, k));
}

TEST(Labelled, EqualSpeedsSplitOnTheBisector) {
    const Dims d{40, 30, 1};
    const auto out = marchLabelled(d, nullptr, {{d.index(10, 15, 0), 0, 0}, {d.index(29, 15, 0), 0, 1}}, {1.0, 1.0});
    long count[2] = {0, 0};
    for (int j = 0; j < d.ny; ++j)
        for (int i = 0; i < d.nx; ++i) {
            const int l = out.label.at(i, j, 0);
            ASSERT_GE(l, 0);
            ++count[l];
            // Away from the bisector x = 19.5, the nearer source wins.
            if (i <= 18) {
                EXPECT_EQ(l, 0) << i << "," << j;
            } else if (i >= 21) {
                EXPECT_EQ(l, 1) << i << "," << j;
            }
        }
    EXPECT_LT(std::abs(count[0] - count[1]), 0.05 * (count[0] + count[1]));
}

TEST(Labelled, SpeedRatioTwoGivesApolloniusCircle) {
    // Fronts from a (speed 2) and b (speed 1): the boundary is the Apollonius circle where
    // |x−a| = 2|x−b|: centre b + (b−a)/3, radius 2|b−a|/3.
    const Dims d{81, 81, 1};
    const double ax = 25, ay = 40, bx = 49, by = 40;
    const auto out = marchLabelled(d, nullptr, {{d.index(25, 40, 0), 0, 0}, {d.index(49, 40, 0), 0, 1}}, {2.0, 1.0});
    const double cx = bx + (bx - ax) / 3, cy = by + (by - ay) / 3, rad = 2 * (bx - ax) / 3;
    int wrong = 0, checked = 0;
    for (int j = 0; j < d.ny; ++j)
        for (int i = 0; i < d.nx; ++i) {
            const double r = std::hypot(i - cx, j - cy);
            const int expect = r < rad ? 1 : 0;
            if (std::abs(r - rad) < 2.5) continue;  // first-order band around the circle
            ++checked;
            wrong += out.label.at(i, j, 0) != expect;
        }
    EXPECT_GT(checked, 5000);
    EXPECT_LT(wrong, checked / 200);
}

TEST(Labelled, ImpassableVoxelsAreNotReached) {
    const Dims d{9, 1, 1};
    Grid3<float> s(d, 1.0f);
    s.at(4, 0, 0) = std::numeric_limits<float>::infinity();
    const auto out = marchLabelled(d, &s, {{0, 0, 0}}, {1.0});
    EXPECT_EQ(out.label.at(3, 0, 0), 0);
    EXPECT_EQ(out.label.at(4, 0, 0), -1);
    EXPECT_EQ(out.label.at(8, 0, 0), -1);
    EXPECT_TRUE(std::isinf(out.time.at(8, 0, 0)));
}

/// Random slowness in [0.5, 2] with every 37th voxel impassable.
Grid3<float> randomSlowness(const Dims& d, unsigned seed, bool walls = true) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.5f, 2.0f);
    Grid3<float> s(d);
    for (float& v : s.data) v = u(rng);
    if (walls)
        for (std::size_t v = 0; v < s.size(); v += 37) s[v] = std::numeric_limits<float>::infinity();
    return s;
}

TEST(Labelled, OneLabelIsTheSingleFrontBitForBit) {
    // With one label the labelled march is plain fast marching: the same bits as EikonalField.
    const Dims d{23, 17, 9};
    const Grid3<float> s = randomSlowness(d, 5, false);
    const std::vector<Seed> seeds{{d.index(2, 3, 4), 0, 0}, {d.index(20, 3, 1), 0, 0}};
    EikonalField f;
    f.solve(d, s, seeds, std::numeric_limits<double>::infinity());
    const auto got = marchLabelled(d, &s, seeds, {1.0});
    for (std::size_t v = 0; v < d.count(); ++v) {
        ASSERT_EQ(got.time[v], f.value()[v]) << v;
        ASSERT_EQ(got.label[v], 0) << v;
    }
}

TEST(Labelled, RowGivesExactTimes) {
    // A row of 11 voxels: label 0 at x = 0 (speed 1), label 1 at x = 10 (speed 2, slowness 0.5).
    // Label 0 arrives at x at time x, label 1 at (10 − x) / 2: label 0 holds x <= 3 (3 < 3.5),
    // label 1 from x = 4 (3 < 4).
    const Dims d{11, 1, 1};
    const auto out = marchLabelled(d, nullptr, {{0, 0, 0}, {10, 0, 1}}, {1.0, 2.0});
    const std::vector<double> time{0, 1, 2, 3, 3, 2.5, 2, 1.5, 1, 0.5, 0};
    const std::vector<std::int32_t> label{0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1};
    EXPECT_EQ(out.time.data, time);
    EXPECT_EQ(out.label.data, label);
    // Equal speeds: the middle voxel ties at time 5 and goes to the lower label, whichever
    // seed is listed first.
    const auto tie = marchLabelled(d, nullptr, {{10, 0, 1}, {0, 0, 0}}, {1.0, 1.0});
    EXPECT_EQ(tie.time.at(5, 0, 0), 5.0);
    EXPECT_EQ(tie.label.at(5, 0, 0), 0);
    EXPECT_EQ(tie.label.at(6, 0, 0), 1);
}

TEST(Labelled, ReportsProgressAndStopsWhenCancelled) {
    // 128 × 128 × 160 = 2 621 440 voxels, two fronts: a report every 2^20 settled voxels (two), each
    // with the phase, the count so far and the grid's voxel count; the result is the same as
    // without a callback.
    const Dims d{128, 128, 160};
    const std::vector<Seed> seeds{{d.index(0, 0, 0), 0, 0}, {d.index(127, 127, 159), 0, 1}};
    std::vector<long> done;
    const auto out = marchLabelled(
        d, nullptr, seeds, {1.0, 1.5},
        [&](const std::string& phase, long n, long total) {
            EXPECT_EQ(phase, "zones");
            EXPECT_EQ(total, long(d.count()));
            done.push_back(n);
        },
        "zones");
    EXPECT_EQ(done, (std::vector<long>{1L << 20, 2L << 20}));
    const auto plain = marchLabelled(d, nullptr, seeds, {1.0, 1.5});
    EXPECT_EQ(out.label.data, plain.label.data);
    EXPECT_EQ(out.time.data, plain.time.data);
    // A callback that throws Cancelled stops the march at the first report.
    int calls = 0;
    EXPECT_THROW(marchLabelled(d, nullptr, seeds, {1.0, 1.5},
                               [&](const std::string&, long, long) {
                                   ++calls;
                                   throw Cancelled("test");
                               }),
                 Cancelled);
    EXPECT_EQ(calls, 1);
}

TEST(Labelled, FrontsPassThroughEachOthersVoxels) {
    // 2×2: label 0 starts at (0,0) at time 0, label 1 at (1,0) at time 0.9, both speed 1.
    // Label 1 holds (1,0) (0.9 < 1), but label 0's own time there (1) is within the dominance
    // margin, so label 0 still propagates from it: at (1,1) label 0's two-sided update
    // (2 + √2) / 2 = 1.707 beats label 1's 0.9 + 1 = 1.9, as with fronts marched alone.
    const Dims d{2, 2, 1};
    const auto out = marchLabelled(d, nullptr, {{d.index(0, 0, 0), 0, 0}, {d.index(1, 0, 0), 0.9, 1}}, {1.0, 1.0});
    EXPECT_EQ(out.label.data, (std::vector<std::int32_t>{0, 1, 0, 0}));
    EXPECT_EQ(out.time.data,
              (std::vector<double>{0, 0.9, 1, upwindUpdate(1, 1, std::numeric_limits<double>::infinity(), 1)}));
}

/// Exact multiplicatively weighted Voronoi label of voxel (i, j, k): argmin |x − s_l| / p_l
/// (lower label on ties).
int voronoiLabel(const std::vector<Index3>& at, const std::vector<double>& p, int i, int j, int k) {
    int best = -1;
    double bestD = std::numeric_limits<double>::infinity();
    for (std::size_t l = 0; l < at.size(); ++l) {
        const double dist = std::sqrt(double((i - at[l].i) * (i - at[l].i) + (j - at[l].j) * (j - at[l].j) +
                                             (k - at[l].k) * (k - at[l].k))) /
                            p[l];
        if (dist < bestD) {
            bestD = dist;
            best = int(l);
        }
    }
    return best;
}

/// Voxels whose march label differs from the weighted Voronoi label although no voxel of their
/// 3×3×3 neighbourhood has another Voronoi label (i.e. more than one voxel from a boundary).
/// `wrongNear` counts those within one voxel of a boundary.
long wrongAwayFromBoundaries(const Dims& d, const LabelledArrival& out, const std::vector<Index3>& at,
                             const std::vector<double>& p, long& wrongNear) {
    Grid3<std::int32_t> exact(d);
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) exact.at(i, j, k) = voronoiLabel(at, p, i, j, k);
    long wrong = 0;
    wrongNear = 0;
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                if (out.label.at(i, j, k) == exact.at(i, j, k)) continue;
                bool nearBoundary = false;
                for (const auto& o : allNeighbours())
                    if (d.contains(i + o.di, j + o.dj, k + o.dk) &&
                        exact.at(i + o.di, j + o.dj, k + o.dk) != exact.at(i, j, k))
                        nearBoundary = true;
                ++(nearBoundary ? wrongNear : wrong);
            }
    return wrong;
}

TEST(Labelled, UnequalSpeedsGiveTheWeightedVoronoiCellsInTwoAndThreeSources) {
    // Uniform rock, 3D, two and three sources of unequal speeds (the slower ones on the +x
    // face): the labels are the weighted Voronoi cells (Apollonius spheres) except within one
    // voxel of a boundary.
    const Dims d{40, 32, 20};
    const std::vector<Index3> two{{6, 16, 10}, {39, 14, 8}};
    const std::vector<double> p2{2.0, 1.0};
    const std::vector<Index3> three{{6, 16, 10}, {39, 6, 8}, {39, 26, 12}};
    const std::vector<double> p3{2.0, 1.0, 1.3};
    for (const auto& [at, p] : {std::pair{two, p2}, std::pair{three, p3}}) {
        std::vector<Seed> seeds;
        for (std::size_t l = 0; l < at.size(); ++l) seeds.push_back({d.index(at[l]), 0, int(l)});
        const auto out = marchLabelled(d, nullptr, seeds, p);
        long near = 0;
        EXPECT_EQ(wrongAwayFromBoundaries(d, out, at, p, near), 0) << at.size() << " sources";
        std::vector<long> count(at.size(), 0);
        for (std::int32_t l : out.label.data) ++count[std::size_t(l)];
        for (long c : count) EXPECT_GT(c, 500) << at.size() << " sources";
        EXPECT_LT(near, long(d.count()) / 50) << at.size() << " sources";
    }
}

TEST(Labelled, MirroredInputGivesMirroredLabels) {
    // Equal speeds, random slowness with walls, three seeds; the whole input mirrored in x, in y
    // and in both gives the mirrored labels and times, bit for bit.
    const Dims d{23, 17, 9};
    const Grid3<float> s = randomSlowness(d, 9);
    const std::vector<Index3> at{{2, 3, 4}, {18, 5, 1}, {11, 14, 7}};
    const auto march = [&](bool mx, bool my) {
        Grid3<float> m(d);
        for (int k = 0; k < d.nz; ++k)
            for (int j = 0; j < d.ny; ++j)
                for (int i = 0; i < d.nx; ++i) m.at(mx ? d.nx - 1 - i : i, my ? d.ny - 1 - j : j, k) = s.at(i, j, k);
        std::vector<Seed> seeds;
        for (std::size_t l = 0; l < at.size(); ++l)
            seeds.push_back(
                {d.index(mx ? d.nx - 1 - at[l].i : at[l].i, my ? d.ny - 1 - at[l].j : at[l].j, at[l].k), 0, int(l)});
        return marchLabelled(d, &m, seeds, {1.0, 1.0, 1.0});
    };
    const auto plain = march(false, false);
    for (int l = 0; l < 3; ++l) EXPECT_GT(std::count(plain.label.data.begin(), plain.label.data.end(), l), 200) << l;
    for (const auto& [mx, my] : {std::pair{true, false}, std::pair{false, true}, std::pair{true, true}}) {
        const auto mirrored = march(mx, my);
        for (int k = 0; k < d.nz; ++k)
            for (int j = 0; j < d.ny; ++j)
                for (int i = 0; i < d.nx; ++i) {
                    const int mi = mx ? d.nx - 1 - i : i, mj = my ? d.ny - 1 - j : j;
                    ASSERT_EQ(mirrored.label.at(mi, mj, k), plain.label.at(i, j, k)) << i << "," << j << "," << k;
                    const double a = mirrored.time.at(mi, mj, k), b = plain.time.at(i, j, k);
                    ASSERT_TRUE(a == b || (std::isinf(a) && std::isinf(b))) << i << "," << j << "," << k;
                }
    }
}

/// The per-front minimum: each label's front marched alone over the block (EikonalField at the
/// label's slowness, the same float product), merged by (time, label).
LabelledArrival frontsMarchedAlone(const Dims& d, const Grid3<float>* s, const std::vector<Seed>& seeds,
                                   const std::vector<double>& speed) {
    LabelledArrival expect{Grid3<double>(d, std::numeric_limits<double>::infinity()), Grid3<std::int32_t>(d, -1)};
    for (int label = 0; label < int(speed.size()); ++label) {
        std::vector<Seed> own;
        for (Seed q : seeds)
            if (q.label == label) own.push_back({q.voxel, q.value, 0});
        if (own.empty()) continue;
        Grid3<float> ls(d);
        const float inv = float(1.0 / speed[std::size_t(label)]);
        for (std::size_t v = 0; v < d.count(); ++v) ls[v] = (s ? (*s)[v] : 1.0f) * inv;
        EikonalField f;
        f.solve(d, ls, own, std::numeric_limits<double>::infinity());
        for (std::size_t v = 0; v < d.count(); ++v)
            if (f.value()[v] < expect.time[v]) {
                expect.time[v] = f.value()[v];
                expect.label[v] = label;
            }
    }
    return expect;
}

void expectSame(const LabelledArrival& got, const LabelledArrival& expect, const std::string& what) {
    ASSERT_EQ(got.label.data, expect.label.data) << what;
    for (std::size_t v = 0; v < got.time.size(); ++v)
        ASSERT_TRUE(got.time[v] == expect.time[v] || (std::isinf(got.time[v]) && std::isinf(expect.time[v])))
            << what << " voxel " << v;
}

TEST(Labelled, EqualsFrontsMarchedAloneForAnyThreadCount) {
    // Five labels (one without seeds) through random slowness with impassable voxels, a seed
    // shared by two labels and a seed starting late: the labels and times are the per-front
    // minimum bit for bit, with one thread and with two.
    const Dims d{23, 17, 9};
    const Grid3<float> s = randomSlowness(d, 5);
    const std::vector<double> speed{1.0, 1.7, 0.8, 1.2, 2.5};
    const std::vector<Seed> seeds{{d.index(2, 3, 4), 0, 0},   {d.index(20, 3, 1), 0.5, 1}, {d.index(11, 15, 7), 0, 2},
                                  {d.index(12, 15, 7), 0, 2}, {d.index(5, 10, 0), 0, 4},   {d.index(2, 3, 4), 0, 4}};
    const LabelledArrival expect = frontsMarchedAlone(d, &s, seeds, speed);
    for (int threads : {1, 2}) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        expectSame(marchLabelled(d, &s, seeds, speed), expect, std::to_string(threads) + " thread(s)");
    }
    // Label 4 shares a seed voxel with label 0 at the same time: the lower label keeps it.
    EXPECT_EQ(expect.label[d.index(2, 3, 4)], 0);
    EXPECT_EQ(std::count(expect.label.data.begin(), expect.label.data.end(), 3), 0);
}

TEST(Labelled, EqualsFrontsMarchedAloneOnRandomInputs) {
    // 2–8 labels with equal and unequal speeds at random seeds (some starting late), in uniform
    // rock, in smooth slowness (a product of sines) and in rough slowness (independent per voxel
    // in [0.5, 2], some with walls): the labels are the per-front minimum's, bit for bit. The
    // times are too except for a few: a first-order update depends on every voxel between the
    // source and it (monotone lattice paths), not only on those near its ray, so a time beside
    // a zone boundary can take in, with a tiny weight, a front's time from where it has stopped
    // (docs/model.md "Zones").
    long off = 0, total = 0;
    double worst = 0;
    for (unsigned trial = 0; trial < 300; ++trial) {
        std::mt19937 rng(100 + trial);
        const Dims d{int(8 + rng() % 25), int(8 + rng() % 20), int(1 + rng() % 12)};
        const int kind = int(trial % 3);  // 0 uniform, 1 smooth, 2 rough
        Grid3<float> s = randomSlowness(d, 200 + trial, trial % 2 == 0);
        if (kind == 1) {
            const double fx = 0.2 + 0.1 * (rng() % 5), fy = 0.15 + 0.1 * (rng() % 5), fz = 0.3;
            for (int k = 0; k < d.nz; ++k)
                for (int j = 0; j < d.ny; ++j)
                    for (int i = 0; i < d.nx; ++i)
                        s.at(i, j, k) = float(1.2 + 0.7 * std::sin(fx * i) * std::cos(fy * j + 0.5 * std::sin(fz * k)));
        }
        const int labels = int(2 + rng() % 7);
        std::vector<double> speed(std::size_t(labels), 1.0);
        if (trial % 4 >= 2)
            for (double& p : speed) p = std::vector<double>{0.6, 1.0, 1.5, 2.0, 3.0}[rng() % 5];
        std::vector<Seed> seeds;
        for (int l = 0; l < labels; ++l) seeds.push_back({rng() % d.count(), double(rng() % 3) * 0.25, l});
        const Grid3<float>* slow = kind == 0 ? nullptr : &s;
        const LabelledArrival expect = frontsMarchedAlone(d, slow, seeds, speed);
        const LabelledArrival got = marchLabelled(d, slow, seeds, speed);
        ASSERT_EQ(got.label.data, expect.label.data) << "trial " << trial;
        for (std::size_t v = 0; v < d.count(); ++v) {
            ++total;
            if (got.time[v] == expect.time[v] || (std::isinf(got.time[v]) && std::isinf(expect.time[v]))) continue;
            ++off;
            worst = std::max(worst, std::abs(got.time[v] - expect.time[v]) / expect.time[v]);
        }
    }
    std::printf("times off %ld of %ld, worst relative %g\n", off, total, worst);
    EXPECT_LT(off, total / 100);
    EXPECT_LT(worst, 1e-3);
}

TEST(Labelled, BadInputThrows) {
    const Dims d{3, 3, 3};
    EXPECT_THROW(marchLabelled(d, nullptr, {{100, 0, 0}}, {1.0}), InternalError);
    EXPECT_THROW(marchLabelled(d, nullptr, {{0, 0, 2}}, {1.0}), InternalError);
    EXPECT_THROW(marchLabelled(d, nullptr, {{0, 0, 0}}, {0.0}), InternalError);
    EXPECT_THROW(marchLabelled(d, nullptr, {{0, -1.0, 0}}, {1.0}), InternalError);
}

}  // namespace
}  // namespace cavesim::fastmarch

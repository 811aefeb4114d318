// Fast marching against exact answers: distance from a point and a plane, bisector and
// Apollonius boundaries of labelled fronts, caps, incremental updates, mirror symmetry.
#include <gtest/gtest.h>

#include <cmath>
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
                if (whole.value()[n] <= limit) ASSERT_EQ(limited.value()[n], whole.value()[n]) << round << " " << n;
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

TEST(Labelled, ParallelFrontsEqualOneAtATimeForAnyThreadCount) {
    // Five labels (one without seeds) through random slowness with impassable voxels: more labels
    // than workers, so the fronts march in batches. The result must equal each front marched on
    // its own and merged by (time, label), bit for bit, with one thread and with all.
    const Dims d{23, 17, 9};
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.5f, 2.0f);
    Grid3<float> s(d);
    for (float& v : s.data) v = u(rng);
    for (std::size_t v = 0; v < s.size(); v += 37) s[v] = std::numeric_limits<float>::infinity();
    const std::vector<double> speed{1.0, 1.7, 0.8, 1.2, 2.5};
    const std::vector<Seed> seeds{{d.index(2, 3, 4), 0, 0},   {d.index(20, 3, 1), 0.5, 1}, {d.index(11, 15, 7), 0, 2},
                                  {d.index(12, 15, 7), 0, 2}, {d.index(5, 10, 0), 0, 4},   {d.index(2, 3, 4), 0, 4}};
    LabelledArrival expect{Grid3<double>(d, std::numeric_limits<double>::infinity()), Grid3<std::int32_t>(d, -1)};
    for (int label = 0; label < int(speed.size()); ++label) {
        std::vector<Seed> own;
        for (Seed q : seeds)
            if (q.label == label) own.push_back({q.voxel, q.value, 0});
        if (own.empty()) continue;
        const auto one = marchLabelled(d, &s, own, {speed[std::size_t(label)]});
        for (std::size_t v = 0; v < d.count(); ++v)
            if (one.time[v] < expect.time[v]) {
                expect.time[v] = one.time[v];
                expect.label[v] = label;
            }
    }
    for (int threads : {1, 2}) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        const auto got = marchLabelled(d, &s, seeds, speed);
        ASSERT_EQ(got.label.data, expect.label.data) << threads << " thread(s)";
        for (std::size_t v = 0; v < d.count(); ++v)
            ASSERT_TRUE(got.time[v] == expect.time[v] || (std::isinf(got.time[v]) && std::isinf(expect.time[v]))) << v;
    }
    // Label 4 shares a seed voxel with label 0 at the same time: the lower label keeps it.
    EXPECT_EQ(expect.label[d.index(2, 3, 4)], 0);
    EXPECT_EQ(std::count(expect.label.data.begin(), expect.label.data.end(), 3), 0);
}

TEST(Labelled, BadInputThrows) {
    const Dims d{3, 3, 3};
    EXPECT_THROW(marchLabelled(d, nullptr, {{100, 0, 0}}, {1.0}), InternalError);
    EXPECT_THROW(marchLabelled(d, nullptr, {{0, 0, 2}}, {1.0}), InternalError);
    EXPECT_THROW(marchLabelled(d, nullptr, {{0, 0, 0}}, {0.0}), InternalError);
}

}  // namespace
}  // namespace cavesim::fastmarch

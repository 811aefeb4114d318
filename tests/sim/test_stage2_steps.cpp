// The steps of one stage-2 iteration (sim/stage2_steps.h), each on a grid of a few voxels against
// numbers computed by hand from Listing 1 and Eq. 1–2 of the paper.
#include <cmath>
#include <initializer_list>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "sim/domain.h"
#include "sim/stage2_steps.h"

using namespace cavesim;
using namespace cavesim::stage2;

namespace {

/// The slot of direction (di, dj, dk).
int slotOf(int di, int dj, int dk) {
    for (int s = 0; s < 26; ++s)
        if (slots()[std::size_t(s)].di == di && slots()[std::size_t(s)].dj == dj && slots()[std::size_t(s)].dk == dk)
            return s;
    return -1;
}

/// A row of voxels along x with the given porosity, water and pressure; every row marked wet.
struct Row3 {
    Domain dom;
    Stage2State st;
    Grid3<double> P;
    Row3(std::vector<float> R, std::vector<double> W, std::vector<double> p)
        : dom(emptyDomain(Dims{int(R.size()), 1, 1}, 1.0, 0.f)), st(dom.dims), P(dom.dims, 0.0) {
        for (std::size_t v = 0; v < R.size(); ++v) {
            dom.porosity[v] = R[v];
            st.water[v] = W[v];
            P[v] = p[v];
        }
        activateAll(st);
    }
    double offer(std::size_t v, int di, int dj = 0, int dk = 0) const {
        return offerOf(dom, P, TransportWeight::kProportional, st, v, slotOf(di, dj, dk));
    }
    double at(const std::vector<double>& field, std::size_t v) const { return st.at(field, v); }
    void accept() { computeAcceptance(dom, P, TransportWeight::kProportional, st); }
    std::pair<double, double> move() { return moveWater(dom, P, TransportWeight::kProportional, st); }
};

}  // namespace

TEST(Stage2Steps, SlotsPairMinusAndPlusXAndKnowTheirOpposites) {
    const auto& s = slots();
    EXPECT_EQ(s[0].di, -1);
    EXPECT_EQ(s[1].di, 1);
    EXPECT_EQ(s[0].dj, s[1].dj);
    EXPECT_EQ(s[0].dk, s[1].dk);
    for (int a = 0; a < 26; ++a) {
        const Slot& x = s[std::size_t(a)];
        const Slot& y = s[std::size_t(x.opposite)];
        EXPECT_EQ(x.di, -y.di);
        EXPECT_EQ(x.dj, -y.dj);
        EXPECT_EQ(x.dk, -y.dk);
        EXPECT_DOUBLE_EQ(x.invLength, 1.0 / std::sqrt(double(x.di * x.di + x.dj * x.dj + x.dk * x.dk)));
    }
}

TEST(Stage2Steps, RefillLevelsFollowSourcePressure) {
    Domain d = emptyDomain(Dims{4, 1, 1}, 1.0, 0.1f);
    d.sourceVoxels = {{0}, {3}};
    d.sourcePressure = {1.0, 2.0};
    const std::vector<Refill> levels = refillLevels(d);
    ASSERT_EQ(levels.size(), 2u);
    EXPECT_DOUBLE_EQ(levels[0].level, 0.5);  // 1 / 2
    EXPECT_DOUBLE_EQ(levels[1].level, 1.0);
    Stage2State st(d.dims);
    st.water[0] = 0.02;  // below 0.5 · 0.1 = 0.05: filled up by 0.03
    st.water[3] = 0.2;   // above its level 0.1: left alone
    const double injected = refillSources(d, levels, st);
    EXPECT_NEAR(injected, 0.05 - 0.02, 1e-8);
    EXPECT_NEAR(st.water[0], 0.05, 1e-8);
    EXPECT_EQ(st.water[3], 0.2);
    EXPECT_EQ(st.tileWet[0], 1);  // the source tile is active and wet
}

// Listing 1 on a row: voxel 0 (W 0.4, P 2) has one lower neighbour with free capacity 0.4, so it
// offers all 0.4; voxel 1 (W 0.1, P 1) would share 0.5 of free capacity but holds only 0.1, so its
// offer is scaled to 0.1; voxel 2 is dry and offers nothing. Nobody offers uphill.
TEST(Stage2Steps, OffersFollowListing1) {
    Row3 r({0.5f, 0.5f, 0.5f}, {0.4, 0.1, 0.0}, {2, 1, 0});
    computeOffers(r.dom, r.P, TransportWeight::kProportional, r.st);
    EXPECT_DOUBLE_EQ(r.offer(0, +1), 0.4);
    EXPECT_DOUBLE_EQ(r.offer(1, +1), 0.1);
    EXPECT_EQ(r.offer(1, -1), 0.0);
    EXPECT_EQ(r.offer(2, -1), 0.0);

    r.accept();
    EXPECT_DOUBLE_EQ(r.at(r.st.incoming, 1), 0.4);
    EXPECT_DOUBLE_EQ(r.at(r.st.accept, 1), 1.0);  // free 0.4 ≥ 0.4
    EXPECT_DOUBLE_EQ(r.at(r.st.incoming, 2), 0.1);

    const auto [moved, drained] = r.move();
    EXPECT_DOUBLE_EQ(moved, 0.5);
    EXPECT_EQ(drained, 0.0);
    EXPECT_DOUBLE_EQ(r.at(r.st.fc, 0), 0.4);
    EXPECT_DOUBLE_EQ(r.at(r.st.fc, 1), 0.1);
    EXPECT_DOUBLE_EQ(r.st.water[0], 0.0);
    EXPECT_DOUBLE_EQ(r.st.water[1], 0.4);
    EXPECT_DOUBLE_EQ(r.st.water[2], 0.1);
}

// Senders are sought only among the voxels holding water (Stage2State::flowingMask), which every
// step that moves water keeps up to date: after two iterations the mask is what the water says, a
// voxel that ran dry has stopped sending and a sink that drained is not marked.
TEST(Stage2Steps, SendersAreFoundAmongTheWetVoxelsAsTheWaterMoves) {
    Row3 r({0.5f, 0.5f, 0.5f, 1.f}, {0.4, 0.1, 0.0, 0.0}, {3, 2, 1, 0});
    r.dom.flags[3] |= kSink;
    const auto maskFromWater = [&] {
        Stage2State copy = r.st;
        copy.recountWater();
        return copy.flowingMask;
    };
    for (int iteration = 0; iteration < 2; ++iteration) {
        computeOffers(r.dom, r.P, TransportWeight::kProportional, r.st);
        r.accept();
        r.move();
        EXPECT_EQ(r.st.flowingMask, maskFromWater()) << "iteration " << iteration;
    }
    // By hand: 0.4 and 0.1 move one voxel on each iteration; the sink drains the 0.1.
    EXPECT_EQ(r.st.water[0], 0.0);
    EXPECT_EQ(r.st.water[1], 0.0);
    EXPECT_DOUBLE_EQ(r.st.water[2], 0.4);
    EXPECT_EQ(r.st.flowingMask[0][0], 0b0100);  // only voxel 2 holds water; 0 and 1 ran dry, 3 drained
    computeOffers(r.dom, r.P, TransportWeight::kProportional, r.st);
    EXPECT_EQ(r.offer(1, +1), 0.0);  // a voxel that ran dry sends nothing: its last norm went back to rest
    EXPECT_DOUBLE_EQ(r.offer(2, +1), 0.4);
    EXPECT_EQ(r.st.senderMask[0][0], 0b0100);
}

// A voxel holding water with no lower neighbour sends nothing, and nothing near it sends, so its
// tile's water does not change; when the pressure beside it falls it must send (Listing 1 visits
// every voxel every iteration), and the pressure bound must cover it before that. The row is 20
// voxels long so that the stranded voxel (0) lies two tiles away from the only sender (18 → 19).
TEST(Stage2Steps, StrandedWaterSendsOnceThePressureBesideItFalls) {
    std::vector<float> R(20, 0.5f);
    std::vector<double> W(20, 0.0), p(20, 10.0);
    W[0] = 0.3;
    p[0] = 5;  // lower than both neighbours: stranded
    W[18] = 0.2;
    p[18] = 1;
    p[19] = 0;
    Row3 r(R, W, p);
    const auto iteration = [&] {
        computeOffers(r.dom, r.P, TransportWeight::kProportional, r.st);
        r.accept();
        r.move();
    };
    iteration();
    EXPECT_EQ(r.st.water[0], 0.3);  // nothing lower: it stays
    EXPECT_EQ(r.st.water[19], 0.2);
    iteration();                      // nothing changed near voxel 0
    EXPECT_EQ(r.st.water[0], 0.3);
    // The bound of the pressures the next iteration reads covers the stranded voxel.
    EXPECT_GE(pressureRead(r.dom, r.st, r.P), 5.0);
    r.P[1] = 4;  // the pressure beside it falls
    iteration();
    EXPECT_DOUBLE_EQ(r.st.water[1], 0.3);  // all of it moved: voxel 1 had room for it
    EXPECT_EQ(r.st.water[0], 0.0);
}

// Two donors (P 2) offer 0.2 each to the voxel between them (P 0), which has 0.2 of free capacity:
// it accepts half of every offer, so each donor sends 0.1. Water is conserved.
TEST(Stage2Steps, OverOfferedReceiverAcceptsTheSameFractionOfEveryOffer) {
    Row3 r({1.f, 0.3f, 1.f}, {0.5, 0.1, 0.5}, {2, 0, 2});
    computeOffers(r.dom, r.P, TransportWeight::kProportional, r.st);
    EXPECT_NEAR(r.offer(0, +1), 0.2, 1e-7);
    EXPECT_NEAR(r.offer(2, -1), 0.2, 1e-7);
    r.accept();
    EXPECT_NEAR(r.at(r.st.accept, 1), 0.5, 1e-6);
    r.move();
    EXPECT_NEAR(r.at(r.st.fc, 0), 0.1, 1e-7);
    EXPECT_NEAR(r.at(r.st.fc, 2), 0.1, 1e-7);
    EXPECT_NEAR(r.st.water[1], 0.3, 1e-7);  // full
    EXPECT_NEAR(r.st.water[0] + r.st.water[1] + r.st.water[2], 1.1, 1e-15);
}

// Proportional weights divide by the distance: from (0,0) at P 3 to its face neighbours at P 2 the
// weight is 1, to the diagonal one at P 1 it is 2/√2 = √2. With free capacity 0.5 each the shares
// total 0.5 > W = 0.1, so they are scaled by 0.2. Uniform weights give 0.5/3 · 0.2 each.
TEST(Stage2Steps, ProportionalWeightsDivideByDistance) {
    for (TransportWeight w : {TransportWeight::kProportional, TransportWeight::kUniform}) {
        Domain d = emptyDomain(Dims{2, 2, 1}, 1.0, 0.5f);
        Stage2State st(d.dims);
        Grid3<double> P(d.dims, 0.0);
        P.at(0, 0, 0) = 3;
        P.at(1, 0, 0) = 2;
        P.at(0, 1, 0) = 2;
        P.at(1, 1, 0) = 1;
        st.water[d.dims.index(0, 0, 0)] = 0.1;
        activateAll(st);
        computeOffers(d, P, w, st);
        const std::size_t v = d.dims.index(0, 0, 0);
        const double norm = 2 + std::sqrt(2.0);
        const double face = w == TransportWeight::kProportional ? 0.1 / norm : 0.1 / 3;
        const double diag = w == TransportWeight::kProportional ? 0.1 * std::sqrt(2.0) / norm : 0.1 / 3;
        EXPECT_NEAR(offerOf(d, P, w, st, v, slotOf(1, 0, 0)), face, 1e-15);
        EXPECT_NEAR(offerOf(d, P, w, st, v, slotOf(0, 1, 0)), face, 1e-15);
        EXPECT_NEAR(offerOf(d, P, w, st, v, slotOf(1, 1, 0)), diag, 1e-15);
    }
}

// A voxel an ulp over full (free capacity < 0) receives no offers: its acceptance is 1, not 0/0.
TEST(Stage2Steps, OverFullVoxelWithNothingIncomingAcceptsOne) {
    Row3 r({0.5f, 0.5f, 0.5f}, {0.0, 0.5000000000000001, 0.0}, {0, 0, 0});
    computeOffers(r.dom, r.P, TransportWeight::kProportional, r.st);
    r.accept();
    EXPECT_EQ(r.at(r.st.incoming, 1), 0.0);
    EXPECT_EQ(r.at(r.st.accept, 1), 1.0);
}

TEST(Stage2Steps, SinksDrainWhatTheyReceive) {
    Row3 r({0.5f, 1.f, 0.5f}, {0.3, 0.0, 0.0}, {1, 0, 2});
    r.dom.flags[1] |= kSink;
    computeOffers(r.dom, r.P, TransportWeight::kProportional, r.st);
    r.accept();
    const auto [moved, drained] = r.move();
    EXPECT_DOUBLE_EQ(moved, 0.3);
    EXPECT_DOUBLE_EQ(drained, 0.3);
    EXPECT_EQ(r.st.water[1], 0.0);
}

// Eq. 2 on a row with P = (2, 1, 0) and f_c = (0.4, 0.1, 0): "max" gives each voxel the largest f_c
// of its lower neighbours: f_a = (0.1, 0, 0). "split" gives the sum of the lower neighbours' f_c
// divided by their number of uphill neighbours: voxel 1 has one (voxel 0), so f_a(0) = 0.1 / 1.
TEST(Stage2Steps, BlendingFollowsEq2) {
    for (FlowBlending b : {FlowBlending::kMax, FlowBlending::kSplit}) {
        Row3 r({0.5f, 0.5f, 0.5f}, {0, 0, 0}, {2, 1, 0});
        r.st.ref(r.st.fc, 0) = 0.4;
        r.st.ref(r.st.fc, 1) = 0.1;
        blendFlow(r.dom, r.P, b, r.st);
        EXPECT_DOUBLE_EQ(r.at(r.st.fa, 0), 0.1);
        EXPECT_EQ(r.at(r.st.fa, 1), 0.0);
        EXPECT_EQ(r.at(r.st.fa, 2), 0.0);
    }
    // Two uphill neighbours share a voxel's f_c under "split": P = (1, 0, 1), f_c(1) = 0.6.
    Row3 r({0.5f, 0.5f, 0.5f}, {0, 0, 0}, {1, 0, 1});
    r.st.ref(r.st.fc, 1) = 0.6;
    blendFlow(r.dom, r.P, FlowBlending::kSplit, r.st);
    EXPECT_DOUBLE_EQ(r.at(r.st.fa, 0), 0.3);
    EXPECT_DOUBLE_EQ(r.at(r.st.fa, 2), 0.3);
    blendFlow(r.dom, r.P, FlowBlending::kMax, r.st);
    EXPECT_DOUBLE_EQ(r.at(r.st.fa, 0), 0.6);
}

// Eq. 1: f = wa · f_a + f_c = 0.25 · 0.1 + 0.4 = 0.425; ΔR = w0 · f^m = 0.15 · 0.425 (m = 1) on
// R = 0.05; capped at 1 − R; m = 2 squares f. Sources and sinks never erode. A voxel reaching the
// channel threshold becomes channel and takes the channel rate.
TEST(Stage2Steps, ErosionFollowsEq1) {
    Domain d = emptyDomain(Dims{4, 1, 1}, 1.0, 0.05f);
    d.porosity[1] = 0.99f;
    d.porosity[2] = 0.45f;
    d.flags[3] |= kSource;
    Stage2State st(d.dims);
    for (std::size_t v = 0; v < 4; ++v) {
        st.ref(st.fa, v) = 0.1;
        st.ref(st.fc, v) = 0.4;
    }
    Stage2Options g;  // w0 0.15, wa 0.25, m 1, threshold 0.5
    Grid3<float> rate = rateField(d, g);
    std::vector<std::size_t> fresh, conducting;
    const double eroded = erode(d, g, st, rate, fresh, conducting);
    EXPECT_FLOAT_EQ(d.porosity[0], float(0.05f + 0.15 * 0.425));
    EXPECT_FLOAT_EQ(d.porosity[1], 1.f);  // capped
    EXPECT_FLOAT_EQ(d.porosity[2], float(0.45f + 0.15 * 0.425));
    EXPECT_FLOAT_EQ(d.porosity[3], 0.05f);  // source
    EXPECT_FLOAT_EQ(d.flow[0], 0.425f);
    EXPECT_NEAR(eroded, 0.15 * 0.425 * 2 + (1.0 - double(0.99f)), 1e-6);
    // Voxels 1 and 2 crossed 0.5: channel, at the channel rate, listed once.
    EXPECT_TRUE(d.flags[1] & kChannel);
    EXPECT_TRUE(d.flags[2] & kChannel);
    EXPECT_FALSE(d.flags[0] & kChannel);
    EXPECT_EQ(fresh, (std::vector<std::size_t>{1, 2}));
    EXPECT_EQ(conducting, (std::vector<std::size_t>{1, 2}));
    EXPECT_EQ(st.channelVoxels, 2);
    EXPECT_EQ(rate[1], float(g.pRateChannel));

    Domain e = emptyDomain(Dims{1, 1, 1}, 1.0, 0.05f);
    g.m = 2.0;
    Grid3<float> rate2 = rateField(e, g);
    Stage2State s2(e.dims);
    s2.ref(s2.fa, 0) = 0.1;
    s2.ref(s2.fc, 0) = 0.4;
    fresh.clear();
    erode(e, g, s2, rate2, fresh, conducting);
    EXPECT_FLOAT_EQ(e.porosity[0], float(0.05f + 0.15 * 0.425 * 0.425));
}

// The porosity rate of a protochannel (docs/model.md, "Pressure rate"): s = ln(R / R0) / ln(T / R0)
// taken down to a multiple of 1/16, rate = pRate · (pRateChannel / pRate)^s. With R0 = 0.05 and
// T = 0.5, R = 0.25 gives s = ln 5 / ln 10 = 0.69897 → 11/16; R = 0.05 · 10^(8/16) = 0.158 gives
// exactly 8/16.
TEST(Stage2Steps, PorosityRateFollowsTheLogOfTheOpening) {
    Stage2Options g;                                  // pRate 0.5, pRateChannel 0.001, threshold 0.5
    EXPECT_EQ(porosityRate(0.05f, 0.05f, g), 0.5f);   // unopened: rock
    EXPECT_EQ(porosityRate(0.5f, 0.05f, g), 0.001f);  // at the threshold: channel
    EXPECT_EQ(porosityRate(0.9f, 0.05f, g), 0.001f);
    EXPECT_FLOAT_EQ(porosityRate(0.25f, 0.05f, g), float(0.5 * std::pow(0.002, 11.0 / 16)));
    EXPECT_FLOAT_EQ(porosityRate(0.1582f, 0.05f, g), float(0.5 * std::pow(0.002, 8.0 / 16)));
    EXPECT_EQ(porosityRate(0.04f, 0.05f, g), 0.5f);  // never above the rock rate
    // Initial porosity at or above the threshold: channel rate once opened at all.
    EXPECT_EQ(porosityRate(0.6f, 0.6f, g), 0.5f);
    EXPECT_EQ(porosityRate(0.61f, 0.6f, g), 0.001f);
    // Only ratios enter: both rates × 4 give 4 × the rate, bit for bit.
    Stage2Options g4 = g;
    g4.pRate *= 4;
    g4.pRateChannel *= 4;
    EXPECT_EQ(porosityRate(0.25f, 0.05f, g4), 4.f * porosityRate(0.25f, 0.05f, g));
    // rateField: a stage-1 protochannel follows its porosity, a [[rock.channel]] voxel is open.
    Domain d = emptyDomain(Dims{3, 1, 1}, 1.0, 0.05f);
    d.porosity[0] = d.porosity[1] = 0.25f;
    d.flags[0] |= kProtochannel;
    d.flags[1] |= kProtochannel | kFeatureChannel;
    const Grid3<float> rate = rateField(d, g);
    EXPECT_EQ(rate[0], porosityRate(0.25f, 0.05f, g));
    EXPECT_EQ(rate[1], 0.001f);
    EXPECT_EQ(rate[2], 0.5f);
    g.rateRule = RateRule::kChannelFlag;  // the paper's rule
    EXPECT_EQ(rateField(d, g)[0], 0.001f);
}

// Erosion lowers a protochannel's rate as it opens and lists it for the pressure decrease; a rock
// voxel eroded as much keeps the rock rate until it becomes channel.
TEST(Stage2Steps, ProtochannelRateFallsAsItOpens) {
    Domain d = emptyDomain(Dims{2, 1, 1}, 1.0, 0.05f);
    d.porosity[0] = 0.25f;
    d.flags[0] |= kProtochannel;
    d.porosity[1] = 0.25f;  // rock opened as far, by erosion
    Stage2State st(d.dims);
    for (std::size_t v = 0; v < 2; ++v) st.ref(st.fc, v) = 0.4;  // f = 0.4: R += 0.06
    Stage2Options g;
    Grid3<float> rate = rateField(d, g);
    const float before = rate[0];
    std::vector<std::size_t> fresh, conducting;
    erode(d, g, st, rate, fresh, conducting);
    EXPECT_FLOAT_EQ(d.porosity[0], 0.31f);
    EXPECT_EQ(rate[0], porosityRate(0.31f, 0.05f, g));
    EXPECT_LT(rate[0], before);
    EXPECT_EQ(rate[1], 0.5f);
    EXPECT_EQ(fresh, (std::vector<std::size_t>{0}));
    EXPECT_TRUE(conducting.empty());
}

// Head inflow: level = clamp(head − P(v) / cap, 0, 1).
TEST(Stage2Steps, HeadLevelsFollowTheField) {
    Domain d = emptyDomain(Dims{4, 1, 1}, 1.0, 0.1f);
    d.sourceVoxels = {{0}, {3}};
    d.sourcePressure = {1.0, 2.0};
    std::vector<Refill> levels = refillLevels(d);
    Grid3<double> P(d.dims, 0.0);
    P[0] = 10;  // head 0.5 of cap 40: 0.5 − 0.25
    P[3] = 50;  // above the cap: head 1 − 1.25 → 0
    headLevels(P, 40.0, levels);
    EXPECT_DOUBLE_EQ(levels[0].level, 0.25);
    EXPECT_DOUBLE_EQ(levels[1].level, 0.0);
    P[3] = 0;  // joined to a sink: the whole head
    headLevels(P, 40.0, levels);
    EXPECT_DOUBLE_EQ(levels[1].level, 1.0);
    Stage2State st(d.dims);
    std::vector<double> perSource(2, 0.0);
    const double injected = refillSources(d, levels, st, &perSource);
    EXPECT_NEAR(injected, 0.025 + 0.1, 1e-7);
    EXPECT_NEAR(perSource[0], 0.025, 1e-7);
    EXPECT_NEAR(perSource[1], 0.1, 1e-7);
}

// The avalanche: P(x) = min over neighbours P(y) + rate(x) · |x − y|. A row with a sink at 0 and
// rock rate 0.5 has P = (0, 0.5, 1); voxel 1 turning channel (rate 0.001) lowers it to
// (0, 0.001, 0.501), and both changed voxels are counted.
TEST(Stage2Steps, PressureUpdateIsTheAvalancheRule) {
    Domain d = emptyDomain(Dims{3, 1, 1}, 1.0, 0.05f);
    d.flags[0] |= kSink;
    d.sinkVoxels = {{0}};
    Stage2Options g;
    g.pRate = 0.5;
    g.pRateChannel = 0.001;
    Grid3<float> rate(d.dims, 0.5f);
    fastmarch::EikonalField P;
    P.solve(d.dims, rate, {{0, 0.0, 0}}, 100.0, fastmarch::Stencil::kAvalanche26);
    EXPECT_DOUBLE_EQ(P.value()[1], 0.5);
    EXPECT_DOUBLE_EQ(P.value()[2], 1.0);
    rate[1] = 0.001f;
    EXPECT_EQ(updatePressure(P, rate, {1}), 2u);
    EXPECT_NEAR(P.value()[1], 0.001, 1e-9);
    EXPECT_NEAR(P.value()[2], 0.501, 1e-9);
    EXPECT_EQ(updatePressure(P, rate, {}), 0u);
}

namespace {

/// waterAndChannels throws a RuntimeError whose message holds every one of `parts`.
void expectBookkeepingRefuses(const Domain& d, const Stage2State& st, const Grid3<double>& P, int iteration,
                              std::initializer_list<const char*> parts) {
    try {
        waterAndChannels(d, st, P, iteration);
        FAIL() << "no error";
    } catch (const RuntimeError& e) {
        const std::string m = e.what();
        for (const char* part : parts) EXPECT_NE(m.find(part), std::string::npos) << part << " in " << m;
    }
}

}  // namespace

TEST(Stage2Steps, BookkeepingCountsAndRefusesNonFiniteWater) {
    Domain d = emptyDomain(Dims{3, 1, 1}, 1.0, 0.05f);
    d.flags[1] |= kChannel;
    Stage2State st(d.dims);
    Stage2Options g;
    Grid3<float> rate = rateField(d, g);
    startStage2(d, g, st, rate);  // counts the channel voxel
    st.water = {0.1, 0.2, 0.3};
    activateWet(st);
    const Grid3<double> P(d.dims, 1.0);
    const auto [stored, channels] = waterAndChannels(d, st, P, 7);
    EXPECT_DOUBLE_EQ(stored, 0.1 + 0.2 + 0.3);
    EXPECT_EQ(channels, 1);
    st.water[2] = std::nan("");
    st.recountWater();  // a hand-set value: the steps keep the tiles' sums, a hand edit recounts them
    expectBookkeepingRefuses(d, st, P, 7, {"stage 2", "iteration 7", "water became non-finite", "(2, 0, 0)"});
    // Flow is checked where something worked this iteration (the work masks near a sender).
    st.water[2] = 0.3;
    st.recountWater();
    d.flow[0] = std::numeric_limits<float>::infinity();
    EXPECT_NO_THROW(waterAndChannels(d, st, P, 8));  // nothing worked: the flow is as it was
    st.ref(st.fc, 0) = 0;                            // the tile works (its whole mask)
    expectBookkeepingRefuses(d, st, P, 8, {"iteration 8", "flow became non-finite", "(0, 0, 0)"});
}

TEST(Stage2Steps, SourcesConnectThroughChannelVoxelsOnly) {
    Domain d = emptyDomain(Dims{5, 1, 1}, 1.0, 0.05f);
    d.flags[0] |= kSource;
    d.sourceVoxels = {{0}};
    d.flags[4] |= kSink;
    d.sinkVoxels = {{4}};
    d.flags[1] |= kChannel;
    d.flags[2] |= kChannel;
    EXPECT_EQ(connectedSources(d), std::vector<bool>{false});
    d.flags[3] |= kChannel;
    EXPECT_EQ(connectedSources(d), std::vector<bool>{true});
}

// The incremental search: voxels turning channel join the reached set only when they touch it,
// and a source is connected exactly when the full search says so.
TEST(Stage2Steps, IncrementalReachEqualsTheFullSearch) {
    Domain d = emptyDomain(Dims{6, 1, 1}, 1.0, 0.05f);
    d.flags[0] |= kSource;
    d.sourceVoxels = {{0}};
    d.flags[5] |= kSink;
    d.sinkVoxels = {{5}};
    Stage2State st(d.dims);
    reachFromSinks(d, st);
    EXPECT_EQ(extendReach(d, st, {}), std::vector<bool>{false});
    // Channels grow from the source side first: nothing new is reached.
    for (std::size_t v : {1u, 2u}) d.flags[v] |= kChannel;
    EXPECT_EQ(extendReach(d, st, {1, 2}), std::vector<bool>{false});
    EXPECT_FALSE(st.reached[2]);
    d.flags[4] |= kChannel;
    EXPECT_EQ(extendReach(d, st, {4}), std::vector<bool>{false});
    EXPECT_TRUE(st.reached[4]);
    // The last gap closes: the search from voxel 3 reaches the source through 2 and 1.
    d.flags[3] |= kChannel;
    EXPECT_EQ(extendReach(d, st, {3}), std::vector<bool>{true});
    EXPECT_EQ(connectedSources(d), std::vector<bool>{true});
    for (std::size_t v = 0; v < 6; ++v) EXPECT_TRUE(st.reached[v]) << v;
}

// ---- Water table and gravity (docs/model.md, "Water table and gravity") -------------------------

// A level table is the same height in every column; a table dipping 45° towards +x (dip direction
// 90°) falls one voxel per voxel of x, through `level` at the centre column x = 2.
TEST(Stage2Steps, WaterTableIsAPlaneThroughTheCentreColumn) {
    Hydrology h;
    const std::vector<double> level = waterTableColumns(Dims{5, 3, 4}, h, 2.5);
    ASSERT_EQ(level.size(), 15u);
    for (double z : level) EXPECT_EQ(z, 2.5);
    h.dip = 45;
    h.dipDirection = 90;
    const std::vector<double> dip = waterTableColumns(Dims{5, 1, 4}, h, 2.0);
    for (int i = 0; i < 5; ++i) EXPECT_NEAR(dip[std::size_t(i)], 2.0 - (i - 2), 1e-12);
    EXPECT_TRUE(isVadose(Dims{5, 1, 4}, dip, 4, 0, 1));   // table at 0 there
    EXPECT_FALSE(isVadose(Dims{5, 1, 4}, dip, 0, 0, 3));  // table at 4 there
}

// The potential: P below the table; above it cap + p_rate · (k − table) + lateral · P.
TEST(Stage2Steps, VadosePotentialIsHeightAboveTheTable) {
    const Dims d{1, 1, 4};
    Grid3<double> P(d, 0.0), phi(d, 0.0);
    for (int k = 0; k < 4; ++k) P[std::size_t(k)] = 0.1 * (k + 1);
    Stage2Options g;
    g.pRate = 0.5;
    g.hydrology.lateral = 0.1;
    Stage2State st(d);
    const std::vector<double> table = waterTableColumns(d, g.hydrology, 1.5);
    gravityPotential(P, table, 10.0, g, st, true, phi);
    EXPECT_EQ(phi[0], 0.1);
    EXPECT_EQ(phi[1], 0.2);
    EXPECT_NEAR(phi[2], 10.0 + 0.5 * 0.5 + 0.1 * 0.3, 1e-12);
    EXPECT_NEAR(phi[3], 10.0 + 0.5 * 1.5 + 0.1 * 0.4, 1e-12);
}

namespace {

/// A vertical 3 × 1 × 3 section (x, z), porosity 0.5, uniform pressure 0, table at z = 0: the two
/// upper rows are vadose. Water `w` in voxel (i, 0, k); one transport step on the gravity potential.
struct VadoseSection {
    Domain dom = emptyDomain(Dims{3, 1, 3}, 1.0, 0.5f);
    Stage2State st{dom.dims};
    Grid3<double> P{dom.dims, 0.0}, phi{dom.dims, 0.0};
    Stage2Options g;
    VadoseSection(int i, int k, double w) {
        g.pRate = 0.5;
        g.hydrology.lateral = 0.1;
        st.water[dom.dims.index(i, 0, k)] = w;
        activateAll(st);
        gravityPotential(P, waterTableColumns(dom.dims, g.hydrology, 0.0), 10.0, g, st, true, phi);
        computeOffers(dom, phi, TransportWeight::kProportional, st);
        computeAcceptance(dom, phi, TransportWeight::kProportional, st);
        moveWater(dom, phi, TransportWeight::kProportional, st);
    }
    double water(int i, int k) const { return st.water[dom.dims.index(i, 0, k)]; }
    double total() const {
        double s = 0;
        for (double x : st.water) s += x;
        return s;
    }
};

}  // namespace

// Water in the top middle voxel goes only down: straight down with weight 0.5 (Δφ = p_rate · 1,
// distance 1), down-diagonally with 0.5/√2 each; level neighbours (Δφ = 0) and nothing above get
// nothing. Shares total 0.5 > W = 0.3, so all 0.3 leaves: 0.3 · 0.5 / (0.5 + 2 · 0.5/√2) below.
TEST(Stage2Steps, VadoseWaterMovesDownNotUp) {
    const VadoseSection s(1, 2, 0.3);
    const double norm = 0.5 + 2 * 0.5 / std::sqrt(2.0);
    EXPECT_NEAR(s.water(1, 1), 0.3 * 0.5 / norm, 1e-12);
    EXPECT_NEAR(s.water(0, 1), 0.3 * (0.5 / std::sqrt(2.0)) / norm, 1e-12);
    EXPECT_NEAR(s.water(2, 1), s.water(0, 1), 1e-15);  // mirror symmetric
    EXPECT_NEAR(s.water(1, 2), 0.0, 1e-15);            // all of it left (to round-off)
    EXPECT_EQ(s.water(0, 2), 0.0);                     // no sideways flow on a level floor at uniform pressure
    EXPECT_EQ(s.water(2, 2), 0.0);
    EXPECT_EQ(s.water(1, 0), 0.0);       // one voxel per iteration
    EXPECT_NEAR(s.total(), 0.3, 1e-15);  // conserved
    // From the middle row the water goes down into the phreatic row, never up into the vadose one.
    const VadoseSection m(1, 1, 0.3);
    EXPECT_EQ(m.water(0, 2) + m.water(1, 2) + m.water(2, 2), 0.0);
    EXPECT_GT(m.water(1, 0), m.water(0, 0));
    EXPECT_NEAR(m.total(), 0.3, 1e-15);
    // Phreatic water (bottom row, uniform pressure) cannot rise into the vadose zone: it stays.
    const VadoseSection b(1, 0, 0.3);
    EXPECT_EQ(b.water(1, 0), 0.3);
    EXPECT_EQ(b.total(), 0.3);
}

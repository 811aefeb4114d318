// The parameter registry: every entry is documented, every numeric range is enforced by the parser,
// and every key survives the effective-scenario writer (each set to a value other than its default).
#include <cmath>
#include <cstdio>
#include <limits>

#include <gtest/gtest.h>

#include "core/error.h"
#include "sim/parameters.h"
#include "sim/scenario_io.h"

using namespace cavesim;

namespace {

/// A valid value of `p` other than `d` (its default), inside its range.
ParamValue otherValue(const Param& p, const ParamValue& d) {
    const ParamRange& r = p.range;
    switch (p.type) {
        case ParamType::kBool:
            return !std::get<bool>(d);
        case ParamType::kInt: {
            const std::int64_t v = std::get<std::int64_t>(d);
            return double(v + 1) <= r.hi ? v + 1 : v - 1;
        }
        case ParamType::kReal: {
            const double v = std::get<double>(d);
            return v < r.hi ? v + (r.hi - v) / 4 : v - (v - r.lo) / 2;
        }
        case ParamType::kString:
            return std::get<std::string>(d) + "_x";
        case ParamType::kChoice:
            for (const auto& c : p.choices)
                if (std::get<std::string>(d) != c.name) return std::string(c.name);
            break;
        case ParamType::kInt3: {
            auto v = std::get<std::vector<std::int64_t>>(d);
            for (auto& x : v) x = double(x + 1) <= r.hi ? x + 1 : x - 1;
            return v;
        }
        case ParamType::kReal3: {
            auto v = std::get<std::vector<double>>(d);
            for (auto& x : v) x += 1.5;
            return v;
        }
        case ParamType::kReal3List:
            return std::vector<Vec3d>{{1, 2, 3}, {4.5, 5, 6}};
        case ParamType::kChoiceList:
            return std::vector<std::string>{p.choices.back().name};
        case ParamType::kIntList:
            return std::vector<std::int64_t>{7, 3};
        case ParamType::kVoxel:
            return std::vector<std::int64_t>{10, 10, 10};
        case ParamType::kVoxelBox:
            return std::vector<std::int64_t>{0, 0, 0, 1, 2, 3};
        case ParamType::kPath:
            return std::get<std::string>(d) + "site/" + p.key + ".tif";
    }
    ADD_FAILURE() << "no other value for " << p.key;
    return d;
}

const char* kTerminals = "[[source]]\nat = [30, 30, 19]\n[[sink]]\nat = [30, 30, 0]\n";

std::string number(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

}  // namespace

TEST(Parameters, EveryEntryIsDocumented) {
    std::size_t keys = 0;
    for (const ParamSection& s : scenarioParameters()) {
        for (const Param& p : s.params) {
            ++keys;
            SCOPED_TRACE(s.qualified(p.key));
            EXPECT_FALSE(p.key.empty());
            EXPECT_FALSE(p.description.empty());
            EXPECT_FALSE(p.unit.empty());  // "–" when dimensionless
            EXPECT_FALSE(paramRangeText(p).empty());
            EXPECT_TRUE(bool(p.get) && bool(p.set) && bool(p.address));
            if (p.type == ParamType::kChoice || p.type == ParamType::kChoiceList) { EXPECT_GE(p.choices.size(), 2u); }
            if (p.type == ParamType::kInt || p.type == ParamType::kReal) { EXPECT_LE(p.range.lo, p.range.hi); }
            const std::string reference = scenarioReferenceMarkdown();
            EXPECT_NE(reference.find("| `" + p.key + "` |"), std::string::npos);
        }
    }
    EXPECT_EQ(keys, 123u);  // a new key: add its entry, then update this count
}

TEST(Parameters, EveryKeyRoundTripsWithANonDefaultValue) {
    Scenario s;
    bool box = true;  // terminals: the first section's entry as a box, the next as one voxel
    for (const ParamSection& sec : scenarioParameters()) {
        void* rec = sec.isArray ? sec.append(s) : sec.mutableRecord(s, 0);
        const bool isTerminal = std::any_of(sec.params.begin(), sec.params.end(),
                                            [](const Param& p) { return p.type == ParamType::kVoxel; });
        for (const Param& p : sec.params) {
            SCOPED_TRACE(sec.qualified(p.key));
            if ((p.type == ParamType::kVoxel && box) || (p.type == ParamType::kVoxelBox && !box)) continue;
            const ParamValue d = p.get(sec.defaults());
            const ParamValue v = otherValue(p, d);
            EXPECT_NE(v, d);
            p.set(rec, v);
            EXPECT_EQ(p.get(rec), v);
        }
        if (isTerminal) box = !box;
    }
    // Keys that bound or exclude each other, back to a valid combination (each was set above).
    for (FractureFamily& f : s.fractureFamilies) {
        f.spacing = 0;
        f.density = 1e-3;
        f.minLength = 3;
        f.maxLength = 20;
    }
    for (RechargeSpec& r : s.recharge) {
        r.kind = RechargeKind::kStream;
        r.area.clear();
        const double top = s.size[2] - 1;
        r.points = {{1, 1, top}, {9, 9, top}};
    }
    s.site.dem.clear();  // [[recharge]] feeds the top face: not with a DEM
    // Water tables must lie in the block and phases name existing terminals (relations, not ranges).
    s.stage2.hydrology.waterTable = 3;
    s.stage2.hydrology.fromSite = false;  // a site's surface excludes a level
    s.stage2.enabled = true;              // [hydrology] and [[phase]] act on stage 2
    s.output.images = true;               // snapshots are pictures
    for (Stage2Phase& ph : s.stage2.phases) {
        ph.waterTable = 2;
        ph.iterations = 7;  // the snapshot lies within the run
        ph.sinks = {1};
        ph.sources = {1};
    }
    ASSERT_NO_THROW(validateScenario(s));
    const std::string text = scenarioToToml(s);
    Scenario back;
    ASSERT_NO_THROW(back = parseScenarioString(text, "roundtrip.toml")) << text;
    for (const ParamSection& sec : scenarioParameters()) {
        ASSERT_EQ(sec.count(back), sec.count(s)) << sec.path;
        for (std::size_t i = 0; i < sec.count(s); ++i)
            for (const Param& p : sec.params) {
                // A key that does not apply to its entry (a sinkhole's count on a stream) is not written.
                if (p.applies && !p.applies(sec.record(s, i))) continue;
                EXPECT_EQ(p.get(sec.record(back, i)), p.get(sec.record(s, i)))
                    << sec.qualified(p.key) << " = " << paramValueText(p.get(sec.record(s, i))) << " in\n"
                    << text;
            }
    }
    EXPECT_EQ(scenarioToToml(back), text);
}

TEST(Parameters, ValuesJustOutsideEachRangeAreRefused) {
    std::size_t checked = 0;
    for (const ParamSection& sec : scenarioParameters()) {
        for (const Param& p : sec.params) {
            const bool scalar = p.type == ParamType::kInt || p.type == ParamType::kReal;
            if (!(scalar || p.type == ParamType::kInt3 || p.type == ParamType::kIntList) || p.range.domainScaled)
                continue;
            const bool whole = p.type != ParamType::kReal;
            const double step = whole ? 1.0 : 1e-3 * std::max(1.0, std::fabs(p.range.lo));
            const double stepHi = whole ? 1.0 : 1e-3 * std::max(1.0, std::fabs(p.range.hi));
            std::vector<double> outside{p.range.loOpen ? p.range.lo : p.range.lo - step};
            if (p.range.hi < 9e18) outside.push_back(p.range.hiOpen ? p.range.hi : p.range.hi + stepHi);
            for (const double o : outside) {
                const std::string v = whole ? std::to_string(std::int64_t(o)) : number(o);
                const std::string value = p.type == ParamType::kInt3      ? "[" + v + ", 10, 10]"
                                          : p.type == ParamType::kIntList ? "[" + v + "]"
                                                                          : v;
                std::string text;
                if (sec.path.empty()) {
                    text = p.key + " = " + value + "\n" + kTerminals;
                } else {
                    text = std::string(kTerminals) + sec.header() + "\n";
                    for (const Param& q : sec.params)
                        if (!q.example.empty() && q.key != p.key) text += q.key + " = " + q.example + "\n";
                    text += p.key + " = " + value + "\n";
                }
                SCOPED_TRACE(text);
                try {
                    parseScenarioString(text, "range.toml");
                    ADD_FAILURE() << sec.qualified(p.key) << " = " << value << " was accepted";
                } catch (const InputError& e) {
                    EXPECT_NE(std::string(e.what()).find("key '" + sec.qualified(p.key) + "'"), std::string::npos)
                        << e.what();
                }
                ++checked;
            }
        }
    }
    EXPECT_GT(checked, 60u);
}

TEST(Parameters, ScenarioKeyNamesARegisteredField) {
    Scenario s;
    EXPECT_EQ(scenarioKey(s, &s.stage1.maxGraphVoxels), "stage1.max_graph_voxels");
    EXPECT_EQ(scenarioKey(s, &s.noise.scale), "rock.noise.scale");
    EXPECT_EQ(scenarioKey(s, &s.seed), "seed");
    EXPECT_THROW(scenarioKey(s, &s.path), RuntimeError);
}

TEST(Parameters, TheExampleScenarioParsesToTheDefaults) {
    const Scenario e = parseScenarioString(exampleScenarioToml(), "example.toml");
    const Scenario d;
    for (const ParamSection& sec : scenarioParameters()) {
        if (sec.isArray) continue;
        for (const Param& p : sec.params) EXPECT_EQ(p.get(sec.record(e, 0)), p.get(sec.record(d, 0))) << p.key;
    }
}

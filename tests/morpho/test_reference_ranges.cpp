// The reference tables: the values of the paper's Tables 2 and 3 and of Collon et al. 2017, their
// lookup and their JSON rows.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "morpho/reference_ranges.h"

namespace cavesim::morpho {
namespace {

TEST(ReferenceRanges, TablesHoldTheirRows) {
    EXPECT_EQ(kKlimchoukRanges.size(), 8u);
    EXPECT_EQ(kFrumkinRanges.size(), 6u);
    EXPECT_EQ(kCollonRanges.size(), 9u);
    std::set<std::string> seen;
    auto checkRow = [&](const ReferenceRange& r) {
        EXPECT_LT(r.low, r.high) << r.key;
        EXPECT_TRUE(seen.insert(std::string(r.key) + "/" + r.category + "/" + std::to_string(r.table)).second)
            << "duplicate " << r.key;
        EXPECT_GT(std::string(r.meaning).size(), 0u);
        EXPECT_GT(std::string(r.source).size(), 0u);
    };
    for (const auto& r : kKlimchoukRanges) {
        EXPECT_EQ(r.table, 2);
        checkRow(r);
    }
    for (const auto& r : kFrumkinRanges) {
        EXPECT_EQ(r.table, 3);
        checkRow(r);
    }
    for (const auto& r : kCollonRanges) {
        EXPECT_EQ(r.table, 0);
        EXPECT_EQ(std::string(r.category), "real caves");
        checkRow(r);
    }
}

TEST(ReferenceRanges, CategoryRangesAreTable2ThenTable3) {
    const auto& all = categoryRanges();
    ASSERT_EQ(all.size(), 14u);
    for (std::size_t n = 0; n < 8; ++n) EXPECT_STREQ(all[n].key, kKlimchoukRanges[n].key);
    for (std::size_t n = 0; n < 6; ++n) EXPECT_EQ(all[8 + n].low, kFrumkinRanges[n].low);
    EXPECT_EQ(&realCaveRanges(), &kCollonRanges);
}

TEST(ReferenceRanges, FindsPublishedValues) {
    const ReferenceRange* r = findReferenceRange("network_density_opt", "confined", 2);
    ASSERT_NE(r, nullptr);
    EXPECT_EQ(r->low, 0.049);
    EXPECT_EQ(r->high, 0.406);
    r = findReferenceRange("mean_width_m", "chamber", 3);
    ASSERT_NE(r, nullptr);
    EXPECT_EQ(r->low, 2.0);
    EXPECT_EQ(r->high, 100.0);
    r = findReferenceRange("h_or", "real caves", 0);
    ASSERT_NE(r, nullptr);
    EXPECT_EQ(r->low, 0.75);
    EXPECT_EQ(r->high, 1.00);
    EXPECT_EQ(findReferenceRange("porosity_pct_rect", "confined", 3), nullptr);  // Table 3 has no porosity
    EXPECT_EQ(findReferenceRange("h_or", "confined", 2), nullptr);
}

TEST(ReferenceRanges, JsonRows) {
    const nlohmann::json rows = referenceRangesJson();
    ASSERT_TRUE(rows.is_array());
    ASSERT_EQ(rows.size(), 23u);
    EXPECT_EQ(rows[0]["key"], "network_density_opt");
    EXPECT_EQ(rows[0]["category"], "unconfined");
    EXPECT_EQ(rows[0]["table"], 2);
    EXPECT_EQ(rows[0]["low"].get<double>(), 0.012);
    EXPECT_EQ(rows[0]["high"].get<double>(), 0.023);
    EXPECT_EQ(rows[0]["source"], "Klimchouk 2006");
    EXPECT_EQ(rows[8]["table"], 3);
    const nlohmann::json& last = rows[22];
    EXPECT_EQ(last["key"], "tortuosity");
    EXPECT_TRUE(last["table"].is_null());
    EXPECT_EQ(last["meaning"], "tortuosity");
    EXPECT_EQ(last["low"].get<double>(), 1.12);
    EXPECT_EQ(last["source"], "Collon et al. 2017");
    for (const auto& row : rows)
        for (const char* field : {"key", "meaning", "category", "table", "low", "high", "source"})
            EXPECT_TRUE(row.contains(field)) << row.dump();
}

}  // namespace
}  // namespace cavesim::morpho

/// @file reference_ranges.cpp
/// @brief The reference tables as lists and JSON rows.
#include "morpho/reference_ranges.h"

#include <cstring>

namespace cavesim::morpho {
namespace {

constexpr std::array<ReferenceRange, 14> joinCategoryTables() {
    std::array<ReferenceRange, 14> all{};
    std::size_t n = 0;
    for (const ReferenceRange& r : kKlimchoukRanges) all[n++] = r;
    for (const ReferenceRange& r : kFrumkinRanges) all[n++] = r;
    return all;
}

constexpr std::array<ReferenceRange, 14> kCategoryRanges = joinCategoryTables();

nlohmann::json row(const ReferenceRange& r) {
    return {{"key", r.key},           {"meaning", r.meaning},
            {"category", r.category}, {"table", r.table > 0 ? nlohmann::json(r.table) : nlohmann::json(nullptr)},
            {"low", r.low},           {"high", r.high},
            {"source", r.source}};
}

}  // namespace

const std::array<ReferenceRange, 14>& categoryRanges() {
    return kCategoryRanges;
}

const std::array<ReferenceRange, 9>& realCaveRanges() {
    return kCollonRanges;
}

const ReferenceRange* findReferenceRange(const char* key, const char* category, int table) {
    auto matches = [&](const ReferenceRange& r) {
        return r.table == table && std::strcmp(r.key, key) == 0 && std::strcmp(r.category, category) == 0;
    };
    for (const ReferenceRange& r : kCategoryRanges)
        if (matches(r)) return &r;
    for (const ReferenceRange& r : kCollonRanges)
        if (matches(r)) return &r;
    return nullptr;
}

nlohmann::json referenceRangesJson() {
    nlohmann::json rows = nlohmann::json::array();
    for (const ReferenceRange& r : kCategoryRanges) rows.push_back(row(r));
    for (const ReferenceRange& r : kCollonRanges) rows.push_back(row(r));
    return rows;
}

}  // namespace cavesim::morpho

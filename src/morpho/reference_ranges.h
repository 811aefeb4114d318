/// @file reference_ranges.h
/// @brief Published value ranges the simulated caves are compared with: the one copy in cavesim.
///
/// Three tables, each a documented constant:
///  - paper Table 2 (Klimchouk 2006): morphometric indices of unconfined and confined caves on the
///    optimised cave field (`kKlimchoukRanges`);
///  - paper Table 3 (Frumkin & Fischhendler 2005): indices of chamber and confined caves on the
///    rectangular cave field (`kFrumkinRanges`);
///  - Collon et al. 2017 (Geomorphology 283): network metrics over 34 surveyed caves
///    (`kCollonRanges`).
/// The morphometric indices are defined in morpho/morphometry.h (paper §4.2), the network metrics in
/// morpho/graph_metrics.h. `caveCategory` votes with the first two tables; the report and
/// `reproduce` print all three through `referenceRangesJson`.
#pragma once

#include <array>

#include <nlohmann/json.hpp>

namespace cavesim::morpho {

/// One published range of one measure.
struct ReferenceRange {
    const char* key;       ///< report.json name: a Morphometry member or a GraphMetrics key
    const char* meaning;   ///< what the measure is, with its unit
    const char* category;  ///< cave category the range describes: "unconfined", "confined", "chamber",
                           ///< or "real caves" (Collon et al.: all 34 caves together)
    int table;             ///< the paper's table that quotes it (2 or 3), 0 if the paper does not
    double low, high;      ///< inclusive bounds, in the measure's unit
    const char* source;    ///< the publication
};

/// Paper Table 2 (Klimchouk 2006), optimised cave field: 4 indices × unconfined / confined.
inline constexpr std::array<ReferenceRange, 8> kKlimchoukRanges{{
    {"network_density_opt", "network density (m/m²)", "unconfined", 2, 0.012, 0.023, "Klimchouk 2006"},
    {"areal_coverage_pct_opt", "areal coverage (%)", "unconfined", 2, 3.77, 8.55, "Klimchouk 2006"},
    {"porosity_pct_opt", "cave porosity (%)", "unconfined", 2, 0.15, 0.77, "Klimchouk 2006"},
    {"mean_width_m", "mean passage width W (m)", "unconfined", 2, 2.52, 4.56, "Klimchouk 2006"},
    {"network_density_opt", "network density (m/m²)", "confined", 2, 0.049, 0.406, "Klimchouk 2006"},
    {"areal_coverage_pct_opt", "areal coverage (%)", "confined", 2, 13.56, 58.51, "Klimchouk 2006"},
    {"porosity_pct_opt", "cave porosity (%)", "confined", 2, 1.1, 12.0, "Klimchouk 2006"},
    {"mean_width_m", "mean passage width W (m)", "confined", 2, 0.65, 4.53, "Klimchouk 2006"},
}};

/// Paper Table 3 (Frumkin & Fischhendler 2005), rectangular cave field: 3 indices × chamber /
/// confined (the table gives no porosity).
inline constexpr std::array<ReferenceRange, 6> kFrumkinRanges{{
    {"network_density_rect", "network density (m/m²)", "chamber", 3, 0.01, 0.25, "Frumkin & Fischhendler 2005"},
    {"areal_coverage_pct_rect", "areal coverage (%)", "chamber", 3, 20.0, 80.0, "Frumkin & Fischhendler 2005"},
    {"mean_width_m", "mean passage width W (m)", "chamber", 3, 2.0, 100.0, "Frumkin & Fischhendler 2005"},
    {"network_density_rect", "network density (m/m²)", "confined", 3, 0.07, 0.35, "Frumkin & Fischhendler 2005"},
    {"areal_coverage_pct_rect", "areal coverage (%)", "confined", 3, 10.0, 40.0, "Frumkin & Fischhendler 2005"},
    {"mean_width_m", "mean passage width W (m)", "confined", 3, 0.9, 8.0, "Frumkin & Fischhendler 2005"},
}};

/// Network metrics over 34 surveyed cave networks (Collon et al. 2017), in the order of the metric
/// keys of `toJson(const GraphMetrics&)`.
inline constexpr std::array<ReferenceRange, 9> kCollonRanges{{
    {"k_mean", "mean degree", "real caves", 0, 1.75, 2.57, "Collon et al. 2017"},
    {"r_k", "degree assortativity", "real caves", 0, -0.56, -0.15, "Collon et al. 2017"},
    {"spl", "mean shortest path (hops)", "real caves", 0, 2.32, 55.72, "Collon et al. 2017"},
    {"cpd", "central point dominance", "real caves", 0, 0.02, 0.57, "Collon et al. 2017"},
    {"h_or", "orientation entropy", "real caves", 0, 0.75, 1.00, "Collon et al. 2017"},
    {"len_mean_m", "mean branch length (m)", "real caves", 0, 8.46, 331.74, "Collon et al. 2017"},
    {"cv_len", "branch length variation", "real caves", 0, 0.90, 2.56, "Collon et al. 2017"},
    {"h_len", "length entropy", "real caves", 0, 0.07, 0.67, "Collon et al. 2017"},
    {"tortuosity", "tortuosity", "real caves", 0, 1.12, 1.54, "Collon et al. 2017"},
}};

/// The 14 category ranges of the paper's Tables 2 and 3, Table 2 first (what `caveCategory` votes with).
const std::array<ReferenceRange, 14>& categoryRanges();

/// The 9 real-cave ranges of Collon et al. 2017 (`kCollonRanges`).
const std::array<ReferenceRange, 9>& realCaveRanges();

/// The range of `key` for `category` in the paper's `table` (2 or 3; 0 for Collon et al. with
/// category "real caves"), or nullptr if there is none (e.g. porosity in Table 3).
const ReferenceRange* findReferenceRange(const char* key, const char* category, int table);

/// Every range as one JSON row each, Table 2, then Table 3, then Collon et al.:
/// {"key", "meaning", "category", "table" (null for Collon et al.), "low", "high", "source"}.
nlohmann::json referenceRangesJson();

}  // namespace cavesim::morpho

/// @file report.h
/// @brief report.json and report.md: what was simulated, what happened, and how the cave measures.
#pragma once

#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "sim/domain.h"
#include "sim/fractures.h"
#include "sim/scenario.h"
#include "sim/stage1.h"
#include "sim/stage2.h"

namespace cavesim::mesh {
struct MeshStats;
}
namespace cavesim::morpho {
struct CaveAnalysis;
}

namespace cavesim::app {

struct Timing {
    double stage1 = 0, stage2 = 0, mesh = 0, report = 0, exports = 0, total = 0;
};

/// What a run produced besides the grids.
struct RunRecord {
    int threads = 1;
    std::optional<Stage1Result> stage1;
    std::optional<Stage2Result> stage2;
    /// Sources joined to a sink through channel or protochannel voxels before stage 2's first
    /// iteration (sim/connectivity.h); empty when stage 2 did not run.
    std::optional<int> connectedAtStart;
    Timing timing;
    nlohmann::json mesh;                              ///< mesh statistics (null when no mesh was written)
    nlohmann::json analysis;                          ///< {network, morphometry, graph_metrics, skeleton, category}
    nlohmann::json speleothems;                       ///< app/speleo_report.h (null when [speleothems] is off)
    nlohmann::json files = nlohmann::json::object();  ///< fingerprints of written files, by name
    std::vector<std::string> exports;                 ///< the files of `[output] formats` written, in format order
    nlohmann::json json;                              ///< filled by writeReport: the report.json document
    /// The scenario's fracture discs, measured (measuredFractureNetwork); empty without fracture families.
    std::optional<FractureNetwork> fractures;
};

/// A report number: `v`, or null when it is not finite (JSON has no NaN or infinity).
nlohmann::json jsonNumber(double v);

nlohmann::json meshJson(const mesh::MeshStats& stats);
/// network, morphometry, graph_metrics, skeleton summary, cave category, pattern and
/// cross-sections of an analysis (the keys of `kAnalysisKeys`).
nlohmann::json analysisJson(const morpho::CaveAnalysis& analysis);

/// The report.json keys that come from the analysis of the cave.
inline constexpr const char* kAnalysisKeys[] = {"network",       "morphometry", "graph_metrics", "skeleton",
                                                "cave_category", "pattern",     "cross_sections"};

/// Puts the analysis document `analysis` (analysisJson, or null) into the report.json document
/// `report`: its `kAnalysisKeys` (null when absent) and, when `report` has a stage-2 object,
/// `stage2.near_protochannels`.
void putAnalysis(nlohmann::json& report, const nlohmann::json& analysis);

/// The scenario's fracture discs (generateFractureNetwork: deterministic) with their family
/// statistics measured (measureFractureNetwork): report.json `fracture_network` and images/fractures.png.
FractureNetwork measuredFractureNetwork(const Scenario& s);

/// The report.json document (its keys: README.md, "Commands" and the output table).
nlohmann::json buildReportJson(const Scenario& s, const Domain& dom, const RunRecord& rec);

/// The human report: parameters, timings, events, pictures, indices beside the paper's ranges.
/// `dir` is used only to see which pictures exist.
std::string buildReportMarkdown(const Scenario& s, const nlohmann::json& report, const std::string& dir);

/// Writes report.json and report.md into `dir` (each through a temporary name and a rename).
void writeReport(const Scenario& s, const Domain& dom, RunRecord& rec, const std::string& dir);

/// Writes the report files of `dir` from the report.json document `report`: report.json, report.md
/// (buildReportMarkdown) and report.html (app/report_html.h).
void writeReportFiles(const Scenario& s, const nlohmann::json& report, const std::string& dir);

/// One row of the morphometric indices table (paper Tables 2–4): its label and its key in
/// report.json `morphometry`, without the _opt / _rect suffix (W, "mean_width_m", has none).
struct IndexRow {
    const char* label;
    const char* key;
};
/// The rows, in the order of paperIndexText's rows: density, coverage, porosity, W.
inline constexpr IndexRow kIndexRows[] = {
    {"network density (m/m²)", "network_density"},
    {"areal coverage (%)", "areal_coverage_pct"},
    {"porosity (%)", "porosity_pct"},
    {"W (m)", "mean_width_m"},
};

/// The network metrics of Collon et al. 2017 (report.json `graph_metrics`), in the order the
/// reports list them.
inline constexpr const char* kNetworkMetricKeys[] = {"h_or", "len_mean_m", "cv_len", "h_len",     "k_mean",
                                                     "r_k",  "spl",        "cpd",    "tortuosity"};

/// The paper's own measurements of one of its caves: Table 4 (optimised field first, rectangular
/// field second) and Table 5 (run times on its 2.5 GHz single-threaded machine).
struct PaperCave {
    const char* name;  ///< our scenario name: "fig10", "fig11", "fig12"
    double density[2], coverage[2], porosity[2], width;
    const char* stage1Time;
    const char* stage2Time;
};
/// The paper's values for a scenario of that name, or nullptr.
const PaperCave* paperCave(const std::string& scenarioName);
/// One Table 4 cell as the paper prints it: row 0 density, 1 coverage, 2 porosity as
/// "optimised (rectangular)", row 3 W.
std::string paperIndexText(const PaperCave& paper, int row);

/// A report value as text: integers as they are, reals to `digits` significant digits, null "–".
std::string formatValue(const nlohmann::json& v, int digits = 3);

/// The value at `path` in the document `j`, one key per level of nested objects (e.g.
/// {"pattern", "criteria", "loops"}), or null when a key is missing or a level is not an object.
const nlohmann::json& reportValue(const nlohmann::json& j, std::initializer_list<const char*> path);

}  // namespace cavesim::app

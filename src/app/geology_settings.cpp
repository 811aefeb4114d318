// The generated page of the shipped geological settings (`cavesim reproduce geology`).
#include "app/geology_settings.h"

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <utility>

#include "app/report.h"
#include "morpho/reference_ranges.h"

namespace cavesim::app {
namespace {

std::string fmt(const nlohmann::json& v, int digits = 3) {
    return formatValue(v, digits);
}

/// A length in metres without a fractional part, e.g. "1234".
std::string metres(const nlohmann::json& v) {
    if (!v.is_number()) return "–";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.0f", v.get<double>());
    return buf;
}

/// The karstnet metrics inside the real caves' range: "in/with range", and the ones outside
/// (key, value, range), or "too small" when the network has too few branches to be compared.
struct KarstnetCount {
    int in = 0, compared = 0;
    bool tooSmall = false;
    std::vector<std::string> out;
};

KarstnetCount karstnetCount(const nlohmann::json& report) {
    KarstnetCount c;
    const nlohmann::json& gm = reportValue(report, {"graph_metrics"});
    if (!gm.is_object()) return c;
    c.tooSmall = reportValue(gm, {"too_small"}).is_boolean() && reportValue(gm, {"too_small"}).get<bool>();
    for (const char* key : kNetworkMetricKeys) {
        const morpho::ReferenceRange* r = morpho::findReferenceRange(key, "real caves", 0);
        const nlohmann::json& v = reportValue(gm, {key});
        if (!r || !v.is_number()) continue;
        ++c.compared;
        const double x = v.get<double>();
        if (x >= r->low && x <= r->high) {
            ++c.in;
        } else {
            char buf[128];
            std::snprintf(buf, sizeof buf, "`%s` %s (%g – %g)", key, fmt(v).c_str(), r->low, r->high);
            c.out.push_back(buf);
        }
    }
    return c;
}

std::string karstnetCell(const KarstnetCount& c) {
    if (c.tooSmall) return "too small";
    if (c.compared == 0) return "–";
    return std::to_string(c.in) + "/" + std::to_string(c.compared);
}

/// Breakthrough iterations: one, or one per base-level phase ("150 / – / 684").
std::string breakthroughCell(const nlohmann::json& report) {
    const nlohmann::json& phases = reportValue(report, {"stage2", "phases"});
    if (!phases.is_array() || phases.empty()) return fmt(reportValue(report, {"stage2", "breakthrough_iteration"}));
    std::string out;
    for (const nlohmann::json& p : phases)
        out += (out.empty() ? "" : " / ") + fmt(reportValue(p, {"breakthrough_iteration"}));
    return out;
}

}  // namespace

const std::vector<GeologySetting>& geologySettings() {
    static const std::vector<GeologySetting> settings = {
        {"branchwork", "plan.png", "plan"},
        {"network_maze", "plan.png", "plan"},
        {"anastomotic", "plan.png", "plan"},
        {"multilevel", "side_xz.png", "side view x–z"},
    };
    return settings;
}

std::string geologyPictureName(const std::string& scenario) {
    return "geology_" + scenario + ".png";
}

int passageLevels(const nlohmann::json& crossSections) {
    const nlohmann::json& passages = reportValue(crossSections, {"passages"});
    if (!passages.is_array()) return 0;
    std::vector<std::pair<double, double>> extents;  // [bottom, top] in metres
    for (const nlohmann::json& p : passages) {
        const nlohmann::json& cls = reportValue(p, {"class"});
        if (!cls.is_string() || (cls != "tube" && cls != "keyhole")) continue;
        const nlohmann::json &lo = reportValue(p, {"z_min_m"}), &hi = reportValue(p, {"z_max_m"}),
                             &h = reportValue(p, {"height_m"});
        if (!lo.is_number() || !hi.is_number()) continue;
        // A level is made of sub-horizontal passages: one whose centreline climbs more than its own
        // height (a ramp or a round shaft between two levels) joins levels, it does not form one.
        if (h.is_number() && hi.get<double>() - lo.get<double>() > h.get<double>()) continue;
        // A tube spans its height; a keyhole's height is mostly the canyon cut into it, so it counts at
        // its centreline's elevations only.
        const double half = h.is_number() && cls == "tube" ? h.get<double>() / 2 : 0.0;
        extents.push_back({lo.get<double>() - half, hi.get<double>() + half});
    }
    std::sort(extents.begin(), extents.end());
    int levels = 0;
    double top = 0;
    for (const auto& [bottom, t] : extents) {
        if (levels == 0 || bottom > top) {
            ++levels;
            top = t;
        } else {
            top = std::max(top, t);
        }
    }
    return levels;
}

std::string geologySettingsMarkdown(const std::vector<GeologyRun>& runs, int threads) {
    std::ostringstream md;
    // Each run's karstnet comparison and level count, worked out once for the table and its section.
    std::vector<KarstnetCount> karstnet;
    std::vector<int> levels;
    int compared = 0;
    for (const GeologyRun& run : runs) {
        karstnet.push_back(karstnetCount(run.report));
        levels.push_back(passageLevels(reportValue(run.report, {"cross_sections"})));
        compared = std::max(compared, karstnet.back().compared);
    }
    md << "# The shipped geological settings, measured\n\n"
          "Generated by `cavesim reproduce geology` ("
       << threads << " thread(s)); do not edit, rerun the command. Each setting of `scenarios/` ran with seed "
       << kGeologySeed
       << " (`--seed`); every number below is read from its run's `report.json`, and each picture is a copy of "
          "one of its run's pictures (`images/plan.png`; `images/side_xz.png` where the levels lie one above the "
          "other). The geological story of each setting, the rules of the "
          "pattern classes and the results over seeds 1–3: [geology.md](geology.md#shipped-settings).\n\n"
          "| setting | pattern | passage length (m) | branches | loops | karstnet in range | levels | "
          "breakthrough | run time (s) |\n|---|---|---|---|---|---|---|---|---|\n";
    for (std::size_t i = 0; i < runs.size(); ++i) {
        const GeologyRun& run = runs[i];
        const nlohmann::json& r = run.report;
        md << "| [" << run.scenario << "](#" << run.scenario << ") | " << fmt(reportValue(r, {"pattern", "class"}))
           << " | " << metres(reportValue(r, {"morphometry", "length_m"})) << " | "
           << fmt(reportValue(r, {"pattern", "criteria", "branches"})) << " | "
           << fmt(reportValue(r, {"pattern", "criteria", "loops"})) << " | " << karstnetCell(karstnet[i]) << " | "
           << levels[i] << " | " << breakthroughCell(r) << " | " << fmt(reportValue(r, {"timing_s", "total"}), 2)
           << " |\n";
    }
    md << "\n**Pattern**: report.json `pattern.class` (Palmer 1991). **Passage length**: the skeleton's length "
          "(`morphometry.length_m`). **Branches**, **loops**: the classification's counts (`pattern.criteria`). "
          "**Karstnet in range**: of the "
       << compared
       << " network metrics of Collon et al. 2017 (`graph_metrics`), those inside the range of the 34 real "
          "caves. **Levels**: groups of sub-horizontal tube and keyhole passages (`cross_sections`; centreline "
          "elevation range at most the passage height) whose vertical extents (that range, ± half the height "
          "for a tube) overlap; canyons, shafts and ramps between levels do not count. **Breakthrough**: stage-2 "
          "iteration, one per base-level phase. **Run time**: "
          "`timing_s.total`, wall time on this machine.\n";
    for (std::size_t i = 0; i < runs.size(); ++i) {
        const GeologyRun& run = runs[i];
        const nlohmann::json& r = run.report;
        md << "\n## " << run.scenario << "\n\n`scenarios/" << run.scenario << ".toml`, seed " << kGeologySeed;
        const nlohmann::json& grid = reportValue(r, {"grid"});
        const nlohmann::json& h = reportValue(r, {"voxel_size_m"});
        if (grid.is_array() && grid.size() == 3 && h.is_number()) {
            md << ": " << fmt(grid[0]) << " × " << fmt(grid[1]) << " × " << fmt(grid[2]) << " voxels of " << fmt(h)
               << " m";
            if (grid[0].is_number() && grid[1].is_number() && grid[2].is_number())
                md << " (" << fmt(grid[0].get<double>() * h.get<double>()) << " × "
                   << fmt(grid[1].get<double>() * h.get<double>()) << " × "
                   << fmt(grid[2].get<double>() * h.get<double>()) << " m)";
        }
        md << ", " << fmt(reportValue(r, {"stage2", "iterations"})) << " stage-2 iterations.\n\n";
        md << "- Pattern: **" << fmt(reportValue(r, {"pattern", "class"})) << "** ("
           << fmt(reportValue(r, {"pattern", "rule"})) << "); "
           << fmt(reportValue(r, {"pattern", "criteria", "branches"})) << " branches, "
           << fmt(reportValue(r, {"pattern", "criteria", "loops"})) << " loops ("
           << fmt(reportValue(r, {"pattern", "criteria", "loops_per_branch"}))
           << " per branch), share of length in one bed " << fmt(reportValue(r, {"pattern", "criteria", "bed_share"}));
        const nlohmann::json& family = reportValue(r, {"pattern", "criteria", "family_share"});
        if (!family.is_null()) md << ", along the fracture families " << fmt(family);
        md << ".\n";
        md << "- Passage length " << metres(reportValue(r, {"morphometry", "length_m"})) << " m, vertical range "
           << fmt(reportValue(r, {"morphometry", "vertical_range_m"})) << " m.\n";
        const KarstnetCount& k = karstnet[i];
        md << "- Karstnet metrics in the real caves' range: " << karstnetCell(k);
        if (!k.tooSmall && !k.out.empty()) {
            md << "; out: ";
            for (std::size_t j = 0; j < k.out.size(); ++j) md << (j ? ", " : "") << k.out[j];
        }
        md << ".\n";
        const nlohmann::json& summary = reportValue(r, {"cross_sections", "summary"});
        if (summary.is_array()) {
            md << "- Cross-sections (passages, elevation of their centrelines):";
            bool first = true;
            for (const nlohmann::json& c : summary) {
                const nlohmann::json& n = reportValue(c, {"passages"});
                if (!n.is_number() || n.get<double>() <= 0 || reportValue(c, {"class"}) == "short") continue;
                md << (first ? " " : "; ") << fmt(reportValue(c, {"class"})) << " " << fmt(n) << ", z "
                   << metres(reportValue(c, {"z_min_m"})) << "–" << metres(reportValue(c, {"z_max_m"})) << " m (mean "
                   << metres(reportValue(c, {"z_mean_m"})) << ")";
                first = false;
            }
            md << (first ? " none" : "") << "; " << levels[i] << " level(s) of tubes and keyholes.\n";
        }
        const nlohmann::json& phases = reportValue(r, {"stage2", "phases"});
        if (phases.is_array() && !phases.empty()) {
            md << "- Base-level phases:";
            int phase = 0;
            for (const nlohmann::json& p : phases) {
                const nlohmann::json &first = reportValue(p, {"first_iteration"}), &n = reportValue(p, {"iterations"});
                md << (phase > 0 ? ";" : "") << " " << phase + 1 << ") iterations " << fmt(first);
                ++phase;
                if (first.is_number_integer() && n.is_number_integer())
                    md << "–" << first.get<long long>() + n.get<long long>() - 1;
                md << ", water table at z = " << fmt(reportValue(p, {"water_table"})) << " voxels, breakthrough "
                   << fmt(reportValue(p, {"breakthrough_iteration"}));
            }
            md << ".\n";
        } else {
            md << "- Breakthrough at iteration " << breakthroughCell(r) << ".\n";
        }
        md << "- Run time " << fmt(reportValue(r, {"timing_s", "total"}), 2) << " s.\n\n";
        md << "![" << run.scenario << ", seed " << kGeologySeed << ", " << run.view << "](images/"
           << geologyPictureName(run.scenario) << ")\n";
    }
    return md.str();
}

}  // namespace cavesim::app

#include "app/report_pattern.h"

#include <sstream>

#include "app/report.h"

namespace cavesim::app {

namespace {

const nlohmann::json& field(const nlohmann::json& j, const char* key) {
    static const nlohmann::json null;
    return j.is_object() && j.contains(key) ? j.at(key) : null;
}

}  // namespace

std::string patternMarkdown(const nlohmann::json& r) {
    const nlohmann::json& p = field(r, "pattern");
    if (!p.is_object()) return {};
    std::ostringstream md;
    md << "\n## Cave pattern (Palmer 1991)\n\n**" << formatValue(field(p, "class"))
       << "**: " << formatValue(field(p, "rule"))
       << ". Rules and thresholds: docs/geology.md, \"Which pattern did I get?\".\n\n";
    const nlohmann::json& c = field(p, "criteria");
    if (!c.is_object()) return md.str();
    md << "| criterion | value |\n|---|---|\n";
    const std::pair<const char*, const char*> rows[] = {
        {"branches", "branches (chamber stubs aside)"},
        {"chamber_branches", "chamber stubs merged into their junction"},
        {"loops", "independent loops"},
        {"loops_per_km", "loops per km"},
        {"loops_per_branch", "loops per branch"},
        {"junctions", "junctions (degree ≥ 3)"},
        {"junction_degree_mean", "mean junction degree"},
        {"dead_end_share", "share of branches with a blind end"},
        {"orientation_entropy", "orientation entropy h_or"},
        {"orthogonal_share", "orthogonal share (two perpendicular directions ± 10°)"},
        {"orthogonal_azimuth_deg", "azimuth of the orthogonal pair (°)"},
        {"family_share", "share along the fracture families"},
        {"slab_thickness_m", "bed slab thickness (m)"},
        {"bed_share", "share of length in one bed slab"},
        {"vertical_spread_m", "vertical spread (m)"},
        {"plan_coverage", "plan coverage (plan area / hull area)"},
        {"width_cv", "width variation (CV of branch radii)"},
    };
    for (const auto& [key, label] : rows) md << "| " << label << " | " << formatValue(field(c, key)) << " |\n";
    return md.str();
}

std::string crossSectionsMarkdown(const nlohmann::json& r) {
    const nlohmann::json& x = field(r, "cross_sections");
    if (!x.is_object()) return {};
    std::ostringstream md;
    md << "\n## Cross-sections\n\nWidth and height of each passage across its centreline, at "
       << formatValue(field(x, "stations"))
       << " stations; a passage's class is the majority of its stations (docs/geology.md, \"Cross-sections\"). "
          "Elevations z in metres above the block's floor.\n\n"
          "| class | passages | length (m) | mean width (m) | mean height (m) | mean w/h | z mean (m) | z range (m) |\n"
          "|---|---|---|---|---|---|---|---|\n";
    for (const nlohmann::json& s : field(x, "summary")) {
        md << "| " << formatValue(field(s, "class")) << " | " << formatValue(field(s, "passages")) << " | "
           << formatValue(field(s, "length_m")) << " | " << formatValue(field(s, "mean_width_m")) << " | "
           << formatValue(field(s, "mean_height_m")) << " | " << formatValue(field(s, "mean_w_over_h")) << " | "
           << formatValue(field(s, "z_mean_m")) << " | "
           << (field(s, "z_min_m").is_null()
                   ? std::string("–")
                   : formatValue(field(s, "z_min_m")) + " – " + formatValue(field(s, "z_max_m")))
           << " |\n";
    }
    const nlohmann::json& passages = field(x, "passages");
    if (passages.is_array() && !passages.empty()) {
        md << "\n| passage | class | length (m) | width (m) | height (m) | w/h | z (m) "
              "|\n|---|---|---|---|---|---|---|\n";
        int shown = 0;
        for (const nlohmann::json& p : passages) {
            if (shown++ == kSectionRowsShown) break;
            md << "| p" << formatValue(field(p, "id")) << " | " << formatValue(field(p, "class")) << " | "
               << formatValue(field(p, "length_m")) << " | " << formatValue(field(p, "width_m")) << " | "
               << formatValue(field(p, "height_m")) << " | " << formatValue(field(p, "w_over_h")) << " | "
               << formatValue(field(p, "z_m")) << " |\n";
        }
        if (int(passages.size()) > kSectionRowsShown)
            md << "\n" << kSectionRowsShown << " of " << passages.size() << " passages shown; all in `report.json`.\n";
    }
    return md.str();
}

}  // namespace cavesim::app

#include "app/report_section.h"

#include <sstream>

#include "app/cave_maps.h"
#include "app/report.h"

namespace cavesim::app {

bool isSectionScenario(const Scenario& s) {
    return isSection(Dims{s.size[0], s.size[1], s.size[2]});
}

std::string sectionMeasuresMarkdown(const Scenario& s, const nlohmann::json& r) {
    std::ostringstream md;
    if (!r.contains("morphometry") || !r["morphometry"].is_object()) return {};
    const nlohmann::json& mo = r["morphometry"];
    const double h = s.voxelSize;
    const double sectionArea = s.size[0] * h * s.size[2] * h;
    const double length = mo.value("length_m", 0.0);
    const double caveArea = mo.value("volume_m3", 0.0) / (s.size[1] * h);  // the slab is one voxel thick
    auto v = [](double x) { return formatValue(nlohmann::json(x), 4); };
    md << "## Section measures\n\n"
          "A 2D section has no plan: the paper's plan indices (§4.2, Tables 2–4: network density, areal "
          "coverage and porosity of the cave field, W) describe the plan of a 3D cave and are not shown. "
          "Measured in the section plane (x–z):\n\n"
          "| measure | value |\n|---|---|\n";
    md << "| cave length (m) | " << v(length) << " |\n";
    md << "| cave area in the section (m²) | " << v(caveArea) << " |\n";
    md << "| section area (m²) | " << v(sectionArea) << " |\n";
    md << "| cave share of the section (%) | " << v(sectionArea > 0 ? 100.0 * caveArea / sectionArea : 0.0) << " |\n";
    md << "| mean passage width in the section, area / length (m) | "
       << (length > 0 ? v(caveArea / length) : std::string("–")) << " |\n";
    md << "| vertical range (m) | " << formatValue(mo.value("vertical_range_m", nlohmann::json(nullptr))) << " |\n";
    return md.str();
}

}  // namespace cavesim::app

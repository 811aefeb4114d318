#include "app/speleo_report.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

namespace cavesim::app {
namespace {

std::string fmt(double v, int digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}

}  // namespace

nlohmann::json speleothemsJson(const speleo::DecorationSummary& s) {
    nlohmann::json j;
    // A speleothem is grown material: at least one level-set voxel from the original ceiling
    // straight above its tip down to the tip. Convex patches that did not grow (bulges of the
    // cave's own ceiling) are only counted.
    std::vector<const speleo::Stalactite*> grown;
    for (const auto& st : s.stalactites)
        if (st.grownLength >= s.voxelSize && st.grownLength > 0) grown.push_back(&st);
    long stalagmites = 0;
    double longest = 0, total = 0;
    for (const auto* st : grown) {
        stalagmites += st->dripsOnFloor ? 1 : 0;
        longest = std::max(longest, st->grownLength);
        total += st->grownLength;
    }
    j["stalactites"] = long(grown.size());
    j["convex_patches"] = long(s.stalactites.size());
    j["drip_points_on_floor"] = stalagmites;
    j["longest_m"] = longest;
    j["mean_length_m"] = grown.empty() ? 0.0 : total / double(grown.size());
    // The years decorated; null when there was nothing to decorate, `note` says why (and why
    // nothing grew, when nothing did).
    j["years"] = s.emptyCave ? nlohmann::json(nullptr) : nlohmann::json(s.years);
    if (!s.note.empty()) j["note"] = s.note;
    j["mesh_files"] = s.meshFiles;
    j["steps"] = s.steps;
    j["max_speed_mm_per_yr"] = s.maxSpeed * 1000.0;
    j["voxel_size_m"] = s.voxelSize;
    j["level_set_voxels"] = s.levelSetVoxels;
    j["mesh"] = {{"vertices", s.mesh.vertices},
                 {"faces", s.mesh.faces},
                 {"closed", s.mesh.closed},
                 {"manifold", s.mesh.manifold},
                 {"components", s.mesh.components}};
    j["seconds"] = {{"growth", s.secondsGrowth}, {"output", s.secondsOutput}};
    nlohmann::json table = nlohmann::json::array();
    // Longest first (decorateCave orders them by grown length).
    for (std::size_t i = 0; i < grown.size() && i < 20; ++i) {
        const auto& st = *grown[i];
        table.push_back({{"tip_m", {st.tip[0], st.tip[1], st.tip[2]}},
                         {"length_m", st.grownLength},
                         {"radius_m", st.radius},
                         {"tip_speed_mm_per_yr", st.tipSpeed * 1000.0},
                         {"drip_factor", st.dripFactor},
                         {"drips_on_floor", st.dripsOnFloor}});
    }
    j["largest"] = table;
    j["pictures"] = s.pictures;
    return j;
}

void writeSpeleothemsMarkdown(std::ostringstream& md, const nlohmann::json& report) {
    if (!report.contains("speleothems") || report["speleothems"].is_null()) return;
    const nlohmann::json& j = report["speleothems"];
    md << "\n## Speleothems\n\n"
       << j["stalactites"].get<long>() << " stalactite(s) (grown material at least one voxel long, of "
       << j.value("convex_patches", j["stalactites"].get<long>()) << " convex ceiling patches) after "
       << (j["years"].is_number() ? fmt(j["years"].get<double>(), 0) : std::string("no")) << " years ("
       << j["steps"].get<int>() << " steps on a " << fmt(j["voxel_size_m"].get<double>() * 100, 1) << " cm level set), "
       << j["drip_points_on_floor"].get<long>() << " dripping onto the floor (stalagmites); longest "
       << fmt(j["longest_m"].get<double>() * 100, 1) << " cm. ";
    if (j.contains("note")) md << "Note: " << j["note"].get<std::string>() << ". ";
    // Reports written before `mesh_files` always had the three meshes.
    const bool meshes = !j.contains("mesh_files") || !j["mesh_files"].empty();
    md << (meshes ? "Mesh `cave_decorated.obj` / `.ply` / `.glb`: " : "Mesh not written (mesh output is off): ")
       << j["mesh"]["faces"].get<long>() << " faces, closed " << (j["mesh"]["closed"].get<bool>() ? "yes" : "no")
       << ", manifold " << (j["mesh"]["manifold"].get<bool>() ? "yes" : "no")
       << ". Law and limits: docs/speleothems.md.\n\n";
    if (!j["largest"].empty()) {
        md << "Length: from the original ceiling straight above the tip down to the tip (grown material); "
              "radius: of the convex patch around the tip.\n\n"
           << "| # | tip x, y, z (m) | length (cm) | radius (cm) | tip speed (mm/yr) | drip factor |\n"
           << "|---|---|---|---|---|---|\n";
        int k = 1;
        for (const auto& r : j["largest"]) {
            md << "| " << k++ << " | " << fmt(r["tip_m"][0].get<double>(), 2) << ", "
               << fmt(r["tip_m"][1].get<double>(), 2) << ", " << fmt(r["tip_m"][2].get<double>(), 2) << " | "
               << fmt(r["length_m"].get<double>() * 100, 1) << " | " << fmt(r["radius_m"].get<double>() * 100, 1)
               << " | " << fmt(r["tip_speed_mm_per_yr"].get<double>(), 3) << " | "
               << fmt(r["drip_factor"].get<double>(), 2) << " |\n";
        }
    }
    for (const auto& p : j["pictures"]) {
        const std::string f = p.get<std::string>();
        if (f.find("_00") == std::string::npos && &p != &j["pictures"].back()) continue;
        md << "\n![" << f << "](" << f << ")\n";
    }
}

}  // namespace cavesim::app

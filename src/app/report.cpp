#include "app/report.h"

#include "app/speleo_report.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/report_html.h"
#include "app/report_pattern.h"
#include "app/report_section.h"
#include "app/state.h"
#include "core/error.h"
#include "core/fnv.h"
#include "mesh/cave_mesh.h"
#include "morpho/analysis.h"
#include "morpho/graph_metrics.h"
#include "morpho/reference_ranges.h"
#include "sim/fractures.h"
#include "sim/parameters.h"
#include "sim/recharge.h"
#include "sim/scenario_io.h"

namespace fs = std::filesystem;

namespace cavesim::app {

nlohmann::json jsonNumber(double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

namespace {

/// FNV-1a over the bytes of a grid: identical grids, identical checksums (determinism checks).
template <typename T>
std::string checksum(const Grid3<T>& g) {
    Fnv1a64 h;
    h.add(g.data.data(), g.data.size() * sizeof(T));
    return h.hex();
}

constexpr auto num = jsonNumber;

nlohmann::json stage1Json(const Stage1Result& r) {
    nlohmann::json zones = nlohmann::json::array();
    for (const ZoneStats& z : r.perZone) {
        zones.push_back({{"source", z.source},
                         {"voxels", z.voxels},
                         {"graph_nodes", z.graphNodes},
                         {"graph_edges", z.graphEdges},
                         {"graph_bytes", z.graphBytes},
                         {"max_flow", num(z.maxFlow)},
                         {"protosinks", z.protosinks},
                         {"protosinks_with_flow", z.protosinksWithFlow},
                         {"protochannel_voxels", z.protochannelVoxels},
                         {"branches", z.branches},
                         {"cycles_cancelled", z.cyclesCancelled},
                         {"flow_phases", z.phases},
                         {"flow_resistance", num(z.flowResistance)},
                         {"seconds", num(z.seconds)}});
    }
    return {{"zones", r.zones},  {"zone_voxels", r.zoneVoxels},         {"protochannel_voxels", r.protochannelVoxels},
            {"per_zone", zones}, {"seconds_zones", num(r.zoneSeconds)}, {"seconds", num(r.seconds)}};
}

nlohmann::json stage2Json(const Stage2Result& r, double voxelVolume) {
    nlohmann::json hist = nlohmann::json::array();
    for (const Stage2Record& h : r.history) {
        hist.push_back({{"iteration", h.iteration},
                        {"injected", num(h.injected)},
                        {"drained", num(h.drained)},
                        {"stored", num(h.stored)},
                        {"flow", num(h.flow)},
                        {"eroded_m3", num(h.eroded * voxelVolume)},
                        {"channel_voxels", h.channelVoxels},
                        {"pressure_updates", h.pressureUpdates},
                        {"sources_connected", h.sourcesConnected},
                        {"balance_error", num(h.balanceError)}});
    }
    const auto box = [](const std::array<int, 3>& lo, const std::array<int, 3>& hi) {
        return lo[0] > hi[0] ? nlohmann::json(nullptr) : nlohmann::json{{"lo", lo}, {"hi", hi}};
    };
    nlohmann::json phases = nlohmann::json::array();
    for (const Stage2PhaseRecord& p : r.phases) {
        phases.push_back(
            {{"first_iteration", p.firstIteration},
             {"iterations", p.iterations},
             {"water_table", p.waterTable >= 0 ? nlohmann::json(num(p.waterTable)) : nlohmann::json(nullptr)},
             {"water_table_from_site", p.fromSite},
             {"sinks", p.sinks},
             {"sources", p.sources},
             {"breakthrough_iteration",
              p.breakthroughIteration ? nlohmann::json(*p.breakthroughIteration) : nlohmann::json(nullptr)},
             {"cave_voxels_added", p.channelVoxelsEnd - p.channelVoxelsStart},
             {"cave_voxels", p.channelVoxelsEnd},
             {"cave_voxels_below_table", p.caveBelow},
             {"cave_voxels_above_table", p.caveAbove},
             {"cave_volume_below_table_m3", num(double(p.caveBelow) * voxelVolume)},
             {"cave_volume_above_table_m3", num(double(p.caveAbove) * voxelVolume)},
             {"cave_box_below_table", box(p.belowLo, p.belowHi)},
             {"cave_box_above_table", box(p.aboveLo, p.aboveHi)},
             {"cave_above_table_voxels_per_slice", num(p.aboveSliceMean)},
             {"water_injected", num(p.injected)},
             {"water_drained", num(p.drained)},
             {"eroded_m3", num(p.eroded * voxelVolume)}});
    }
    nlohmann::json perSource = nlohmann::json::array();
    for (const auto& it : r.sourceConnectedIteration)
        perSource.push_back(it ? nlohmann::json(*it) : nlohmann::json(nullptr));
    nlohmann::json out = {{"iterations", r.iterations},
                          {"breakthrough_iteration", r.breakthroughIteration ? nlohmann::json(*r.breakthroughIteration)
                                                                             : nlohmann::json(nullptr)},
                          {"source_connected_iteration", perSource},
                          {"water_balance_rel_error", num(r.waterBalanceRelError)},
                          {"water_injected", num(r.totalInjected)},
                          {"source_water_injected",
                           [&] {
                               nlohmann::json a = nlohmann::json::array();
                               for (double x : r.sourceInjected) a.push_back(num(x));
                               return a;
                           }()},
                          {"water_drained", num(r.totalDrained)},
                          {"pressure_cap", num(r.pressureCap)},
                          {"seconds_pressure", num(r.pressureSeconds)},
                          {"seconds_transport", num(r.transportSeconds)},
                          {"seconds_erosion", num(r.erosionSeconds)},
                          {"history", hist}};
    if (!r.phases.empty()) out["phases"] = phases;
    return out;
}

// ---- report.md ---------------------------------------------------------------------------------

std::string fmt(const nlohmann::json& v, int digits = 3) {
    return formatValue(v, digits);
}

}  // namespace

std::string formatValue(const nlohmann::json& v, int digits) {
    if (v.is_null()) return "–";
    if (v.is_boolean()) return v.get<bool>() ? "yes" : "no";
    if (v.is_number_integer()) return std::to_string(v.get<long long>());
    if (v.is_number()) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.*g", digits, v.get<double>());
        return buf;
    }
    if (v.is_string()) return v.get<std::string>();
    return v.dump();
}

const nlohmann::json& reportValue(const nlohmann::json& j, std::initializer_list<const char*> path) {
    static const nlohmann::json null;
    const nlohmann::json* cur = &j;
    for (const char* k : path) {
        if (!cur->is_object() || !cur->contains(k)) return null;
        cur = &(*cur)[k];
    }
    return *cur;
}

namespace {

const nlohmann::json& at(const nlohmann::json& j, const std::string& a, const std::string& b = "") {
    static const nlohmann::json null;
    if (!j.is_object() || !j.contains(a)) return null;
    if (b.empty()) return j.at(a);
    const auto& x = j.at(a);
    return x.is_object() && x.contains(b) ? x.at(b) : null;
}

std::string rangeText(const morpho::ReferenceRange* r) {
    if (!r) return "–";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g – %g", r->low, r->high);
    return buf;
}
std::string inRange(const nlohmann::json& v, const morpho::ReferenceRange* r) {
    if (!v.is_number() || !r) return "";
    const double x = v.get<double>();
    return x >= r->low && x <= r->high ? " ✓" : " ✗";
}

/// Paper Table 4 (its own caves, optimised field; rectangular in parentheses) and Table 5 timings.
const PaperCave kPaperCaves[] = {
    {"fig10", {0.317, 0.122}, {46.51, 17.94}, {5.59, 2.16}, 2.28, "1 min 43 s", "22 min 30 s"},
    {"fig11", {0.462, 0.179}, {77.54, 30.05}, {8.74, 3.39}, 1.95, "1 min 3 s", "9 min 39 s"},
    {"fig12", {0.277, 0.105}, {63.66, 24.05}, {14.06, 5.31}, 3.33, "4 min 6 s", "12 min 41 s"},
};

}  // namespace

const PaperCave* paperCave(const std::string& name) {
    for (const PaperCave& p : kPaperCaves)
        if (name == p.name) return &p;
    return nullptr;
}

std::string paperIndexText(const PaperCave& p, int row) {
    char buf[64];
    if (row == 3) {
        std::snprintf(buf, sizeof buf, "%g", p.width);
    } else {
        const double* v = row == 0 ? p.density : row == 1 ? p.coverage : p.porosity;
        std::snprintf(buf, sizeof buf, "%g (%g)", v[0], v[1]);
    }
    return buf;
}

nlohmann::json meshJson(const mesh::MeshStats& m) {
    return {{"vertices", m.vertices},
            {"faces", m.faces},
            {"area_m2", num(m.areaM2)},
            {"volume_m3", num(m.volumeM3)},
            {"euler_characteristic", m.eulerCharacteristic},
            {"closed", m.closed},
            {"manifold", m.manifold},
            {"components", m.components},
            {"seconds", num(m.seconds)}};
}

nlohmann::json analysisJson(const morpho::CaveAnalysis& a) {
    nlohmann::json j;
    j["network"] = morpho::toJson(a.network, a.skeleton);
    j["morphometry"] = morpho::toJson(a.morphometry);
    j["graph_metrics"] = morpho::toJson(a.metrics);
    j["skeleton"] = {{"nodes", a.skeleton.nodes.size()}, {"edges", a.skeleton.edges.size()}};
    j["cave_category"] = morpho::caveCategory(a.morphometry);
    if (a.nearProtochannels) j["near_protochannels"] = morpho::toJson(*a.nearProtochannels);
    j["pattern"] = morpho::toJson(a.pattern);
    j["cross_sections"] = a.sections.passages.empty() && a.pattern.pattern == "not classified"
                              ? nlohmann::json(nullptr)
                              : morpho::toJson(a.sections);
    j["seconds"] = num(a.seconds);
    return j;
}

FractureNetwork measuredFractureNetwork(const Scenario& s) {
    const Dims dims{s.size[0], s.size[1], s.size[2]};
    FractureNetwork net = generateFractureNetwork(s.fractureFamilies, dims, s.seed);
    measureFractureNetwork(net, s.fractureFamilies, dims);
    return net;
}

/// report.json `fracture_network`: the measured discs `net` of the scenario.
static nlohmann::json fractureNetworkJson(const Scenario& s, const FractureNetwork& net) {
    nlohmann::json fams = nlohmann::json::array();
    double p32 = 0;
    for (std::size_t f = 0; f < net.families.size(); ++f) {
        const FractureFamilyStats& st = net.families[f];
        const FractureFamily& g = s.fractureFamilies[f];
        p32 += st.p32;
        fams.push_back({{"line", g.line},
                        {"count", st.count},
                        {"given_dip_direction_deg", g.dipDirection},
                        {"given_dip_deg", g.dip},
                        {"given_kappa", g.kappa},
                        // No mean of no disc, no concentration estimate from fewer than 2.
                        {"mean_dip_direction_deg", st.count > 0 ? num(st.meanDipDirection) : nlohmann::json(nullptr)},
                        {"mean_dip_deg", st.count > 0 ? num(st.meanDip) : nlohmann::json(nullptr)},
                        {"kappa_estimate", st.count > 1 ? num(st.kappaEstimate) : nlohmann::json(nullptr)},
                        {"mean_length_m", num(st.meanLength * s.voxelSize)},
                        {"p32_per_m", num(st.p32 / s.voxelSize)},
                        {"p32_nominal_per_m", num(st.p32Nominal / s.voxelSize)},
                        {"slab_voxels", st.voxels}});
    }
    return {{"discs", net.discs.size()}, {"p32_per_m", num(p32 / s.voxelSize)}, {"families", fams}};
}

void putAnalysis(nlohmann::json& report, const nlohmann::json& analysis) {
    const bool given = analysis.is_object();
    for (const char* k : kAnalysisKeys)
        report[k] = given && analysis.contains(k) ? analysis[k] : nlohmann::json(nullptr);
    if (given && analysis.contains("near_protochannels") && report.contains("stage2") && report["stage2"].is_object())
        report["stage2"]["near_protochannels"] = analysis["near_protochannels"];
}

nlohmann::json buildReportJson(const Scenario& s, const Domain& dom, const RunRecord& rec) {
    nlohmann::json j;
    j["scenario"] = s.name;
    j["grid"] = {s.size[0], s.size[1], s.size[2]};
    j["voxel_size_m"] = s.voxelSize;
    // Index → world: x = origin + (i, j, k) · voxel size (a voxel's low corner); [site] origin.
    j["world_from_index"] = {{"origin_m", {dom.origin[0], dom.origin[1], dom.origin[2]}},
                             {"scale_m", s.voxelSize},
                             {"crs", s.siteData ? nlohmann::json(s.siteData->crs) : nlohmann::json(nullptr)}};
    j["seed"] = s.seed;
    j["threads"] = rec.threads;
    j["timing_s"] = {{"stage1", num(rec.timing.stage1)},   {"stage2", num(rec.timing.stage2)},
                     {"mesh", num(rec.timing.mesh)},       {"report", num(rec.timing.report)},
                     {"exports", num(rec.timing.exports)}, {"total", num(rec.timing.total)}};
    j["stage1"] = rec.stage1 ? stage1Json(*rec.stage1) : nlohmann::json(nullptr);
    j["stage2"] =
        rec.stage2 ? stage2Json(*rec.stage2, s.voxelSize * s.voxelSize * s.voxelSize) : nlohmann::json(nullptr);
    if (rec.stage2 && rec.connectedAtStart) j["stage2"]["connected_at_start"] = *rec.connectedAtStart;
    putAnalysis(j, rec.analysis);
    j["mesh"] = rec.mesh;
    if (!rec.speleothems.is_null()) j["speleothems"] = rec.speleothems;
    j["files"] = rec.files;
    j["exports"] = rec.exports;
    if (rec.fractures) j["fracture_network"] = fractureNetworkJson(s, *rec.fractures);
    if (!s.recharge.empty()) {
        std::vector<std::size_t> perEntry;
        const std::vector<SourceSpec> inputs = rechargeSources(s, &perEntry);
        nlohmann::json entries = nlohmann::json::array();
        for (std::size_t i = 0; i < s.recharge.size(); ++i) {
            const RechargeSpec& e = s.recharge[i];
            const std::size_t n = perEntry[i];
            entries.push_back({{"kind", e.kind == RechargeKind::kSinkholes ? "sinkholes"
                                        : e.kind == RechargeKind::kDiffuse ? "diffuse"
                                                                           : "stream"},
                               {"line", e.line},
                               {"sources", n}});
        }
        j["recharge"] = {{"sources", inputs.size()}, {"first_source", s.sources.size() + 1}, {"entries", entries}};
    }
    j["checksums"] = {{"porosity", checksum(recordedPorosity(dom, s, StateMoment::kFinal))},
                      {"pressure", checksum(dom.pressure)},
                      {"flow", checksum(dom.flow)},
                      {"zone", checksum(dom.zone)},
                      {"flags", checksum(dom.flags)}};
    return j;
}

std::string buildReportMarkdown(const Scenario& s, const nlohmann::json& r, const std::string& dir) {
    std::ostringstream md;
    md << "# cavesim report: " << s.name << "\n\n";
    md << "Scenario `" << s.name << "` from `" << s.path << "`: grid " << s.size[0] << " × " << s.size[1] << " × "
       << s.size[2] << " voxels of " << s.voxelSize << " m (" << s.size[0] * s.voxelSize << " × "
       << s.size[1] * s.voxelSize << " × " << s.size[2] * s.voxelSize << " m), seed " << s.seed << ", "
       << fmt(r.value("threads", nlohmann::json(1))) << " thread(s); " << s.sources.size() << " source(s), "
       << s.sinks.size() << " sink(s), " << s.spheres.size() << " obstacle(s), " << s.planes.size() << " plane(s), "
       << s.channels.size() << " given channel(s)"
       << (s.recharge.empty() ? std::string()
                              : "; " + std::to_string(at(at(r, "recharge"), "sources").get<long>()) +
                                    " source(s) from " + std::to_string(s.recharge.size()) + " [[recharge]] entries")
       << (s.inceptionHorizons.empty() ? std::string()
                                       : ", " + std::to_string(s.inceptionHorizons.size()) + " inception horizon(s)")
       << ".\n\n";
    if (r.contains("fracture_network")) {
        const auto& fn = r["fracture_network"];
        md << "## Fracture network\n\nDiscs drawn from the seed (docs/geology.md, \"Fracture families\"); the "
              "orientation and kappa are measured back from the discs; P32 is the disc area inside the block per "
              "volume.\n\n| family | discs | given dip dir/dip | measured | kappa given/estimated | mean length (m) | "
              "P32 (1/m) |\n|---|---|---|---|---|---|---|\n";
        int n = 0;
        for (const auto& f : at(fn, "families"))
            md << "| " << ++n << " | " << fmt(at(f, "count")) << " | " << fmt(at(f, "given_dip_direction_deg")) << "/"
               << fmt(at(f, "given_dip_deg")) << " | " << fmt(at(f, "mean_dip_direction_deg")) << "/"
               << fmt(at(f, "mean_dip_deg")) << " | " << fmt(at(f, "given_kappa")) << "/"
               << fmt(at(f, "kappa_estimate")) << " | " << fmt(at(f, "mean_length_m")) << " | "
               << fmt(at(f, "p32_per_m")) << " |\n";
        md << "\n";
    }

    md << "## Parameters\n\nEvery key of the scenario's tables; a value that differs from the default is in bold, "
          "with the default beside it.\n\n"
       << parameterTableMarkdown(s);

    const PaperCave* paper = paperCave(s.name);

    md << "\n## Timings\n\n| phase | seconds |" << (paper ? " paper (Table 5) |" : "") << "\n|---|---|"
       << (paper ? "---|" : "") << "\n";
    const auto& t = at(r, "timing_s");
    md << "| stage 1 | " << fmt(at(t, "stage1")) << " |" << (paper ? std::string(" ") + paper->stage1Time + " |" : "")
       << "\n";
    md << "| stage 2 | " << fmt(at(t, "stage2")) << " |" << (paper ? std::string(" ") + paper->stage2Time + " |" : "")
       << "\n";
    md << "| mesh and pictures | " << fmt(at(t, "mesh")) << " |" << (paper ? " – |" : "") << "\n";
    md << "| skeleton and report | " << fmt(at(t, "report")) << " |" << (paper ? " – |" : "") << "\n";
    if (t.contains("exports"))
        md << "| files for other tools | " << fmt(at(t, "exports")) << " |" << (paper ? " – |" : "") << "\n";
    md << "| total | " << fmt(at(t, "total")) << " |" << (paper ? " – |" : "") << "\n";

    md << "\n## Events\n\n";
    const auto& st1 = at(r, "stage1");
    if (!st1.is_null()) {
        md << "- Stage 1: " << fmt(at(st1, "zones")) << " pressure zone(s), voxels per source "
           << at(st1, "zone_voxels").dump() << ", " << fmt(at(st1, "protochannel_voxels")) << " protochannel voxels.\n";
    }
    const auto& st2 = at(r, "stage2");
    if (!st2.is_null()) {
        md << "- Stage 2: " << fmt(at(st2, "iterations")) << " iterations; sources joined to a sink at the start "
           << fmt(at(st2, "connected_at_start")) << "; breakthrough at iteration "
           << fmt(at(st2, "breakthrough_iteration"))
           << "; iteration at which each source joined a sink: " << at(st2, "source_connected_iteration").dump()
           << ".\n";
        const auto& near = at(st2, "near_protochannels");
        if (!near.is_null())
            md << "- Near the stage-1 protochannels (within " << fmt(at(near, "radius_vox"))
               << " voxels): " << fmt(at(near, "centreline_share")) << " of the centreline, "
               << fmt(at(near, "block_share")) << " of the block.\n";
        if (st2.contains("phases"))
            for (const auto& p : st2["phases"]) {
                md << "- Phase from iteration " << fmt(at(p, "first_iteration")) << ", " << fmt(at(p, "iterations"))
                   << " iterations, water table " << fmt(at(p, "water_table")) << " (voxels), sinks "
                   << at(p, "sinks").dump() << ", sources " << at(p, "sources").dump() << ": breakthrough at iteration "
                   << fmt(at(p, "breakthrough_iteration")) << "; " << fmt(at(p, "cave_voxels_added"))
                   << " cave voxels added; cave volume below the table " << fmt(at(p, "cave_volume_below_table_m3"))
                   << " m³, above " << fmt(at(p, "cave_volume_above_table_m3")) << " m³.\n";
            }
        md << "- Water balance: injected " << fmt(at(st2, "water_injected"), 6) << ", drained "
           << fmt(at(st2, "water_drained"), 6) << ", relative error " << fmt(at(st2, "water_balance_rel_error"), 2)
           << ".\n";
    }
    const auto& net = at(r, "network");
    if (!net.is_null()) {
        md << "- Network (flow paths down the stage-2 pressure, mapped onto the skeleton; definitions in "
              "docs/network-definitions.md): "
           << fmt(at(net, "sources_connected")) << " of " << fmt(at(net, "sources_total"))
           << " sources connected to a sink, " << fmt(at(net, "confluences")) << " confluence(s), "
           << fmt(at(net, "tributary_captures")) << " tributary capture(s), " << fmt(at(net, "phreatic_loops"))
           << " phreatic loop(s); share of the paths that needed a fallback: " << fmt(at(net, "fallback_fraction"))
           << ".\n";
    }
    const auto& mesh = at(r, "mesh");
    if (!mesh.is_null()) {
        md << "- Mesh: " << fmt(at(mesh, "vertices")) << " vertices, " << fmt(at(mesh, "faces")) << " faces, "
           << fmt(at(mesh, "components")) << " component(s), closed " << fmt(at(mesh, "closed")) << ", manifold "
           << fmt(at(mesh, "manifold")) << " (`cave.obj`, `cave.ply`).\n";
    }

    writeSpeleothemsMarkdown(md, r);

    md << "\n## Pictures\n\n";
    const bool section = isSectionScenario(s);
    const std::pair<const char*, const char*> pictures[] = {{"perspective.png", "perspective"},
                                                            {"plan.png", "plan (from above)"},
                                                            {"side_xz.png", "side (x–z)"},
                                                            {"side_yz.png", "side (y–z)"},
                                                            {"map_plan.png", "plan map"},
                                                            {"map_section.png", "section map"},
                                                            {"map_extended_elevation.png", "extended elevation"},
                                                            {"sections.png", "representative passage cross-sections"},
                                                            {"zones.png", "stage-1 zones and protochannels"},
                                                            {"pressure.png", "stage-2 pressure"},
                                                            {"flow.png", "stage-2 flow"},
                                                            {"sequence.png", "stage-2 snapshots"}};
    for (const auto& [file, caption] : pictures)
        if (fs::exists(fs::path(dir) / "images" / file)) md << "![" << caption << "](images/" << file << ")\n\n";

    if (section) md << sectionMeasuresMarkdown(s, r);
    const auto& mo = section ? at(r, "") : at(r, "morphometry");  // a section has no plan indices
    if (!mo.is_null()) {
        md << "## Morphometric indices (paper §4.2)\n\n";
        md << "Cave length " << fmt(at(mo, "length_m")) << " m, plan area " << fmt(at(mo, "area_m2")) << " m², volume "
           << fmt(at(mo, "volume_m3")) << " m³; cave field " << fmt(at(mo, "a_field_opt_m2"))
           << " m² (optimised: the plan with a margin of half the mean passage spacing, "
           << fmt(at(mo, "field_margin_m")) << " m, within the convex hull), " << fmt(at(mo, "a_field_hull_m2"))
           << " m² (convex hull of the plan) and " << fmt(at(mo, "a_field_rect_m2"))
           << " m² (bounding rectangle). Category: **" << fmt(at(r, "cave_category")) << "**.\n\n";
        md << "| index | ours (opt.) | ours (rect.) | unconfined (Tab. 2) | confined (Tab. 2) | chamber (Tab. 3) | "
              "confined (Tab. 3) |"
           << (paper ? " paper's cave (Tab. 4) |" : "") << "\n|---|---|---|---|---|---|---|" << (paper ? "---|" : "")
           << "\n";
        int row = 0;
        for (const IndexRow& x : kIndexRows) {
            const bool width = std::string(x.key) == "mean_width_m";
            const std::string optKey = width ? x.key : std::string(x.key) + "_opt";
            const std::string rectKey = width ? x.key : std::string(x.key) + "_rect";
            const nlohmann::json& opt = at(mo, optKey);
            const nlohmann::json& rect = at(mo, rectKey);
            using morpho::findReferenceRange;
            const auto* confined2 = findReferenceRange(optKey.c_str(), "confined", 2);
            const auto* confined3 = findReferenceRange(rectKey.c_str(), "confined", 3);
            md << "| " << x.label << " | " << fmt(opt) << inRange(opt, confined2) << " | " << fmt(rect)
               << inRange(rect, confined3) << " | " << rangeText(findReferenceRange(optKey.c_str(), "unconfined", 2))
               << " | " << rangeText(confined2) << " | " << rangeText(findReferenceRange(rectKey.c_str(), "chamber", 3))
               << " | " << rangeText(confined3) << " |";
            if (paper) md << " " << paperIndexText(*paper, row) << " |";
            md << "\n";
            ++row;
        }
        md << "\n✓/✗: inside/outside the confined range (optimised column against Table 2, rectangle column against "
              "Table 3).\n";
    }

    const auto& gm = at(r, "graph_metrics");
    if (!gm.is_null()) {
        const bool small = at(gm, "too_small").is_boolean() && at(gm, "too_small").get<bool>();
        md << "\n## Network metrics (Collon et al. 2017)\n\n";
        if (small)
            md << "Too small for network statistics: " << fmt(at(gm, "branches")) << " branch(es), fewer than "
               << morpho::kMinNetworkBranches << "; the metrics are not compared with the real caves.\n\n";
        md << "| metric | meaning | ours | real caves (34 networks) |\n|---|---|---|---|\n";
        for (const char* key : kNetworkMetricKeys) {
            if (section && std::string(key) == "h_or") continue;  // plan azimuths: none in a section
            const morpho::ReferenceRange* m = morpho::findReferenceRange(key, "real caves", 0);
            md << "| `" << key << "` | " << (m ? m->meaning : "") << " | " << fmt(at(gm, key))
               << (small ? std::string(" (too small)") : inRange(at(gm, key), m)) << " | " << rangeText(m) << " |\n";
        }
    }
    md << patternMarkdown(r) << crossSectionsMarkdown(r);
    md << "\nFiles: `scenario.toml` (effective scenario), `state.vdb`, `stage1.vdb`, `cave.obj`, `cave.ply`, "
          "`skeleton.json`, `skeleton_nodes.dat`, `skeleton_links.dat`, `report.json`, `report.html` (this report with "
          "a 3D view), `images/map_*` (cave maps), `images/sections.png` (cross-sections).\n";
    return md.str();
}

void writeReport(const Scenario& s, const Domain& dom, RunRecord& rec, const std::string& dir) {
    rec.json = buildReportJson(s, dom, rec);
    writeReportFiles(s, rec.json, dir);
}

void writeReportFiles(const Scenario& s, const nlohmann::json& report, const std::string& dir) {
    writeFileAtomic((fs::path(dir) / "report.json").string(), report.dump(2) + "\n");
    const std::string md = buildReportMarkdown(s, report, dir);
    writeFileAtomic((fs::path(dir) / "report.md").string(), md);
    writeReportHtml(dir, md);
}

}  // namespace cavesim::app

// `cavesim reproduce`: runs the paper's figure scenarios and writes docs/reproduction.md with our
// pictures and numbers beside the paper's descriptions, Table 4 indices and Table 5 timings.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <tbb/global_control.h>
#include <tbb/info.h>

#include "cli/commands.h"
#include "cli/output_dir.h"
#include "cli/pipeline.h"
#include "cli/progress_bar.h"
#include "cli/report.h"
#include "core/error.h"
#include "sim/scenario_io.h"

namespace fs = std::filesystem;

namespace cavesim::cli {
namespace {

struct Figure {
    const char* scenario;
    const char* title;
    const char* paper;  ///< what the paper's figure shows, in our words
    const char* pictures[3];
};

const Figure kFigures[] = {
    {"fig05_equal", "Figure 5 (left): two sources of equal pressure",
     "Two sources of equal pressure divide the rock between them on the bisector; each zone is a "
     "flow network for stage 1.",
     {"zones.png", nullptr, nullptr}},
    {"fig05_ratio2", "Figure 5 (right): source pressures 2 : 1",
     "The source with the higher pressure claims the larger zone; the boundary bends around the weaker "
     "source.",
     {"zones.png", nullptr, nullptr}},
    {"fig06", "Figure 6: protochannel systems",
     "Protochannels branch outward from a core at each source; zones of neighbouring sources act as "
     "obstacles to each other; a longer system develops where the zone is long.",
     {"zones.png", "perspective.png", nullptr}},
    {"fig08", "Figure 8: channel growth in 2D, rates 0.05 : 0.001",
     "Three synthetic protochannels hang from three sources; the sink is on the right boundary. The "
     "channel nearest the sink breaks through first; its neighbours then link up to it in sequence, "
     "climbing into its passage (phreatic loops).",
     {"sequence.png", "pressure.png", "flow.png"}},
    {"fig09", "Figure 9: channel growth in 2D, rates 0.0025 : 0.001",
     "With little resistance in the rock, development toward the sink is preferred over linking up with "
     "a neighbour and no phreatic loops form; the result depends only on the ratio of the rates.",
     {"sequence.png", "pressure.png", "flow.png"}},
    {"fig10", "Figure 10: three sources, one sink area, spherical obstacles",
     "Protochannels branch from three sources; in stage 2 larger channels converge on a single sink "
     "area, the farther sources reaching it as captured tributaries; obstacles make the channels meander "
     "and form arches.",
     {"perspective.png", "plan.png", "side_xz.png"}},
    {"fig11", "Figure 11: four sources, two sink areas, bedding planes and a vertical fracture",
     "Passages stay nearly planar along two horizontal bedding planes; two nearly vertical passages "
     "follow the vertical fracture plane.",
     {"perspective.png", "plan.png", "side_xz.png"}},
    {"fig12", "Figure 12: one source area, two weak sources, inclined bedding and dense fractures",
     "A single large source area paired with a sink area in the opposite wall gives a wide main passage; "
     "two weak sources at the top add tributaries along the inclined bedding planes.",
     {"perspective.png", "plan.png", "side_xz.png"}},
};

std::string fmt(const nlohmann::json& v, int digits = 3) {
    if (v.is_null()) return "–";
    if (v.is_number_integer()) return std::to_string(v.get<long long>());
    if (v.is_number()) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.*g", digits, v.get<double>());
        return buf;
    }
    if (v.is_string()) return v.get<std::string>();
    return v.dump();
}

const nlohmann::json& get(const nlohmann::json& j, std::initializer_list<const char*> path) {
    static const nlohmann::json null;
    const nlohmann::json* cur = &j;
    for (const char* k : path) {
        if (!cur->is_object() || !cur->contains(k)) return null;
        cur = &(*cur)[k];
    }
    return *cur;
}

}  // namespace

int reproduceCommand(const ReproduceOptions& opt) {
    const fs::path scenarios(opt.scenarioDir);
    if (!fs::is_directory(scenarios))
        throw InputError(opt.scenarioDir + ": no such folder of scenarios (run from the repository root or give --scenarios)");
    // Check every scenario before running any, so a typo costs nothing.
    std::vector<std::pair<const Figure*, Scenario>> runs;
    for (const Figure& f : kFigures) {
        const fs::path p = scenarios / (std::string(f.scenario) + ".toml");
        if (!fs::exists(p)) throw InputError(p.string() + ": missing figure scenario");
        runs.push_back({&f, parseScenarioFile(p.string())});
    }
    const int threads = opt.threads > 0 ? opt.threads : int(tbb::info::default_concurrency());
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));

    const fs::path doc(opt.docPath);
    const fs::path imageDir = doc.parent_path() / "images";
    fs::create_directories(imageDir);

    std::ostringstream md;
    md << "# Reproducing Pytel & Mann (JCGT 2015)\n\n"
          "Generated by `cavesim reproduce` (" << threads << " thread(s)); every number below is measured from the "
          "runs it made. Pictures are copied from the run folders into `docs/images/`. Definitions of the "
          "network counts: [network-definitions.md](network-definitions.md); choices our reading of the paper "
          "had to make: [model.md](model.md).\n\n";
    std::vector<std::pair<std::string, nlohmann::json>> reports;

    for (auto& [fig, s] : runs) {
        ProgressBar bar(true);
        const fs::path out = fs::path(opt.outDir) / s.name;
        OutputDir dir(out, true);
        dir.open();
        const PipelineResult res = runPipeline(s, threads, dir, bar);
        dir.commit();
        std::fprintf(stderr, "reproduce: %s in %.2f s\n", s.name.c_str(), res.totalSeconds);
        const nlohmann::json& r = res.report;
        reports.push_back({s.name, r});

        md << "## " << fig->title << "\n\n**Paper.** " << fig->paper << "\n\n**Ours** (`scenarios/" << fig->scenario
           << ".toml`, " << s.size[0] << "×" << s.size[1] << "×" << s.size[2] << " voxels of " << s.voxelSize
           << " m, " << fmt(get(r, {"timing_s", "total"})) << " s). ";
        if (!get(r, {"stage1"}).is_null())
            md << "Stage 1: zone voxels per source " << get(r, {"stage1", "zone_voxels"}).dump() << ", "
               << fmt(get(r, {"stage1", "protochannel_voxels"})) << " protochannel voxels. ";
        if (!get(r, {"stage2"}).is_null())
            md << "Stage 2: breakthrough at iteration " << fmt(get(r, {"stage2", "breakthrough_iteration"}))
               << ", sources joined a sink at iterations " << get(r, {"stage2", "source_connected_iteration"}).dump()
               << "; " << fmt(get(r, {"network", "sources_connected"})) << " of "
               << fmt(get(r, {"network", "sources_total"})) << " sources connected, "
               << fmt(get(r, {"network", "tributary_captures"})) << " tributary capture(s), "
               << fmt(get(r, {"network", "phreatic_loops"})) << " phreatic loop(s), "
               << fmt(get(r, {"network", "confluences"})) << " confluence(s). ";
        md << "\n\n";
        for (const char* pic : fig->pictures) {
            if (!pic) continue;
            const fs::path src = out / "images" / pic;
            if (!fs::exists(src)) continue;
            const std::string name = s.name + "_" + pic;
            fs::copy_file(src, imageDir / name, fs::copy_options::overwrite_existing);
            md << "![" << s.name << " " << pic << "](images/" << name << ")\n";
        }
        md << "\n";
    }

    md << "## Table 4: morphometric indices\n\nOurs: convex-hull field (rectangular field in parentheses); the "
          "paper's values from its Table 4. Confined ranges (paper Table 2): density 0.049–0.406 m/m², coverage "
          "13.56–58.51 %, porosity 1.1–12 %, W 0.65–4.53 m.\n\n"
          "| index | fig10 ours | fig10 paper | fig11 ours | fig11 paper | fig12 ours | fig12 paper |\n"
          "|---|---|---|---|---|---|---|\n";
    const char* paperRows[4][3] = {{"0.317 (0.122)", "0.462 (0.179)", "0.277 (0.105)"},
                                   {"46.51 (17.94)", "77.54 (30.05)", "63.66 (24.05)"},
                                   {"5.59 (2.16)", "8.74 (3.39)", "14.06 (5.31)"},
                                   {"2.28", "1.95", "3.33"}};
    const char* keys[4] = {"network_density", "areal_coverage_pct", "porosity_pct", "mean_width_m"};
    const char* labels[4] = {"network density (m/m²)", "areal coverage (%)", "porosity (%)", "W (m)"};
    for (int row = 0; row < 4; ++row) {
        md << "| " << labels[row] << " |";
        int c = 0;
        for (const char* name : {"fig10", "fig11", "fig12"}) {
            std::string ours = "–";
            for (const auto& [n, r] : reports) {
                if (n != name) continue;
                const auto& m = get(r, {"morphometry"});
                if (row == 3)
                    ours = fmt(get(m, {keys[row]}));
                else
                    ours = fmt(get(m, {(std::string(keys[row]) + "_opt").c_str()})) + " (" +
                           fmt(get(m, {(std::string(keys[row]) + "_rect").c_str()})) + ")";
            }
            md << " " << ours << " | " << paperRows[row][c++] << " |";
        }
        md << "\n";
    }
    md << "\nCave category from the indices: ";
    for (const auto& [n, r] : reports)
        if (n == "fig10" || n == "fig11" || n == "fig12") md << n << " " << fmt(get(r, {"cave_category"})) << "; ";
    md << "\n\n## Network metrics (Collon et al. 2017)\n\nReal caves (34 networks): h_or 0.75–1.00, len_mean "
          "8.46–331.74 m, cv_len 0.90–2.56, h_len 0.07–0.67, k_mean 1.75–2.57, r_k −0.56 – −0.15, spl "
          "2.32–55.72, cpd 0.02–0.57, tortuosity 1.12–1.54.\n\n| scenario | h_or | len_mean_m | cv_len | h_len | "
          "k_mean | r_k | spl | cpd | tortuosity |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& [n, r] : reports) {
        md << "| " << n << " |";
        for (const char* k : {"h_or", "len_mean_m", "cv_len", "h_len", "k_mean", "r_k", "spl", "cpd", "tortuosity"})
            md << " " << fmt(get(r, {"graph_metrics", k})) << " |";
        md << "\n";
    }
    md << "\n## Table 5: timings\n\nOurs on this machine (" << threads
       << " thread(s), one run; medians of repeated runs are in `bench/README.md`) beside the paper's "
          "single-threaded 2.5 GHz Athlon.\n\n| scenario | grid | stage 1 (s) | stage 2 (s) | whole run (s) | paper "
          "stage 1 | paper stage 2 |\n|---|---|---|---|---|---|---|\n";
    for (const auto& [n, r] : reports) {
        const char* p1 = n == "fig10" ? "1 min 43 s" : n == "fig11" ? "1 min 3 s" : n == "fig12" ? "4 min 6 s" : "–";
        const char* p2 = n == "fig10" ? "22 min 30 s" : n == "fig11" ? "9 min 39 s" : n == "fig12" ? "12 min 41 s" : "–";
        md << "| " << n << " | " << get(r, {"grid"}).dump() << " | " << fmt(get(r, {"timing_s", "stage1"})) << " | "
           << fmt(get(r, {"timing_s", "stage2"})) << " | " << fmt(get(r, {"timing_s", "total"})) << " | " << p1
           << " | " << p2 << " |\n";
    }
    writeFileAtomic(doc.string(), md.str());
    std::printf("wrote %s and %zu run(s) under %s\n", doc.string().c_str(), reports.size(), opt.outDir.c_str());
    return 0;
}

}  // namespace cavesim::cli

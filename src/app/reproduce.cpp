// `cavesim reproduce`: runs the paper's figure scenarios and writes docs/reproduction.md with our
// pictures and numbers beside the paper's descriptions, Table 4 indices and Table 5 timings;
// `cavesim reproduce geology` runs the shipped geological settings and writes
// docs/geology_settings.md with their pictures (app/geology_settings.h).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>

#include <unistd.h>

#include <tbb/global_control.h>
#include <tbb/info.h>

#include "app/commands.h"
#include "app/geology_settings.h"
#include "app/output_dir.h"
#include "app/pipeline.h"
#include "app/report.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "morpho/reference_ranges.h"
#include "sim/parameters.h"
#include "sim/scenario_io.h"

namespace fs = std::filesystem;

namespace cavesim::app {
namespace {

/// The scenario setting (table, key and value) that makes `extent` the cave, as written in a file.
std::string caveSetting(CaveExtent extent) {
    Scenario s;
    s.output.cave = extent;
    const auto [section, param] = findParam(s, &s.output.cave);
    return section->header() + " " + param->key + " = " + paramValueText(param->get(section->record(s, 0)));
}

struct Figure {
    const char* scenario;
    const char* title;
    const char* paper;  ///< what the paper's figure shows, in our words
    const char* pictures[3];
};

const Figure kFigures[] = {
    {"fig05_equal",
     "Figure 5 (left): two sources of equal pressure",
     "Two sources of equal pressure divide the rock between them on the bisector; each zone is a "
     "flow network for stage 1.",
     {"zones.png", nullptr, nullptr}},
    {"fig05_ratio2",
     "Figure 5 (right): source pressures 2 : 1",
     "The source with the higher pressure claims the larger zone; the boundary bends around the weaker "
     "source.",
     {"zones.png", nullptr, nullptr}},
    {"fig06",
     "Figure 6: protochannel systems",
     "Protochannels branch outward from a core at each source; zones of neighbouring sources act as "
     "obstacles to each other; a longer system develops where the zone is long.",
     {"zones.png", "perspective.png", nullptr}},
    {"fig08",
     "Figure 8: channel growth in 2D, rates 0.05 : 0.001",
     "Three synthetic protochannels hang from three sources; the sink is on the right boundary. The "
     "channel nearest the sink breaks through first; its neighbours then link up to it in sequence, "
     "climbing into its passage (phreatic loops).",
     {"sequence.png", "pressure.png", "flow.png"}},
    {"fig09",
     "Figure 9: channel growth in 2D, rates 0.0025 : 0.001",
     "With little resistance in the rock, development toward the sink is preferred over linking up with "
     "a neighbour: each protochannel reaches the sink without first going through a neighbour and no "
     "phreatic loops form; the result depends only on the ratio of the rates.",
     {"sequence.png", "pressure.png", "flow.png"}},
    {"fig10",
     "Figure 10: three sources, one sink area, spherical obstacles",
     "Protochannels branch from three sources; in stage 2 larger channels converge on a single sink "
     "area, the farther sources reaching it as captured tributaries; obstacles make the channels meander "
     "and form arches.",
     {"perspective.png", "plan.png", "side_xz.png"}},
    {"fig11",
     "Figure 11: four sources, two sink areas, bedding planes and a vertical fracture",
     "Passages stay nearly planar along two horizontal bedding planes; two nearly vertical passages "
     "follow the vertical fracture plane.",
     {"perspective.png", "plan.png", "side_xz.png"}},
    {"fig12",
     "Figure 12: one source area, two weak sources, inclined bedding and dense fractures",
     "A single large source area paired with a sink area in the opposite wall gives a wide main passage; "
     "two weak sources at the top add tributaries along the inclined bedding planes.",
     {"perspective.png", "plan.png", "side_xz.png"}},
};

std::string fmt(const nlohmann::json& v) {
    return formatValue(v);
}

/// Where a reproduction writes into the docs: the Markdown file and the pictures' folder beside it.
struct DocTarget {
    fs::path doc;
    fs::path imageDir;
};

/// Checks the Markdown file's place before anything runs: its folder exists, is a folder and can
/// be written; the file is not a folder; `images/` beside it, if there, is a folder that can be
/// written (it is created at the end when missing).
/// @throw InputError naming the path and what is wrong
DocTarget checkedDocTarget(const std::string& docPath) {
    const fs::path doc(docPath);
    const fs::path folder = doc.parent_path().empty() ? fs::path(".") : doc.parent_path();
    const std::string shown = "--doc " + docPath;
    std::error_code ec;
    if (doc.filename().empty() || fs::is_directory(doc, ec))
        throw InputError(shown +
                         ": is a folder; give the Markdown file to write (its pictures go into images/ beside it)");
    if (!fs::exists(folder, ec))
        throw InputError(shown + ": no such folder " + folder.string() +
                         " (run from the repository root, or give --doc a file in an existing folder)");
    if (!fs::is_directory(folder, ec)) throw InputError(shown + ": " + folder.string() + " is not a folder");
    if (::access(folder.c_str(), W_OK | X_OK) != 0)
        throw InputError(shown + ": the folder " + folder.string() + " cannot be written");
    const fs::path images = folder / "images";
    if (fs::exists(fs::symlink_status(images, ec))) {  // a symlink, dangling or not, exists
        if (!fs::is_directory(images, ec))
            throw InputError(shown + ": " + images.string() + " (the pictures' folder) is not a folder");
        if (::access(images.c_str(), W_OK | X_OK) != 0)
            throw InputError(shown + ": the pictures' folder " + images.string() + " cannot be written");
    }
    return {doc, images};
}

/// A picture to write into the docs' images folder once every run has succeeded.
struct StagedPicture {
    std::string name;   ///< file name inside the images folder
    std::string bytes;  ///< its contents, read from the run folder
};

/// The output folders of the runs, one per name under `outDir`, each checked (OutputDir) before the
/// first run starts.
std::vector<std::unique_ptr<OutputDir>> checkedRunDirs(const std::string& outDir,
                                                       const std::vector<std::string>& names) {
    std::vector<std::unique_ptr<OutputDir>> dirs;
    for (const std::string& n : names) dirs.push_back(std::make_unique<OutputDir>(fs::path(outDir) / n, true));
    return dirs;
}

/// Runs `s` into `dir` (staged, renamed into place when complete) and logs its time.
PipelineResult runInto(const Scenario& s, OutputDir& dir, const PipelineOptions& po, const LogFn& log) {
    dir.open();
    PipelineResult res = runPipeline(s, dir, po);
    dir.commit();
    char line[160];
    std::snprintf(line, sizeof line, "reproduce: %s in %.2f s", s.name.c_str(), res.totalSeconds);
    if (log) log(line);
    return res;
}

/// Writes the pictures, then the Markdown file, each whole; the images folder is created when missing.
/// @throw RuntimeError when a folder or a file cannot be written
void writeDocs(const DocTarget& target, const std::vector<StagedPicture>& pictures, const std::string& markdown) {
    std::error_code ec;
    if (!pictures.empty()) {
        fs::create_directories(target.imageDir, ec);
        if (ec) throw RuntimeError("cannot create " + target.imageDir.string() + ": " + ec.message());
    }
    for (const StagedPicture& p : pictures) writeFileAtomic((target.imageDir / p.name).string(), p.bytes);
    writeFileAtomic(target.doc.string(), markdown);
}

/// Reads the scenarios folder's `<name>.toml`, checked and with `seed` when given.
/// @throw InputError when it is missing or invalid
Scenario readScenario(const fs::path& scenarios, const std::string& name, const char* what,
                      std::optional<std::uint64_t> seed) {
    const fs::path p = scenarios / (name + ".toml");
    if (!fs::exists(p)) throw InputError(p.string() + ": missing " + what);
    RunRequest request;
    request.scenarioPath = p.string();
    if (seed) request.seed = std::to_string(*seed);
    return requestedScenario(request);
}

void checkScenarioDir(const fs::path& scenarios) {
    if (!fs::is_directory(scenarios))
        throw InputError(scenarios.string() +
                         ": no such folder of scenarios (run from the repository root or give --scenarios)");
}

void reproduceGeology(const ReproduceOptions& opt, const LogFn& log) {
    const fs::path scenarios(opt.scenarioDir);
    checkScenarioDir(scenarios);
    std::vector<Scenario> runs;
    std::vector<std::string> names;
    for (const GeologySetting& g : geologySettings()) {
        runs.push_back(readScenario(scenarios, g.scenario, "geological setting", kGeologySeed));
        names.push_back(runs.back().name);
    }
    const DocTarget target = checkedDocTarget(opt.docPath);
    std::vector<std::unique_ptr<OutputDir>> dirs = checkedRunDirs(opt.outDir, names);
    const int threads = opt.threads > 0 ? opt.threads : int(tbb::info::default_concurrency());
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));

    std::vector<GeologyRun> results;
    std::vector<StagedPicture> pictures;
    for (std::size_t i = 0; i < runs.size(); ++i) {
        const GeologySetting& g = geologySettings()[i];
        PipelineOptions po;
        po.threads = threads;
        const PipelineResult res = runInto(runs[i], *dirs[i], po, log);
        const fs::path src = dirs[i]->target() / "images" / g.picture;
        std::error_code ec;
        if (!fs::is_regular_file(src, ec))
            throw RuntimeError(src.string() + ": the run of " + g.scenario + " drew no " + g.picture +
                               " (its [output] settings leave the picture out)");
        pictures.push_back({geologyPictureName(g.scenario), readFileBytes(src)});
        results.push_back({g.scenario, g.view, res.report});
    }
    writeDocs(target, pictures, geologySettingsMarkdown(results, threads));
    if (log)
        log("wrote " + target.doc.string() + ", " + std::to_string(pictures.size()) + " picture(s) in " +
            target.imageDir.string() + " and " + std::to_string(runs.size()) + " run(s) under " + opt.outDir);
}

void reproducePaper(const ReproduceOptions& opt, const LogFn& log) {
    const fs::path scenarios(opt.scenarioDir);
    checkScenarioDir(scenarios);
    // Check every scenario before running any, so a typo costs nothing.
    std::vector<std::pair<const Figure*, Scenario>> runs;
    std::vector<std::string> names;
    for (const Figure& f : kFigures) {
        runs.push_back({&f, readScenario(scenarios, f.scenario, "figure scenario", std::nullopt)});
        names.push_back(runs.back().second.name);
    }
    const DocTarget target = checkedDocTarget(opt.docPath);
    std::vector<std::unique_ptr<OutputDir>> dirs = checkedRunDirs(opt.outDir, names);
    const int threads = opt.threads > 0 ? opt.threads : int(tbb::info::default_concurrency());
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    std::vector<StagedPicture> pictures;

    std::ostringstream md;
    md << "# Reproducing Pytel & Mann (JCGT 2015)\n\n"
          "Generated by `cavesim reproduce` ("
       << threads
       << " thread(s)); every number below is measured from the "
          "runs it made. Pictures are copied from the run folders into `docs/images/`. Definitions of the "
          "network counts: [network-definitions.md](network-definitions.md); choices our reading of the paper "
          "had to make: [model.md](model.md).\n\n";
    std::vector<std::pair<std::string, nlohmann::json>> reports;
    // Table 4 both ways: the paper's Figures 10–12 show the protochannels beside the channels and
    // do not say which of them its indices measure, so the caves are also measured with the
    // protochannels as side passages (the same simulation, measured twice).
    std::vector<std::pair<std::string, nlohmann::json>> withProto;
    const auto say = [&log](const std::string& m) {
        if (log) log(m);
    };

    for (std::size_t i = 0; i < runs.size(); ++i) {
        const auto& [fig, s] = runs[i];
        const fs::path out = dirs[i]->target();
        PipelineOptions po;
        po.threads = threads;
        if (paperCave(s.name) && s.output.cave == CaveExtent::kChannels)
            po.alsoMeasure = CaveExtent::kWithProtochannels;
        const PipelineResult res = runInto(s, *dirs[i], po, log);
        const nlohmann::json& r = res.report;
        reports.push_back({s.name, r});
        if (!res.alsoMeasured.is_null()) withProto.push_back({s.name, res.alsoMeasured});

        md << "## " << fig->title << "\n\n**Paper.** " << fig->paper << "\n\n**Ours** (`scenarios/" << fig->scenario
           << ".toml`, " << s.size[0] << "×" << s.size[1] << "×" << s.size[2] << " voxels of " << s.voxelSize << " m, "
           << fmt(reportValue(r, {"timing_s", "total"})) << " s). ";
        if (!reportValue(r, {"stage1"}).is_null())
            md << "Stage 1: zone voxels per source " << reportValue(r, {"stage1", "zone_voxels"}).dump() << ", "
               << fmt(reportValue(r, {"stage1", "protochannel_voxels"})) << " protochannel voxels. ";
        if (!reportValue(r, {"stage2"}).is_null())
            md << "Stage 2: breakthrough at iteration " << fmt(reportValue(r, {"stage2", "breakthrough_iteration"}))
               << ", sources joined a sink at iterations "
               << reportValue(r, {"stage2", "source_connected_iteration"}).dump() << "; "
               << fmt(reportValue(r, {"network", "sources_connected"})) << " of "
               << fmt(reportValue(r, {"network", "sources_total"})) << " sources connected, "
               << fmt(reportValue(r, {"network", "tributary_captures"})) << " tributary capture(s), "
               << fmt(reportValue(r, {"network", "phreatic_loops"})) << " phreatic loop(s), "
               << fmt(reportValue(r, {"network", "confluences"})) << " confluence(s). ";
        md << "\n\n";
        for (const char* pic : fig->pictures) {
            if (!pic) continue;
            const fs::path src = out / "images" / pic;
            if (!fs::exists(src)) continue;
            const std::string name = s.name + "_" + pic;
            pictures.push_back({name, readFileBytes(src)});
            md << "![" << s.name << " " << pic << "](images/" << name << ")\n";
        }
        md << "\n";
    }

    auto table4 = [&](const std::vector<std::pair<std::string, nlohmann::json>>& rs) {
        md << "| index | fig10 ours | fig10 paper | fig11 ours | fig11 paper | fig12 ours | fig12 paper |\n"
              "|---|---|---|---|---|---|---|\n";
        for (int row = 0; row < 4; ++row) {
            const char* key = kIndexRows[row].key;
            md << "| " << kIndexRows[row].label << " |";
            for (const char* name : {"fig10", "fig11", "fig12"}) {
                std::string ours = "–";
                for (const auto& [n, r] : rs) {
                    if (n != name) continue;
                    const auto& m = reportValue(r, {"morphometry"});
                    if (row == 3)
                        ours = fmt(reportValue(m, {key}));
                    else
                        ours = fmt(reportValue(m, {(std::string(key) + "_opt").c_str()})) + " (" +
                               fmt(reportValue(m, {(std::string(key) + "_rect").c_str()})) + ")";
                }
                md << " " << ours << " | " << paperIndexText(*paperCave(name), row) << " |";
            }
            md << "\n";
        }
    };
    // The published ranges as text, from their one copy in morpho/reference_ranges.h.
    const auto rangeList = [](const char* category, int table, const auto& keys) {
        std::string out;
        for (const char* k : keys) {
            const morpho::ReferenceRange* r = morpho::findReferenceRange(k, category, table);
            if (!r) continue;
            char buf[160];
            std::snprintf(buf, sizeof buf, "%s%s %g–%g", out.empty() ? "" : ", ", r->meaning, r->low, r->high);
            out += buf;
        }
        return out;
    };
    md << "## Table 4: morphometric indices\n\nOurs: Klimchouk's optimised cave field (rectangular field in "
          "parentheses); the paper's values from its Table 4. The optimised field encloses the cave with a margin of "
          "half the mean passage spacing: the plan cells, and every cell whose centre lies within S/2 of a plan "
          "cell's centre and inside the plan's convex hull, S = hull area / cave length (`src/morpho/morphometry.h`). "
          "The paper's Table 4 is not self-consistent: network density is length / field and areal coverage is "
          "plan area / field, so density should equal coverage / W; for Figure 10 that is 46.51 % / 2.28 m = "
          "0.204 m/m², not the 0.317 printed (0.122 with the rectangular field, against 17.94 % / 2.28 m = 0.0787). "
          "Confined ranges (paper Table 2): "
       << rangeList("confined", 2,
                    std::initializer_list<const char*>{"network_density_opt", "areal_coverage_pct_opt",
                                                       "porosity_pct_opt", "mean_width_m"})
       << ".\n\nThe cave as the stage-2 channels (the default, `" << caveSetting(CaveExtent::kChannels) << "`):\n\n";
    table4(reports);
    md << "\nRectangle / optimised field (rectangle / convex hull): ";
    for (const auto& [n, r] : reports) {
        const nlohmann::json& rect = reportValue(r, {"morphometry", "a_field_rect_m2"});
        const nlohmann::json& opt = reportValue(r, {"morphometry", "a_field_opt_m2"});
        const nlohmann::json& hull = reportValue(r, {"morphometry", "a_field_hull_m2"});
        if (!rect.is_number() || !opt.is_number() || !hull.is_number() || opt.get<double>() <= 0 ||
            hull.get<double>() <= 0)
            continue;
        md << n << " " << fmt(nlohmann::json(rect.get<double>() / opt.get<double>())) << " ("
           << fmt(nlohmann::json(rect.get<double>() / hull.get<double>())) << "); ";
    }
    md << "the paper's Figure 10: 0.317 / 0.122 = 2.6 (from its densities).\n";
    md << "\nThe same runs with the stage-1 protochannels as side passages (`"
       << caveSetting(CaveExtent::kWithProtochannels)
       << "`; the paper's Figures 10–12 show both kinds of channel and its text does not "
          "say which its indices measure):\n\n";
    table4(withProto);
    md << "\nCave category from the indices (channels; with protochannels): ";
    for (const auto& [n, r] : reports)
        for (const auto& [n2, r2] : withProto)
            if (n == n2)
                md << n << " " << fmt(reportValue(r, {"cave_category"})) << "; "
                   << fmt(reportValue(r2, {"cave_category"})) << ". ";
    md << "\n\n## Network metrics (Collon et al. 2017)\n\nReal caves (34 networks): "
       << rangeList("real caves", 0, kNetworkMetricKeys)
       << ".\n\n| scenario | h_or | len_mean_m | cv_len | h_len | "
          "k_mean | r_k | spl | cpd | tortuosity |\n|---|---|---|---|---|---|---|---|---|---|\n";
    auto metricsRow = [&](const std::string& label, const nlohmann::json& r) {
        md << "| " << label << " |";
        for (const char* k : kNetworkMetricKeys) md << " " << fmt(reportValue(r, {"graph_metrics", k})) << " |";
        md << "\n";
    };
    for (const auto& [n, r] : reports) metricsRow(n, r);
    for (const auto& [n, r] : withProto) metricsRow(n + " with protochannels", r);
    md << "\n## Table 5: timings\n\nOurs on this machine (" << threads
       << " thread(s), one run; medians of repeated runs are in `bench/README.md`) beside the paper's "
          "single-threaded 2.5 GHz Athlon.\n\n| scenario | grid | stage 1 (s) | stage 2 (s) | whole run (s) | paper "
          "stage 1 | paper stage 2 |\n|---|---|---|---|---|---|---|\n";
    for (const auto& [n, r] : reports) {
        const PaperCave* p = paperCave(n);
        const char* p1 = p ? p->stage1Time : "–";
        const char* p2 = p ? p->stage2Time : "–";
        md << "| " << n << " | " << reportValue(r, {"grid"}).dump() << " | "
           << fmt(reportValue(r, {"timing_s", "stage1"})) << " | " << fmt(reportValue(r, {"timing_s", "stage2"}))
           << " | " << fmt(reportValue(r, {"timing_s", "total"})) << " | " << p1 << " | " << p2 << " |\n";
    }
    writeDocs(target, pictures, md.str());
    say("wrote " + target.doc.string() + " and " + std::to_string(reports.size()) + " run(s) under " + opt.outDir);
}

}  // namespace

std::string reproduceDefaultOut(ReproduceSet set) {
    return set == ReproduceSet::kGeology ? "out/geology" : "out/reproduce";
}

std::string reproduceDefaultDoc(ReproduceSet set) {
    return set == ReproduceSet::kGeology ? "docs/geology_settings.md" : "docs/reproduction.md";
}

void reproduce(const ReproduceOptions& options, const LogFn& log) {
    ReproduceOptions opt = options;
    if (opt.outDir.empty()) opt.outDir = reproduceDefaultOut(opt.set);
    if (opt.docPath.empty()) opt.docPath = reproduceDefaultDoc(opt.set);
    if (opt.set == ReproduceSet::kGeology)
        reproduceGeology(opt, log);
    else
        reproducePaper(opt, log);
}

}  // namespace cavesim::app

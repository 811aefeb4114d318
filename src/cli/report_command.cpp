// `cavesim report DIR` (rebuild the report of a run from its files) and `cavesim reproduce`
// (run the paper's figure scenarios and write docs/reproduction.md).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <tbb/global_control.h>
#include <tbb/info.h>

#include "cli/commands.h"
#include "cli/output_dir.h"
#include "cli/pipeline.h"
#include "cli/progress_bar.h"
#include "cli/report.h"
#include "core/error.h"
#include "mesh/vdb_io.h"
#include "morpho/analysis.h"
#include "sim/scenario_io.h"

namespace fs = std::filesystem;

namespace cavesim::cli {
namespace {

using Clock = std::chrono::steady_clock;

nlohmann::json readJsonIfPresent(const fs::path& path) {
    std::ifstream in(path);
    if (!in) return nlohmann::json::object();
    try {
        return nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
        throw InputError(path.string() + ": not valid JSON (" + e.what() + ")");
    }
}

/// A run's domain as it was written: grids from state.vdb, sources and sinks from the scenario.
Domain loadRunDomain(const fs::path& dir, const Scenario& s) {
    Rng rng(s.seed);
    Domain dom = buildDomain(s, rng);
    const std::string vdb = (dir / "state.vdb").string();
    dom.porosity = mesh::readVdbFloat(vdb, "porosity", dom.dims);
    dom.porosity0 = mesh::readVdbFloat(vdb, "porosity0", dom.dims);
    dom.zone = mesh::readVdbInt(vdb, "zone", dom.dims);
    const Grid3<std::int32_t> flags = mesh::readVdbInt(vdb, "flags", dom.dims);
    for (std::size_t v = 0; v < flags.size(); ++v) dom.flags[v] = std::uint8_t(flags[v]);
    if (s.stage2.enabled) {
        dom.pressure = mesh::readVdbFloat(vdb, "pressure", dom.dims);
        dom.flow = mesh::readVdbFloat(vdb, "flow", dom.dims);
        dom.water = mesh::readVdbFloat(vdb, "water", dom.dims);
    }
    return dom;
}

}  // namespace

int reportCommand(const std::string& dirArg) {
    const fs::path dir(dirArg);
    if (!fs::is_directory(dir))
        throw InputError(dirArg + ": not a directory; give the output directory of a `cavesim run`");
    for (const char* f : {"scenario.toml", "state.vdb"})
        if (!fs::exists(dir / f))
            throw InputError((dir / f).string() + ": missing; `cavesim report` needs the files a run writes");
    const auto t0 = Clock::now();
    const Scenario s = parseScenarioFile((dir / "scenario.toml").string());
    const Domain dom = loadRunDomain(dir, s);
    nlohmann::json report = readJsonIfPresent(dir / "report.json");

    // The stage-2 connection iterations date the captures; they come from the run's report.
    std::vector<std::optional<int>> connected;
    if (report.contains("stage2") && report["stage2"].is_object() &&
        report["stage2"].contains("source_connected_iteration")) {
        for (const auto& v : report["stage2"]["source_connected_iteration"])
            connected.push_back(v.is_number_integer() ? std::optional<int>(v.get<int>()) : std::nullopt);
    }
    const morpho::CaveAnalysis analysis = morpho::analyseCave(dom, connected);
    morpho::writeSkeletonFiles(analysis.skeleton, dir.string(), dom.voxelSize, dom.dims);
    const nlohmann::json a = analysisJson(analysis);
    report["scenario"] = s.name;
    report["grid"] = {s.size[0], s.size[1], s.size[2]};
    report["voxel_size_m"] = s.voxelSize;
    report["seed"] = s.seed;
    for (const char* k : {"network", "morphometry", "graph_metrics", "skeleton", "cave_category"}) report[k] = a[k];
    report["timing_s"]["report"] = std::chrono::duration<double>(Clock::now() - t0).count();
    writeFileAtomic((dir / "report.json").string(), report.dump(2) + "\n");
    writeFileAtomic((dir / "report.md").string(), buildReportMarkdown(s, report, dir.string()));
    std::printf("%s: rebuilt report.json, report.md and the skeleton files\n", dir.string().c_str());
    return 0;
}

}  // namespace cavesim::cli

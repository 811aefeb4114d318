// `cavesim report DIR`: rebuild the report of a run from its files.
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>
#include <sstream>
#include <stdexcept>

#include <unistd.h>

#include "app/commands.h"
#include "app/pipeline.h"
#include "app/report.h"
#include "app/state.h"
#include "core/error.h"
#include "core/timer.h"
#include "morpho/analysis.h"
#include "sim/scenario_io.h"
#include "site/site.h"

namespace fs = std::filesystem;

namespace cavesim::app {
namespace {

nlohmann::json readJsonIfPresent(const fs::path& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) return nlohmann::json::object();
    if (!fs::is_regular_file(path, ec)) throw InputError(path.string() + ": not a regular file");
    std::ifstream in(path);
    if (!in) throw InputError(path.string() + ": cannot be read");
    nlohmann::json j;
    try {
        // A report nests a few levels; ~100 000 would overflow the stack when written back.
        j = nlohmann::json::parse(in, [&](int depth, nlohmann::json::parse_event_t, nlohmann::json&) {
            if (depth > 64) throw InputError(path.string() + ": nested more than 64 levels deep: not a cavesim report");
            return true;
        });
    } catch (const nlohmann::json::exception& e) {
        throw InputError(path.string() + ": not valid JSON (" + e.what() + ")");
    }
    if (!j.is_object()) throw InputError(path.string() + ": not a cavesim report (a JSON object is expected)");
    return j;
}

}  // namespace

std::string rebuildReport(const std::string& dirArg) {
    const fs::path dir(dirArg);
    if (!fs::is_directory(dir))
        throw InputError(dirArg + ": not a directory; give the output directory of a `cavesim run`");
    for (const char* f : {"scenario.toml", kCheckedStateFile})
        if (!fs::exists(dir / f))
            throw InputError((dir / f).string() + ": missing; `cavesim report` needs the files a run writes");
    const Stopwatch t0;
    Scenario s = parseScenarioFile((dir / "scenario.toml").string());
    site::loadSite(s);  // a site run's sinkholes and springs are its terminals
    nlohmann::json report = readJsonIfPresent(dir / "report.json");
    // Everything this command rewrites must be a file (or absent), so it does not stop half-way.
    for (const char* f : {"report.json", "report.md", "skeleton.json", "skeleton_nodes.dat", "skeleton_links.dat"}) {
        std::error_code ec;
        if (fs::exists(dir / f, ec) && !fs::is_regular_file(dir / f, ec))
            throw InputError((dir / f).string() + ": not a regular file; `cavesim report` rewrites it");
    }
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
        throw InputError(dirArg + ": cannot write in it (" + std::strerror(errno) + ")");
    const Domain dom = loadState(dir, s, report);

    // The stage-2 connection iterations date the captures; they come from the run's report.
    std::vector<std::optional<int>> connected;
    if (report.contains("stage2") && report["stage2"].is_object() &&
        report["stage2"].contains("source_connected_iteration")) {
        for (const auto& v : report["stage2"]["source_connected_iteration"])
            connected.push_back(v.is_number_integer() ? std::optional<int>(v.get<int>()) : std::nullopt);
    }
    const Cave cave = makeCave(dom, s.output.cave);
    const morpho::CaveAnalysis analysis = analyseRun(cave, dom, s, connected);
    morpho::writeSkeletonFiles(analysis.skeleton, dir.string(), dom.voxelSize, dom.dims);
    report["scenario"] = s.name;
    report["grid"] = {s.size[0], s.size[1], s.size[2]};
    report["voxel_size_m"] = s.voxelSize;
    report["seed"] = s.seed;
    putAnalysis(report, analysisJson(analysis));
    if (!report["timing_s"].is_object()) report["timing_s"] = nlohmann::json::object();
    report["timing_s"]["report"] = t0.seconds();
    writeReportFiles(s, report, dir.string());
    return dir.string() + ": rebuilt report.json, report.md and the skeleton files";
}

}  // namespace cavesim::app

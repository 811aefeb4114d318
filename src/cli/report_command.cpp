// `cavesim report DIR` (rebuild the report of a run from its files) and `cavesim reproduce`
// (run the paper's figure scenarios and write docs/reproduction.md).
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

std::string shortNumber(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

/// The `# state.vdb: {...}` comment a run appends to its scenario.toml, or null.
nlohmann::json recordedInScenario(const fs::path& scenario) {
    std::ifstream in(scenario);
    const std::string tag = "# state.vdb: ";
    for (std::string line; std::getline(in, line);) {
        if (line.compare(0, tag.size(), tag) != 0) continue;
        if (line.size() > 4096) return nullptr;  // a record is one short line
        try {
            return nlohmann::json::parse(line.substr(tag.size()), [](int depth, nlohmann::json::parse_event_t,
                                                                     nlohmann::json&) {
                if (depth > 8) throw std::length_error("nested");
                return true;
            });
        } catch (const std::exception&) {
            return nullptr;
        }
    }
    return nullptr;
}

/// Throws unless every value of `g` satisfies `ok`: a grid that holds what no run writes is damage.
template <typename T, typename Ok>
void checkGrid(const Grid3<T>& g, const std::string& vdb, const char* name, const char* allowed, Ok ok) {
    for (std::size_t v = 0; v < g.size(); ++v)
        if (!ok(g[v]))
            throw InputError(vdb + ": grid '" + name + "' holds " + shortNumber(double(g[v])) + " at voxel " +
                             std::to_string(v) + " (" + allowed + "): the file is damaged; rerun `cavesim run`");
}

/// A run's domain as it was written: grids from state.vdb, sources and sinks from the scenario.
Domain loadRunDomain(const fs::path& dir, const Scenario& s, const nlohmann::json& report) {
    const std::string vdb = (dir / "state.vdb").string();
    // OpenVDB does not survive a damaged file: the run recorded the file's size, checksum and grid
    // in report.json and in the last line of scenario.toml; without a record the file is not read.
    std::error_code ec;
    if (!fs::is_regular_file(vdb, ec)) throw InputError(vdb + ": not a regular file; `cavesim report` needs the run's state.vdb");
    const auto usable = [](const nlohmann::json& r) {
        return r.is_object() && r.contains("bytes") && r["bytes"].is_number_unsigned() && r.contains("fnv1a64") &&
               r["fnv1a64"].is_string() && r.contains("grid") && r["grid"].is_array() && r["grid"].size() == 3 &&
               r.contains("voxel_size_m") && r["voxel_size_m"].is_number();
    };
    nlohmann::json then;
    if (report.contains("files") && report["files"].is_object() && report["files"].contains("state.vdb"))
        then = report["files"]["state.vdb"];
    if (!usable(then)) then = recordedInScenario(dir / "scenario.toml");
    if (!usable(then))
        throw InputError(vdb + ": no usable record of it (report.json `files` and the last line of scenario.toml "
                               "are missing or damaged), so it cannot be checked before reading; rerun `cavesim run`");
    const nlohmann::json now = fileFingerprint(vdb);
    if (now["bytes"] != then["bytes"] || now["fnv1a64"] != then["fnv1a64"])
        throw InputError(vdb + ": changed since the run wrote it (now " + now.dump() + ", the run recorded " +
                         then.dump() + "); rerun `cavesim run`");
    if (then["grid"] != nlohmann::json{s.size[0], s.size[1], s.size[2]} || then["voxel_size_m"] != s.voxelSize)
        throw InputError((dir / "scenario.toml").string() + ": describes a grid of " + std::to_string(s.size[0]) +
                         " x " + std::to_string(s.size[1]) + " x " + std::to_string(s.size[2]) + " voxels of " +
                         shortNumber(s.voxelSize) + " m, but the run's state.vdb holds " + then["grid"].dump() +
                         " of " + then["voxel_size_m"].dump() + " m: the scenario was edited; rerun `cavesim run`");
    Rng rng(s.seed);
    Domain dom = buildDomain(s, rng);
    try {
        dom.porosity = mesh::readVdbFloat(vdb, "porosity", dom.dims);
        dom.porosity0 = mesh::readVdbFloat(vdb, "porosity0", dom.dims);
        dom.zone = mesh::readVdbInt(vdb, "zone", dom.dims);
        const Grid3<std::int32_t> flags = mesh::readVdbInt(vdb, "flags", dom.dims);
        checkGrid(flags, vdb, "flags", "flags are 0-255", [](std::int32_t f) { return f >= 0 && f <= 255; });
        for (std::size_t v = 0; v < flags.size(); ++v) dom.flags[v] = std::uint8_t(flags[v]);
        if (s.stage2.enabled) {
            dom.pressure = mesh::readVdbFloat(vdb, "pressure", dom.dims);
            dom.flow = mesh::readVdbFloat(vdb, "flow", dom.dims);
            dom.water = mesh::readVdbFloat(vdb, "water", dom.dims);
        }
    } catch (const InputError&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw InputError(vdb + ": cannot be read (it asks for more memory than there is): the file is damaged");
    } catch (const std::exception& e) {
        throw InputError(vdb + ": cannot be read (" + e.what() + "): damaged, or not written by `cavesim run`");
    }
    const auto unit = [](float r) { return r >= 0.f && r <= 1.f; };  // false for NaN
    const auto nonNegative = [](float r) { return std::isfinite(r) && r >= 0.f; };
    checkGrid(dom.porosity, vdb, "porosity", "porosity is in [0, 1]", unit);
    checkGrid(dom.porosity0, vdb, "porosity0", "porosity is in [0, 1]", unit);
    const int nSources = int(s.sources.size());
    checkGrid(dom.zone, vdb, "zone", "zones are -1 or a source index",
              [nSources](std::int32_t z) { return z >= -1 && z < nSources; });
    checkGrid(dom.pressure, vdb, "pressure", "pressure is finite and not negative", nonNegative);
    checkGrid(dom.flow, vdb, "flow", "flow is finite and not negative", nonNegative);
    // Water is stored to round-off: a transfer that empties a voxel can leave -1e-18.
    checkGrid(dom.water, vdb, "water", "water is finite and not below -1e-6",
              [](float w) { return std::isfinite(w) && w >= -1e-6f; });
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
    nlohmann::json report = readJsonIfPresent(dir / "report.json");
    // Everything this command rewrites must be a file (or absent), so it does not stop half-way.
    for (const char* f : {"report.json", "report.md", "skeleton.json", "skeleton_nodes.dat", "skeleton_links.dat"}) {
        std::error_code ec;
        if (fs::exists(dir / f, ec) && !fs::is_regular_file(dir / f, ec))
            throw InputError((dir / f).string() + ": not a regular file; `cavesim report` rewrites it");
    }
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
        throw InputError(dirArg + ": cannot write in it (" + std::strerror(errno) + ")");
    const Domain dom = loadRunDomain(dir, s, report);

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
    if (!report["timing_s"].is_object()) report["timing_s"] = nlohmann::json::object();
    report["timing_s"]["report"] = std::chrono::duration<double>(Clock::now() - t0).count();
    writeFileAtomic((dir / "report.json").string(), report.dump(2) + "\n");
    writeFileAtomic((dir / "report.md").string(), buildReportMarkdown(s, report, dir.string()));
    std::printf("%s: rebuilt report.json, report.md and the skeleton files\n", dir.string().c_str());
    return 0;
}

}  // namespace cavesim::cli

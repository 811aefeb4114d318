// `cavesim ensemble`: members, their records, resume, and the summary.
#include "app/ensemble.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>
#include <random>
#include <sstream>
#include <thread>

#include <tbb/global_control.h>
#include <tbb/info.h>

#include "app/output_dir.h"
#include "app/report.h"
#include "app/state.h"
#include "core/atomic_file.h"
#include "core/check.h"
#include "core/error.h"
#include "core/fnv.h"
#include "formats/vtk_formats.h"
#include "mesh/vdb_io.h"
#include "render/ensemble_figures.h"
#include "render/png_io.h"
#include "sim/cave.h"
#include "sim/parameters.h"
#include "sim/scenario_io.h"
#include "site/site.h"

namespace fs = std::filesystem;

namespace cavesim::app {
namespace {

constexpr int kMaxMembers = 100000;
/// Mixed into a member's seed for the engine that draws its varied keys, so the draws are not the
/// first numbers of the engine the member's own run starts from.
constexpr std::uint64_t kVaryStream = 0x76617279ull;  // "vary"

std::uint64_t splitMix64(std::uint64_t z) {
    z ^= z >> 30;
    z *= 0xBF58476D1CE4E5B9ull;
    z ^= z >> 27;
    z *= 0x94D049BB133111EBull;
    z ^= z >> 31;
    return z;
}

std::string memberName(int i) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "m%04d", i);
    return buf;
}

/// The registry entry of a plain-table number key, or nulls.
std::pair<const ParamSection*, const Param*> numberKey(const std::string& key) {
    for (const ParamSection& s : scenarioParameters()) {
        if (s.isArray) continue;
        for (const Param& p : s.params)
            if (s.qualified(p.key) == key && (p.type == ParamType::kReal || p.type == ParamType::kInt)) return {&s, &p};
    }
    return {nullptr, nullptr};
}

std::string text(double v) {
    return paramValueText(ParamValue(v));
}

bool inRange(const ParamRange& r, double v) {
    return (r.loOpen ? v > r.lo : v >= r.lo) && (r.hiOpen ? v < r.hi : v <= r.hi);
}

nlohmann::json readJson(const fs::path& p) {
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) return nullptr;
    try {
        return nlohmann::json::parse(readFileBytes(p));
    } catch (const std::exception&) {
        return nullptr;
    }
}

std::string fingerprint(const Scenario& s) {
    const std::string t = scenarioToToml(s);
    Fnv1a64 h;
    h.add(t.data(), t.size());
    return h.hex();
}

/// Numbers of a report section, flattened to "section.key" (booleans and arrays left out).
void flatten(const nlohmann::json& j, const std::string& prefix, std::map<std::string, double>& out) {
    if (j.is_object()) {
        for (auto it = j.begin(); it != j.end(); ++it) flatten(it.value(), prefix + "." + it.key(), out);
    } else if (j.is_number()) {
        out[prefix] = j.get<double>();
    }
}

struct Stats {
    std::size_t n = 0;
    double mean = 0, sd = 0, min = 0, q1 = 0, median = 0, q3 = 0, max = 0;
};

double quantile(const std::vector<double>& sorted, double q) {
    const double at = q * double(sorted.size() - 1);
    const std::size_t lo = std::size_t(std::floor(at));
    const std::size_t hi = std::min(sorted.size() - 1, lo + 1);
    return sorted[lo] + (at - double(lo)) * (sorted[hi] - sorted[lo]);
}

Stats stats(std::vector<double> v) {
    Stats s;
    s.n = v.size();
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    double sum = 0;
    for (double x : v) sum += x;
    s.mean = sum / double(v.size());
    double ss = 0;
    for (double x : v) ss += (x - s.mean) * (x - s.mean);
    s.sd = v.size() > 1 ? std::sqrt(ss / double(v.size() - 1)) : 0.0;
    s.min = v.front();
    s.max = v.back();
    s.q1 = quantile(v, 0.25);
    s.median = quantile(v, 0.5);
    s.q3 = quantile(v, 0.75);
    return s;
}

std::string fmt(const nlohmann::json& v) {
    if (!v.is_number()) return "–";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", v.get<double>());
    return buf;
}

/// Checks the ensemble folder before any work: new, empty, or an earlier ensemble's.
void checkEnsembleDir(const fs::path& out) {
    std::error_code ec;
    if (!fs::exists(out, ec)) return;
    if (!fs::is_directory(out, ec)) throw InputError(out.string() + ": exists and is not a directory");
    if (fs::is_empty(out, ec)) return;
    if (fs::is_directory(out / "members", ec) || fs::is_regular_file(out / "ensemble.json", ec)) return;
    throw InputError(out.string() +
                     ": not empty and not an ensemble folder (no members/ or ensemble.json); choose another --out");
}

}  // namespace

VaryRange parseVary(const std::string& t) {
    const std::string what = "--vary " + t;
    const std::size_t eq = t.find('=');
    if (eq == std::string::npos || eq == 0)
        throw InputError(what + ": must be KEY=LOW:HIGH or KEY=LOW:HIGH:uniform|log (e.g. stage2.p_rate=0.2:0.6)");
    VaryRange v;
    v.key = t.substr(0, eq);
    std::vector<std::string> parts;
    std::stringstream rest(t.substr(eq + 1));
    for (std::string piece; std::getline(rest, piece, ':');) parts.push_back(piece);
    if (parts.size() < 2 || parts.size() > 3)
        throw InputError(what + ": must be KEY=LOW:HIGH or KEY=LOW:HIGH:uniform|log (e.g. stage2.p_rate=0.2:0.6)");
    const auto [section, param] = numberKey(v.key);
    if (!param)
        throw InputError(what + ": '" + v.key +
                         "' is not a number key of a scenario table (see docs/scenario-format.md; e.g. stage2.p_rate)");
    if (section->path == "domain" || section->path.empty())
        throw InputError(what + ": '" + v.key + "' cannot vary: every member has the ensemble's grid and seed rule");
    v.integer = param->type == ParamType::kInt;
    auto number = [&](const std::string& x) {
        try {
            std::size_t used = 0;
            const double d = std::stod(x, &used);
            if (used != x.size() || !std::isfinite(d)) throw std::invalid_argument(x);
            return d;
        } catch (const std::exception&) {
            throw InputError(what + ": '" + x + "' is not a number");
        }
    };
    v.lo = number(parts[0]);
    v.hi = number(parts[1]);
    if (v.lo > v.hi) throw InputError(what + ": LOW " + parts[0] + " is above HIGH " + parts[1]);
    for (double x : {v.lo, v.hi})
        if (!inRange(param->range, x))
            throw InputError(what + ": " + text(x) + " is outside the allowed range of '" + v.key + "', " +
                             paramRangeText(*param));
    if (parts.size() == 3) {
        if (parts[2] == "log")
            v.law = VaryLaw::kLogUniform;
        else if (parts[2] == "uniform")
            v.law = VaryLaw::kUniform;
        else
            throw InputError(what + ": law '" + parts[2] + "' must be uniform or log");
    } else {
        v.law = param->key.find("rate") != std::string::npos && v.lo > 0 ? VaryLaw::kLogUniform : VaryLaw::kUniform;
    }
    if (v.law == VaryLaw::kLogUniform && v.lo <= 0) throw InputError(what + ": a log-uniform range needs LOW > 0");
    return v;
}

std::uint64_t memberSeed(std::uint64_t scenarioSeed, int member) {
    return splitMix64(scenarioSeed + std::uint64_t(member + 1) * 0x9E3779B97F4A7C15ull) >> 1;
}

Scenario memberScenario(const Scenario& base, int member, const std::vector<VaryRange>& vary, nlohmann::json* values) {
    Scenario s = base;
    s.seed = memberSeed(base.seed, member);
    std::mt19937_64 draw(s.seed ^ kVaryStream);
    if (values) *values = nlohmann::json::object();
    for (const VaryRange& v : vary) {
        const double u = double(draw()) * 0x1p-64;
        double x = v.law == VaryLaw::kLogUniform ? v.lo * std::pow(v.hi / v.lo, u) : v.lo + u * (v.hi - v.lo);
        x = std::clamp(x, v.lo, v.hi);
        const auto [section, param] = numberKey(v.key);
        CAVESIM_CHECK(param, "a varied key that parseVary accepted is not in the registry");
        void* record = section->mutableRecord(s, 0);
        if (v.integer) {
            const auto n = std::int64_t(std::llround(x));
            param->set(record, ParamValue(n));
            if (values) (*values)[v.key] = n;
        } else {
            param->set(record, ParamValue(x));
            if (values) (*values)[v.key] = x;
        }
    }
    try {
        validateScenario(s);
    } catch (const InputError& e) {
        throw InputError("member " + std::to_string(member) + ": " + e.what());
    }
    return s;
}

std::string memberChecksum(const fs::path& dir) {
    std::vector<fs::path> files;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        if (!e.is_regular_file()) continue;
        const fs::path rel = fs::relative(e.path(), dir);
        if (rel == "report.json" || rel == "report.md" || rel == "report.html") continue;  // timings
        files.push_back(rel);
    }
    std::sort(files.begin(), files.end(),
              [](const fs::path& a, const fs::path& b) { return a.generic_string() < b.generic_string(); });
    Fnv1a64 h;
    for (const fs::path& rel : files) {
        const std::string name = rel.generic_string();
        h.add(name.data(), name.size() + 1);  // with the terminating 0
        const std::string bytes = readFileBytes(dir / rel);
        const std::uint64_t n = bytes.size();
        h.add(&n, sizeof n);
        h.add(bytes.data(), bytes.size());
    }
    return h.hex();
}

EnsembleOutcome runEnsemble(const EnsembleRequest& request, const Communicator& comm, const LogFn& log) {
    Scenario base = parseScenarioFile(request.scenarioPath);
    site::loadSite(base);  // read once; the members share it
    if (request.members < 1 || request.members > kMaxMembers)
        throw InputError("--members " + std::to_string(request.members) + ": must be 1–" + std::to_string(kMaxMembers));
    std::vector<VaryRange> vary;
    for (const std::string& t : request.vary) {
        vary.push_back(parseVary(t));
        for (std::size_t i = 0; i + 1 < vary.size(); ++i)
            if (vary[i].key == vary.back().key)
                throw InputError("--vary " + t + ": '" + vary.back().key + "' is varied twice");
    }
    // Every member's seed and draws must give a valid scenario (p_rate_channel at most p_rate,
    // snapshots the run reaches, sinkholes that fit, ...): checked for all members before anything
    // is written, so a request that makes an impossible member is refused with exit 2 instead of
    // failing members one by one.
    for (int i = 0; i < request.members; ++i) {
        try {
            (void)memberScenario(base, i, vary);
        } catch (const InputError& e) {
            std::string ranges;
            for (const std::string& t : request.vary) ranges += " --vary " + t;
            throw InputError(std::string(e.what()) + " (seed " + std::to_string(memberSeed(base.seed, i)) +
                             (ranges.empty() ? std::string() : ", drawn by" + ranges) + ")");
        }
    }
    const fs::path out =
        fs::absolute(request.outDir.empty() ? fs::path("out") / (base.name + "_ensemble") : fs::path(request.outDir))
            .lexically_normal();
    checkEnsembleDir(out);
    const fs::path membersDir = out / "members";
    std::error_code ec;
    fs::create_directories(membersDir, ec);
    if (!fs::is_directory(membersDir))
        throw InputError(membersDir.string() + ": cannot be created (" + ec.message() + ")");

    const int threads = request.threads > 0
                            ? request.threads
                            : std::max(1, int(tbb::info::default_concurrency()) / std::max(1, comm.localRanks));
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));

    // This rank's members, and which of them are already finished.
    EnsembleOutcome outcome;
    outcome.out = out;
    outcome.members = request.members;
    std::vector<int> pending;
    for (int i = comm.rank; i < request.members; i += comm.size) {
        const nlohmann::json rec = readJson(membersDir / (memberName(i) + ".json"));
        bool done = false;
        if (rec.is_object() && rec.value("status", "") == "ok") {
            try {
                const Scenario ms = memberScenario(base, i, vary);
                const fs::path dir = membersDir / memberName(i);
                done = rec.value("scenario_fnv1a64", "") == fingerprint(ms) && fs::is_directory(dir) &&
                       rec.value("checksum", "") == memberChecksum(dir);
            } catch (const std::exception&) {
                done = false;
            }
        }
        if (done)
            ++outcome.skipped;
        else
            pending.push_back(i);
    }
    if (log && outcome.skipped > 0)
        log("rank " + std::to_string(comm.rank) + ": " + std::to_string(outcome.skipped) +
            " member(s) already finished, kept");

    std::mutex logMutex;
    auto say = [&](const std::string& m) {
        if (!log) return;
        std::lock_guard<std::mutex> lock(logMutex);
        log(m);
    };
    std::atomic<std::size_t> next{0};
    std::atomic<int> failed{0};
    auto worker = [&]() {
        for (std::size_t n = next++; n < pending.size(); n = next++) {
            const int i = pending[n];
            nlohmann::json rec = {{"member", i}, {"seed", memberSeed(base.seed, i)}};
            try {
                nlohmann::json values;
                const Scenario ms = memberScenario(base, i, vary, &values);
                rec["values"] = values;
                rec["scenario_fnv1a64"] = fingerprint(ms);
                const fs::path dir = membersDir / memberName(i);
                OutputDir od(dir, true);
                od.open();
                PipelineOptions options;
                options.threads = threads;
                const PipelineResult r = runPipeline(ms, od, options);
                od.commit();
                rec["status"] = "ok";
                rec["checksum"] = memberChecksum(dir);
                rec["breakthrough_iteration"] =
                    r.breakthroughIteration ? nlohmann::json(*r.breakthroughIteration) : nlohmann::json(nullptr);
                say(memberName(i) + ": ok, checksum " + rec["checksum"].get<std::string>());
            } catch (const std::exception& e) {
                rec["status"] = "failed";
                rec["error"] = e.what();
                ++failed;
                say(memberName(i) + ": failed: " + e.what());
            }
            try {
                writeFileAtomic((membersDir / (memberName(i) + ".json")).string(), rec.dump(2) + "\n");
            } catch (const std::exception& e) {
                say(memberName(i) + ": record not written: " + e.what());
            }
        }
    };
    const int parallel = std::max(1, std::min(request.parallel > 0 ? request.parallel : threads, int(pending.size())));
    if (!pending.empty()) {
        std::vector<std::thread> pool;
        for (int t = 1; t < parallel; ++t) pool.emplace_back(worker);
        worker();
        for (auto& t : pool) t.join();
    }
    outcome.ran = int(pending.size());
    outcome.failed = failed;
    outcome.ok = outcome.ran - outcome.failed + outcome.skipped;

    if (comm.barrier) comm.barrier();
    if (comm.rank == 0) {
        const nlohmann::json summary = summariseEnsemble(out, base, request.members, vary, log);
        outcome.ok = summary["ok"].get<int>();
        outcome.failed = summary["failed"].get<int>();
        outcome.summary = true;
    }
    return outcome;
}

nlohmann::json summariseEnsemble(const fs::path& out, const Scenario& base, int members,
                                 const std::vector<VaryRange>& vary, const LogFn& log) {
    const fs::path membersDir = out / "members";
    const Dims dims{base.size[0], base.size[1], base.size[2]};
    Grid3<std::uint32_t> caveCount(dims, 0);
    std::map<std::string, std::vector<double>> metrics;
    std::map<std::string, std::map<std::string, int>> classes;
    nlohmann::json records = nlohmann::json::array();
    int ok = 0, failed = 0, missing = 0, breakthrough = 0;
    for (int i = 0; i < members; ++i) {
        nlohmann::json rec = readJson(membersDir / (memberName(i) + ".json"));
        if (!rec.is_object() || !rec.contains("status")) {
            ++missing;
            records.push_back({{"member", i}, {"status", "missing"}});
            continue;
        }
        if (rec["status"] != "ok") {
            ++failed;
            records.push_back(rec);
            continue;
        }
        const fs::path dir = membersDir / memberName(i);
        try {
            const nlohmann::json report = readJson(dir / "report.json");
            if (!report.is_object()) throw InputError((dir / "report.json").string() + ": missing or damaged");
            const Scenario ms = memberScenario(base, i, vary);
            const Domain dom = loadState(dir, ms, report);
            const Grid3<std::uint8_t> mask = caveMask(dom, ms.output.cave);
            for (std::size_t v = 0; v < mask.size(); ++v) caveCount[v] += mask[v] ? 1u : 0u;
            std::map<std::string, double> m;
            for (const char* k : {"network", "morphometry", "graph_metrics"})
                if (report.contains(k)) flatten(report[k], k, m);
            const nlohmann::json& st2 = report.contains("stage2") ? report["stage2"] : nlohmann::json(nullptr);
            if (st2.is_object() && st2.contains("breakthrough_iteration") &&
                st2["breakthrough_iteration"].is_number()) {
                ++breakthrough;
                m["stage2.breakthrough_iteration"] = st2["breakthrough_iteration"].get<double>();
            }
            for (const auto& [k, x] : m) metrics[k].push_back(x);
            for (auto it = report.begin(); it != report.end(); ++it)
                if ((it.key() == "cave_category" || it.key().rfind("pattern", 0) == 0) && it.value().is_string())
                    ++classes[it.key()][it.value().get<std::string>()];
            ++ok;
        } catch (const std::exception& e) {
            ++failed;
            rec["status"] = "failed";
            rec["error"] = std::string("its files cannot be summarised: ") + e.what();
        }
        rec.erase("scenario_fnv1a64");
        records.push_back(rec);
    }

    Grid3<float> probability(dims, 0.f);
    if (ok > 0)
        for (std::size_t v = 0; v < probability.size(); ++v) probability[v] = float(double(caveCount[v]) / ok);
    std::size_t everCave = 0;
    for (std::uint32_t c : caveCount.data) everCave += c > 0 ? 1 : 0;

    std::error_code ec;
    fs::create_directories(out / "images", ec);
    const int width = 640;
    nlohmann::json metricsJson = nlohmann::json::object();
    for (const auto& [key, values] : metrics) {
        const Stats s = stats(values);
        std::string stem = key;
        std::replace(stem.begin(), stem.end(), '.', '_');
        const std::string file = "images/hist_" + stem + ".png";
        const int bins = std::clamp(int(std::ceil(std::sqrt(double(values.size())))), 1, 20);
        render::writePng((out / file).string(), render::histogramFigure(values, key, "", bins, width));
        const auto num = jsonNumber;
        metricsJson[key] = {{"n", s.n},          {"mean", num(s.mean)}, {"sd", num(s.sd)},
                            {"min", num(s.min)}, {"q1", num(s.q1)},     {"median", num(s.median)},
                            {"q3", num(s.q3)},   {"max", num(s.max)},   {"histogram", file}};
    }
    const std::array<double, 3> origin{base.site.origin[0], base.site.origin[1], base.site.origin[2]};
    const std::string vdb = (out / "probability.vdb").string(), vti = (out / "probability.vti").string();
    mesh::writeVdb(vdb,
                   {mesh::NamedGrid{"probability", &probability, nullptr,
                                    "fraction of the ensemble's members in which the voxel is cave"}},
                   base.voxelSize, origin);
    formats::writeScalarVti(probability, "probability", "1 (fraction of members in which the voxel is cave)",
                            base.voxelSize, origin, vti);
    // The terminals' columns (box centres), the site's sinkholes and springs included.
    std::vector<std::array<double, 2>> sources, sinks;
    auto centre = [](const VoxelBox& b) {
        return std::array<double, 2>{0.5 * (b.lo[0] + b.hi[0]), 0.5 * (b.lo[1] + b.hi[1])};
    };
    for (const SourceSpec& t : base.sources) sources.push_back(centre(t.box));
    for (const SinkSpec& t : base.sinks) sinks.push_back(centre(t.box));
    if (base.siteData) {
        for (const SourceSpec& t : base.siteData->sources) sources.push_back(centre(t.box));
        for (const SinkSpec& t : base.siteData->sinks) sinks.push_back(centre(t.box));
    }
    render::writePng(
        (out / "images/probability_plan.png").string(),
        render::probabilityPlanFigure(probability, base.voxelSize, origin[0], origin[1],
                                      base.name + ": karstification probability (" + std::to_string(ok) + " members)",
                                      900, sources, sinks));

    nlohmann::json varyJson = nlohmann::json::array();
    for (const VaryRange& v : vary)
        varyJson.push_back({{"key", v.key},
                            {"low", v.lo},
                            {"high", v.hi},
                            {"law", v.law == VaryLaw::kLogUniform ? "log-uniform" : "uniform"}});
    nlohmann::json j;
    j["scenario"] = base.name;
    j["scenario_file"] = base.path;
    j["seed"] = base.seed;
    j["seed_rule"] = "member i: SplitMix64(seed + (i + 1) * 0x9E3779B97F4A7C15) >> 1";
    j["members"] = members;
    j["ok"] = ok;
    j["failed"] = failed;
    j["missing"] = missing;
    j["vary"] = varyJson;
    j["breakthrough"] = {{"members", breakthrough}, {"fraction", ok > 0 ? double(breakthrough) / ok : 0.0}};
    j["classes"] = classes;
    j["metrics"] = metricsJson;
    j["probability"] = {{"grid", {dims.nx, dims.ny, dims.nz}},
                        {"voxel_size_m", base.voxelSize},
                        {"world_origin_m", origin},
                        {"voxels_cave_in_any_member", everCave},
                        {"files", {"probability.vdb", "probability.vti", "images/probability_plan.png"}}};
    j["member_records"] = records;
    writeFileAtomic((out / "ensemble.json").string(), j.dump(2) + "\n");

    std::ostringstream md;
    md << "# cavesim ensemble: " << base.name << "\n\n"
       << members << " member(s) of `" << base.path << "` (seed " << base.seed << "; member i's seed is "
       << "SplitMix64(seed + (i + 1) · 0x9E3779B97F4A7C15) >> 1): **" << ok << " ok**, " << failed << " failed, "
       << missing << " not run. " << breakthrough << " of " << ok << " break through.\n\n";
    if (!vary.empty()) {
        md << "## Varied keys\n\n| key | low | high | law |\n|---|---|---|---|\n";
        for (const auto& v : varyJson)
            md << "| `" << v["key"].get<std::string>() << "` | " << fmt(v["low"]) << " | " << fmt(v["high"]) << " | "
               << v["law"].get<std::string>() << " |\n";
        md << "\n";
    }
    md << "## Karstification probability\n\nFraction of the ok members in which each voxel is cave: "
          "`probability.vdb` (grid `probability`), `probability.vti` (cell array `probability`). "
       << everCave << " voxel(s) are cave in at least one member. Plan view (largest along each column):\n\n"
       << "![probability](images/probability_plan.png)\n\n";
    if (!classes.empty()) {
        md << "## Classes\n\n| class | value | members |\n|---|---|---|\n";
        for (const auto& [k, counts] : classes)
            for (const auto& [name, n] : counts) md << "| " << k << " | " << name << " | " << n << " |\n";
        md << "\n";
    }
    md << "## Measures\n\n| measure | n | mean | sd | min | q1 | median | q3 | max | histogram |\n"
          "|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& [key, s] : metricsJson.items())
        md << "| `" << key << "` | " << s["n"] << " | " << fmt(s["mean"]) << " | " << fmt(s["sd"]) << " | "
           << fmt(s["min"]) << " | " << fmt(s["q1"]) << " | " << fmt(s["median"]) << " | " << fmt(s["q3"]) << " | "
           << fmt(s["max"]) << " | [png](" << s["histogram"].get<std::string>() << ") |\n";
    md << "\n## Members\n\n| member | seed | status | values / error |\n|---|---|---|---|\n";
    for (const auto& r : records) {
        md << "| " << r["member"] << " | " << (r.contains("seed") ? r["seed"].dump() : "–") << " | "
           << r.value("status", "") << " | ";
        if (r.contains("error"))
            md << r["error"].get<std::string>();
        else if (r.contains("values"))
            md << r["values"].dump();
        md << " |\n";
    }
    writeFileAtomic((out / "ensemble.md").string(), md.str());
    if (log)
        log("ensemble: " + std::to_string(ok) + " ok, " + std::to_string(failed) + " failed, " +
            std::to_string(missing) + " not run; summary in " + (out / "ensemble.md").string());
    return j;
}

}  // namespace cavesim::app

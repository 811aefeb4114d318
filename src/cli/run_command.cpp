// `cavesim run`, `cavesim validate`: the pipeline of DESIGN §1 from scenario to report.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>

#include <tbb/global_control.h>
#include <tbb/info.h>

#include "cli/commands.h"
#include "cli/output_dir.h"
#include "cli/pipeline.h"
#include "cli/progress_bar.h"
#include "core/error.h"
#include "sim/scenario_io.h"

namespace fs = std::filesystem;

namespace cavesim::cli {

int validateCommand(const std::string& path) {
    const Scenario s = parseScenarioFile(path);
    std::printf("%s: ok: scenario '%s', grid %d x %d x %d (%.3g m voxels), %zu source(s), %zu sink(s), stage 1 %s, stage 2 %s\n",
                path.c_str(), s.name.c_str(), s.size[0], s.size[1], s.size[2], s.voxelSize, s.sources.size(),
                s.sinks.size(), s.stage1.enabled ? "on" : "off",
                s.stage2.enabled ? (std::to_string(s.stage2.iterations) + " iterations").c_str() : "off");
    return 0;
}

int runCommand(const RunOptions& opt) {
    Scenario s = opt.scenarioPath ? parseScenarioFile(*opt.scenarioPath) : defaultScenario();
    if (opt.seed) {
        // Digits only (no sign, no wrap-around), at most 2^63 - 1: the effective scenario.toml must
        // hold the seed and reproduce the run.
        const std::string& text = *opt.seed;
        const std::string digits = text.size() > 1 ? text.substr(std::min(text.find_first_not_of('0'), text.size() - 1)) : text;
        const std::string allowed = ": must be a whole number in [0, " +
                                    std::to_string(std::numeric_limits<std::int64_t>::max()) + "]";
        if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || digits.size() > 19)
            throw InputError("--seed " + text + allowed);
        const unsigned long long v = std::stoull(digits);
        if (v > std::uint64_t(std::numeric_limits<std::int64_t>::max())) throw InputError("--seed " + text + allowed);
        s.seed = v;
    }
    if (!opt.meshStyle.empty()) s.output.meshStyle = opt.meshStyle;
    validateScenario(s);

    const fs::path out = opt.outDir.empty() ? fs::path("out") / s.name : fs::path(opt.outDir);
    OutputDir dir(out, opt.force);  // refuses a non-empty directory before any work

    const int threads = opt.threads > 0 ? opt.threads : int(tbb::info::default_concurrency());
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));

    ProgressBar bar(opt.quiet);
    bar.log("scenario '" + s.name + "' (" + s.path + "), grid " + std::to_string(s.size[0]) + "x" +
            std::to_string(s.size[1]) + "x" + std::to_string(s.size[2]) + ", seed " + std::to_string(s.seed) +
            ", " + std::to_string(threads) + " thread(s)");
    dir.open();
    PipelineResult result = runPipeline(s, threads, dir, bar);
    dir.commit();
    bar.log("wrote " + out.string() + " in " + std::to_string(result.totalSeconds).substr(0, 5) + " s" +
            (result.breakthroughIteration ? ", breakthrough at iteration " + std::to_string(*result.breakthroughIteration)
                                          : std::string()));
    return 0;
}

}  // namespace cavesim::cli

/// @file ensemble.h
/// @brief `cavesim ensemble`: many realisations of one scenario, on one machine or spread over
/// the ranks of an MPI job, resumable, summarised as distributions and a karstification
/// probability grid.
///
/// Not in the paper (one cave per scenario there). Layout of an ensemble folder DIR:
///  - `DIR/members/mNNNN/` — member NNNN's run folder, exactly what `cavesim run` writes for the
///    member's scenario (its seed and varied keys), written atomically;
///  - `DIR/members/mNNNN.json` — the member's record: seed, varied values, status (`ok` or
///    `failed`), the error of a failed member, and the member checksum of an ok one;
///  - `DIR/ensemble.json`, `DIR/ensemble.md`, `DIR/probability.vdb`, `DIR/probability.vti`,
///    `DIR/images/probability_plan.png`, `DIR/images/hist_*.png` — the summary.
///
/// Member i's seed is `memberSeed(seed, i)`; its varied keys are drawn from an engine seeded by
/// the same value (`memberScenario`). Nothing a member writes depends on how many members run at
/// once, on how many ranks or threads there are, or on whether it was resumed.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/pipeline.h"
#include "sim/scenario.h"

namespace cavesim::app {

/// How a varied key is drawn.
enum class VaryLaw { kUniform, kLogUniform };

/// One `--vary KEY=LOW:HIGH[:uniform|:log]`: a number key of the scenario drawn per member.
struct VaryRange {
    std::string key;  ///< dotted scenario key of a plain table ("stage2.p_rate")
    double lo = 0, hi = 0;
    VaryLaw law = VaryLaw::kUniform;
    bool integer = false;  ///< an integer key: the draw is rounded to the nearest whole number
};

/// Parses `--vary` text against the scenario registry. Without a law, a key whose name contains
/// "rate" is drawn log-uniformly (rates span decades), any other uniformly. LOW ≤ HIGH, both inside
/// the key's allowed range, both > 0 for `log`.
/// @throw InputError naming the text, the key and what is allowed
VaryRange parseVary(const std::string& text);

/// Member i's seed: SplitMix64(seed + (i + 1) · 0x9E3779B97F4A7C15) with the top bit cleared
/// (so it is a valid scenario seed, 0 … 2⁶³ − 1). SplitMix64(z): z ^= z >> 30; z *= 0xBF58476D1CE4E5B9;
/// z ^= z >> 27; z *= 0x94D049BB133111EB; z ^= z >> 31.
std::uint64_t memberSeed(std::uint64_t scenarioSeed, int member);

/// Member i's scenario: `base` with seed `memberSeed(base.seed, i)` and each varied key drawn, in
/// `vary` order, from a std::mt19937_64 seeded with that seed: u = the engine's next value / 2⁶⁴,
/// uniform lo + u (hi − lo), log-uniform lo · (hi / lo)^u. `values` receives {key: value}.
/// @throw InputError if the member's scenario is not valid
Scenario memberScenario(const Scenario& base, int member, const std::vector<VaryRange>& vary,
                        nlohmann::json* values = nullptr);

/// The member checksum of a member's run folder: FNV-1a 64 over, for every regular file in path
/// order, its relative path, a 0 byte, its length (8 bytes) and its bytes — except report.json,
/// report.md and report.html, which hold timings and the thread count. Equal checksums: byte-identical results.
/// @throw RuntimeError if a file cannot be read
std::string memberChecksum(const std::filesystem::path& dir);

/// The processes that share one ensemble: this one is `rank` of `size`. Member i runs on rank
/// i mod size; rank 0 writes the summary once every rank is done (`barrier`).
struct Communicator {
    int rank = 0;
    int size = 1;
    int localRanks = 1;             ///< ranks on this machine (they share its cores)
    std::function<void()> barrier;  ///< waits for every rank (none for a single process)
};

struct EnsembleRequest {
    std::string scenarioPath;
    int members = 0;                ///< 1 … 100 000
    std::vector<std::string> vary;  ///< `--vary` texts
    std::string outDir;             ///< empty: out/<scenario name>_ensemble
    int threads = 0;                ///< threads of this process; 0: the machine's cores / its ranks
    int parallel = 0;               ///< members at once in this process; 0: as many as threads
};

struct EnsembleOutcome {
    std::filesystem::path out;
    int members = 0;
    int ok = 0, failed = 0;  ///< over the whole ensemble (rank 0), or this rank's share
    int ran = 0;             ///< members this process ran (not resumed)
    int skipped = 0;         ///< members this process found finished and kept
    bool summary = false;    ///< this process wrote the summary
};

/// Runs the members of this rank that are not finished, then (rank 0) summarises the ensemble.
/// A member is finished when its record says `ok`, its scenario is the one this request makes,
/// and its folder still has the recorded checksum; a failed member is retried. A member that fails
/// is recorded with its error and the others go on. `DIR` may be new, empty or an earlier folder
/// of an ensemble (resume); anything else is refused.
/// @throw InputError for a bad request (scenario, --vary, members, output folder) before any
///        member runs; RuntimeError when the summary cannot be written
EnsembleOutcome runEnsemble(const EnsembleRequest& request, const Communicator& comm, const LogFn& log);

/// Writes the summary of the ensemble folder `dir` from the member records and folders:
/// ensemble.json, ensemble.md, probability.vdb and .vti, and the pictures. Returns ensemble.json.
/// @param base     the ensemble's scenario (grid, voxel size, site placement, cave definition)
/// @param members  the number of members
/// @param vary     the varied keys
nlohmann::json summariseEnsemble(const std::filesystem::path& dir, const Scenario& base, int members,
                                 const std::vector<VaryRange>& vary, const LogFn& log);

/// The communicator of this process: an MPI job's world when the command was started by
/// `mpirun` (initialising MPI; finalised at exit) and cavesim was built with MPI, else a single
/// process. `mpiAvailable` tells which build this is.
/// @throw InputError when started by mpirun in a build without MPI
Communicator processCommunicator();
bool mpiAvailable();

}  // namespace cavesim::app

// libFuzzer target: any bytes as the stage-2 state of a checkpoint (sim/stage2_checkpoint.h; the
// file around it, app/checkpoint.h, is zlib data under two checksums that mutations would only
// break). The bytes are restored onto a small prepared domain and, when accepted, stage 2 resumes
// from them for two iterations, once as the scenario's plain run and once as a run of two base-level
// phases under a water table (a state fits at most one of them). The reader must refuse what it did
// not write with InputError (a resumed state may still stop with RuntimeError on numbers that are
// not finite), and neither may read or write out of bounds. Seeds: fuzz/corpus/checkpoint, real
// states after 3 iterations: stage2_after_3.bin, a plain run's in the layout of checkpoint format
// version 1, and phased_after_3.bin, a phased run's in phase 2 (regenerate with
// `fuzz_checkpoint -write_seed=FILE` and `-write_phased_seed=FILE`).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "core/error.h"
#include "sim/domain.h"
#include "sim/scenario_io.h"
#include "sim/stage2.h"
#include "sim/stage2_checkpoint.h"

namespace {

using namespace cavesim;

const Scenario& scenario() {
    static const Scenario s = parseScenarioString(R"(name = "fuzz"
seed = 1
[domain]
size = [8, 8, 8]
[rock]
porosity = 0.05
[[rock.channel]]
points = [[1, 1, 7], [1, 1, 4]]
[[source]]
at = [1, 1, 7]
[[sink]]
box = [[7, 0, 0], [7, 7, 1]]
[stage1]
enabled = false
[stage2]
iterations = 3
p_rate = 0.05
p_rate_channel = 0.001
)",
                                                  "fuzz.toml");
    return s;
}

/// The scenario's stage 2 as two phases under a water table: 2 iterations, then `second`.
Stage2Options phasedOptions(int second) {
    static const Scenario s = [] {
        Scenario p = scenario();
        p.stage2.hydrology.waterTable = 5;
        Stage2Phase a, b;
        a.iterations = 2;
        b.iterations = 1;
        b.waterTable = 3;
        p.stage2.phases = {a, b};
        return p;
    }();
    Stage2Options g = s.stage2;
    g.phases[1].iterations = second;
    return g;
}

const Domain& prepared() {
    static const Domain d = [] {
        Rng rng(scenario().seed);
        Domain dom = buildDomain(scenario(), rng);
        prepareStage2(dom, scenario().stage2);
        return dom;
    }();
    return d;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
    // `-write_seed=FILE`: writes the state after the scenario's 3 iterations (the seed corpus);
    // `-write_phased_seed=FILE` the state after 3 iterations of the phased run (in phase 2).
    for (int a = 1; a < *argc; ++a) {
        const bool plain = std::strncmp((*argv)[a], "-write_seed=", 12) == 0;
        const bool phased = std::strncmp((*argv)[a], "-write_phased_seed=", 19) == 0;
        if (plain || phased) {
            Domain d = prepared();
            Stage2Options g = scenario().stage2;
            g.iterations = 4;
            if (phased) g = phasedOptions(2);
            Stage2Checkpoints ck;
            ck.every = 3;
            std::string bytes;
            ck.save = [&](int, const std::string& state) { bytes = state; };
            runStage2(d, g, {}, {}, ck);
            std::FILE* f = std::fopen((*argv)[a] + (plain ? 12 : 19), "wb");
            if (!f || std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size() || std::fclose(f) != 0) return 1;
            std::exit(0);
        }
    }
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    int iteration = 0;
    try {
        Domain probe = prepared();
        stage2::Carry carry(probe.dims);
        stage2::decodeCarry(bytes, "fuzz", carry, probe);
        iteration = carry.iteration;
    } catch (const InputError&) {
        return 0;
    }
    if (iteration > 1000000) return 0;
    Stage2Options plain = scenario().stage2;
    plain.iterations = iteration + 2;
    for (const Stage2Options& g : {plain, phasedOptions(iteration)}) {
        try {
            Domain d = prepared();
            Stage2Checkpoints ck;
            ck.resume = &bytes;
            ck.resumeName = "fuzz";
            (void)runStage2(d, g, {}, {}, ck);
        } catch (const InputError&) {
        } catch (const RuntimeError&) {
        }
    }
    return 0;
}

// Speleothem growth on the Figure 10 cave: the target is 1,000 years within 60 s on a
// 2-core machine. The cave is simulated once (scenarios/fig10.toml, outside the timing); each
// iteration resamples its smooth mesh to the decoration level set (default 0.1 m voxels), adds the
// seeded ceiling relief and grows 1,000 years with the default [speleothems] options.
//
// Reported: BM_Fig10Speleothems1000Years (level set, relief, growth) and, for scale, the same at
// 0.05 m voxels; medians of repetitions as bench/README.md says.
#include <benchmark/benchmark.h>

#include "mesh/cave_mesh.h"
#include "sim/cave.h"
#include "sim/scenario_io.h"
#include "sim/simulate.h"
#include "speleo/speleothems.h"

namespace {

using namespace cavesim;

const Cave& fig10Cave() {
    static const Cave cave = [] {
        const Scenario s = parseScenarioFile(std::string(CAVESIM_SOURCE_DIR) + "/scenarios/fig10.toml");
        return makeCave(simulate(s), s.output.cave);
    }();
    return cave;
}

void growFig10(benchmark::State& state, double voxelSize) {
    const Cave& cave = fig10Cave();
    const mesh::TriangleMesh caveMesh = mesh::buildCaveMesh(cave.mask, cave.voxelSize);
    SpeleothemOptions o;
    o.enabled = true;
    o.years = 1000;
    o.voxelSize = voxelSize;
    long stalactites = 0, steps = 0;
    for (auto _ : state) {
        speleo::DecorationField f = speleo::fieldFromMesh(caveMesh, o.voxelSize);
        speleo::addCeilingRoughness(f, o.roughness, o.roughnessScale, o.seed);
        const speleo::GrowthResult g = speleo::grow(f, o);
        stalactites = long(g.stalactites.size());
        steps = g.steps;
    }
    state.counters["stalactites"] = double(stalactites);
    state.counters["steps"] = double(steps);
}

void BM_Fig10Speleothems1000Years(benchmark::State& state) {
    growFig10(state, 0.1);
}
void BM_Fig10Speleothems1000YearsFine(benchmark::State& state) {
    growFig10(state, 0.05);
}

}  // namespace

BENCHMARK(BM_Fig10Speleothems1000Years)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_Fig10Speleothems1000YearsFine)->Unit(benchmark::kSecond)->Iterations(1);

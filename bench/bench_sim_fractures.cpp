// Fracture network: drawing the discs of two families and rasterising them into a 200 × 200 × 60
// block (docs/geology.md, "Fracture families").
#include <benchmark/benchmark.h>

#include "sim/domain.h"
#include "sim/fractures.h"

namespace {

using namespace cavesim;

std::vector<FractureFamily> twoFamilies() {
    std::vector<FractureFamily> f(2);
    f[0].dipDirection = 90;
    f[0].dip = 85;
    f[0].kappa = 40;
    f[0].spacing = 10;
    f[1].dipDirection = 0;
    f[1].dip = 80;
    f[1].kappa = 20;
    f[1].spacing = 15;
    for (FractureFamily& g : f) {
        g.lengthExponent = 2.5;
        g.minLength = 5;
        g.maxLength = 100;
    }
    return f;
}

void BM_GenerateDfn(benchmark::State& state) {
    const auto fam = twoFamilies();
    const Dims d{200, 200, 60};
    std::size_t discs = 0;
    for (auto _ : state) discs = generateFractureNetwork(fam, d, 1).discs.size();
    state.counters["discs"] = double(discs);
}
BENCHMARK(BM_GenerateDfn)->Unit(benchmark::kMillisecond);

void BM_GenerateAndRasteriseDfn(benchmark::State& state) {
    const auto fam = twoFamilies();
    const Dims d{200, 200, 60};
    Domain dom = emptyDomain(d, 1.0, 0.05f);
    for (auto _ : state) applyFractureNetwork(dom, generateFractureNetwork(fam, d, 1), fam);
}
BENCHMARK(BM_GenerateAndRasteriseDfn)->Unit(benchmark::kMillisecond);

void BM_MeasureDfn(benchmark::State& state) {
    const auto fam = twoFamilies();
    const Dims d{200, 200, 60};
    FractureNetwork net = generateFractureNetwork(fam, d, 1);
    for (auto _ : state) measureFractureNetwork(net, fam, d);
    state.counters["p32_f1"] = net.families[0].p32;
}
BENCHMARK(BM_MeasureDfn)->Unit(benchmark::kMillisecond);

}  // namespace

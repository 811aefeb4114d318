// The 2D figures of the voxel state at the default width (1024 px): zones.png, pressure.png +
// flow.png, one stage-2 snapshot and the sequence strip, on a 60×60×20 block (three zones,
// branching protochannels, a channel network with pressure and flow) and on an 80×1×40 section.
// Medians of 5 repetitions.
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>

#include "render/pictures.h"
#include "render/png_io.h"
#include "sim/cave.h"
#include "sim/domain.h"

namespace {

using namespace cavesim;

Domain synthetic(Dims dims) {
    Domain d = emptyDomain(dims, 1.0, 0.05f);
    const double src[3][3] = {{6, 0.2 * dims.ny, 0.8 * dims.nz},
                              {8, 0.8 * dims.ny, 0.7 * dims.nz},
                              {0.45 * dims.nx, 0.85 * dims.ny, 0.85 * dims.nz}};
    for (int k = 0; k < dims.nz; ++k)
        for (int j = 0; j < dims.ny; ++j)
            for (int i = 0; i < dims.nx; ++i) {
                int best = 0;
                double bestDist = 1e300;
                for (int s = 0; s < 3; ++s) {
                    const double q = std::hypot(i - src[s][0], j - src[s][1], k - src[s][2]);
                    if (q < bestDist) bestDist = q, best = s;
                }
                d.zone.at(i, j, k) = best;
                // Protochannels: star-shaped lines from each source along the axes.
                const int dx = int(std::lround(i - src[best][0])), dy = int(std::lround(j - src[best][1])),
                          dz = int(std::lround(k - src[best][2]));
                if ((dy == 0 && dz == 0) || (dx == 0 && dz == 0) || (std::abs(dx) == std::abs(dy) && dz == 0))
                    d.flags.at(i, j, k) |= kProtochannel;
                // A winding channel toward the sink at x = max, flow along it.
                const double yc = 0.5 * dims.ny + 0.3 * dims.ny * std::sin(i * 0.15), zc = 0.5 * dims.nz;
                const double r = std::hypot(j - yc, k - zc);
                if (r < 1.6) {
                    d.flags.at(i, j, k) |= kChannel;
                    d.porosity.at(i, j, k) = 0.9f;
                }
                d.flow.at(i, j, k) = float(std::exp(-r) * (1.0 + i) * 1e-3);
                d.pressure.at(i, j, k) = float((dims.nx - i) * 0.5 + 0.2 * r);
            }
    for (int s = 0; s < 3; ++s) {
        const Index3 p{int(src[s][0]), int(src[s][1]), int(src[s][2])};
        d.sourceVoxels.push_back({dims.index(p)});
        d.sourcePressure.push_back(1.0);
    }
    d.sinkVoxels.push_back({dims.index(dims.nx - 1, dims.ny / 2, 0)});
    return d;
}

const Domain& block() {
    static const Domain d = synthetic({60, 60, 20});
    return d;
}
const Domain& section() {
    static const Domain d = synthetic({80, 1, 40});
    return d;
}

std::filesystem::path scratch() {
    const auto dir = std::filesystem::temp_directory_path() / "cavesim_bench_render";
    std::filesystem::create_directories(dir);
    return dir;
}

void BM_ZonesPicture(benchmark::State& state) {
    const auto path = (scratch() / "zones.png").string();
    for (auto _ : state) render::writeZonesPicture(block(), path, 1024);
}
BENCHMARK(BM_ZonesPicture)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);

void BM_FieldPictures(benchmark::State& state) {
    const auto dir = scratch().string();
    const Grid3<std::uint8_t> mask = caveMask(block(), CaveExtent::kChannels);
    for (auto _ : state) render::writeFieldPictures(block(), mask, dir, 1024);
}
BENCHMARK(BM_FieldPictures)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);

void BM_StateFrameBlock(benchmark::State& state) {
    const Grid3<std::uint8_t> mask = caveMask(block(), CaveExtent::kChannels);
    for (auto _ : state)
        benchmark::DoNotOptimize(render::stateFrame(block(), mask, "iteration 120", 1024).pixels.data());
}
BENCHMARK(BM_StateFrameBlock)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);

void BM_StateFrameSection(benchmark::State& state) {
    const Grid3<std::uint8_t> mask = caveMask(section(), CaveExtent::kChannels);
    for (auto _ : state)
        benchmark::DoNotOptimize(render::stateFrame(section(), mask, "iteration 120", 1024).pixels.data());
}
BENCHMARK(BM_StateFrameSection)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);

void BM_SequenceOfFive(benchmark::State& state) {
    const std::vector<render::Image> frames(
        5, render::stateFrame(section(), caveMask(section(), CaveExtent::kChannels), "iteration 120", 1024));
    const auto path = (scratch() / "sequence.png").string();
    for (auto _ : state) render::writePng(path, render::composeStrip(frames, 1));
}
BENCHMARK(BM_SequenceOfFive)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);

}  // namespace

// The cave mesh and the ray-traced pictures of a 60×60×20 result: the target is meshing
// and all pictures under 1 s on a 2-core machine. The cave is synthetic but shaped like a
// result: four winding tubes of radius 0.8–2 voxels from three sources toward one sink, crossing
// and joining (about 1,600 cave voxels, 5 % of the block), with stray short branches.
//
// Reported: BM_WriteCaveMesh (writeCaveMesh: level set, mesh, cave.obj + cave.ply),
// BM_WriteCavePictures (writeCavePictures: level set, four ray-traced views, PNGs) at the
// default width of 1024 px, both in sequence (BM_MeshAndPictures, the number), both with
// one shared level set (BM_MeshAndPicturesShared), and their parts; medians of 5 repetitions.
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <vector>

#include "mesh/cave_mesh.h"
#include "mesh/cave_pictures.h"
#include "sim/cave.h"
#include "sim/domain.h"

namespace {

using namespace cavesim;

Domain windingTubes() {
    Domain d = emptyDomain(Dims{60, 60, 20}, 1.0, 0.05f);
    constexpr double kPi = 3.14159265358979323846;
    struct Tube {
        double y0, ay, phase, z0, az, r0;
    };
    const std::array<Tube, 4> tubes{
        {{12, 6, 0.3, 14, 3, 1.0}, {30, 9, 1.7, 9, 4, 1.6}, {47, 5, 2.9, 5, 2, 1.2}, {20, 12, 4.0, 16, 2, 0.8}}};
    auto centre = [&](const Tube& t, double x) {
        return std::array<double, 3>{x, t.y0 + t.ay * std::sin(2 * kPi * x / 40 + t.phase),
                                     t.z0 + t.az * std::sin(2 * kPi * x / 25 + t.phase)};
    };
    for (const Tube& t : tubes) {
        std::vector<std::array<double, 3>> samples;
        for (int s = 0; s <= 400; ++s) samples.push_back(centre(t, 2 + 55.0 * s / 400));
        for (int k = 0; k < d.dims.nz; ++k)
            for (int j = 0; j < d.dims.ny; ++j)
                for (int i = 0; i < d.dims.nx; ++i) {
                    double best = 1e300, along = 0;
                    for (const auto& p : samples) {
                        const double q =
                            std::pow(i + 0.5 - p[0], 2) + std::pow(j + 0.5 - p[1], 2) + std::pow(k + 0.5 - p[2], 2);
                        if (q < best) best = q, along = p[0];
                    }
                    if (std::sqrt(best) <= t.r0 + 0.5 * std::sin(0.3 * along)) d.flags.at(i, j, k) |= kChannel;
                }
    }
    for (int s = 0; s < 3; ++s) {
        const auto c = centre(tubes[std::size_t(s)], 2.0);
        const std::size_t n = d.dims.index(1, int(c[1]), int(c[2]));
        d.flags[n] |= kSource;
        d.sourceVoxels.push_back({n});
        d.sourcePressure.push_back(1.0);
    }
    std::vector<std::size_t> sink;
    for (int k = 0; k < 6; ++k)
        for (int j = 25; j < 36; ++j) {
            const std::size_t n = d.dims.index(59, j, k);
            d.flags[n] |= kSink;
            sink.push_back(n);
        }
    d.sinkVoxels.push_back(sink);
    return d;
}

const Cave& fixture() {
    static const Cave c = makeCave(windingTubes(), CaveExtent::kChannels);
    return c;
}

std::filesystem::path scratchDir() {
    const auto dir = std::filesystem::temp_directory_path() / "cavesim_bench_mesh";
    std::filesystem::create_directories(dir / "images");
    return dir;
}

void BM_WriteCaveMesh(benchmark::State& state) {
    const Cave& cave = fixture();
    const auto dir = scratchDir();
    for (auto _ : state) benchmark::DoNotOptimize(mesh::writeCaveMesh(cave, dir.string()).faces);
    state.counters["faces"] = double(mesh::measureMesh(mesh::buildCaveMesh(cave.mask, cave.voxelSize)).faces);
}
BENCHMARK(BM_WriteCaveMesh)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);

void BM_BuildCaveMesh(benchmark::State& state) {
    const Cave& cave = fixture();
    for (auto _ : state) benchmark::DoNotOptimize(mesh::buildCaveMesh(cave.mask, cave.voxelSize).triangles.size());
}
BENCHMARK(BM_BuildCaveMesh)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);

void BM_WriteCavePictures(benchmark::State& state) {
    const auto dir = scratchDir() / "images";
    for (auto _ : state) mesh::writeCavePictures(fixture(), dir.string(), int(state.range(0)));
}
BENCHMARK(BM_WriteCavePictures)
    ->Arg(1024)
    ->Arg(800)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);

void BM_RenderCaveViews(benchmark::State& state) {
    for (auto _ : state)
        benchmark::DoNotOptimize(mesh::renderCaveViews(fixture(), int(state.range(0)))[0].pixels.data());
}
BENCHMARK(BM_RenderCaveViews)
    ->Arg(1024)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);

void BM_MeshAndPictures(benchmark::State& state) {
    const Cave& cave = fixture();
    const auto dir = scratchDir();
    for (auto _ : state) {
        benchmark::DoNotOptimize(mesh::writeCaveMesh(cave, dir.string()).faces);
        mesh::writeCavePictures(cave, (dir / "images").string(), 1024);
    }
}
BENCHMARK(BM_MeshAndPictures)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);

// The same files through writeCaveMeshAndPictures (one level set for both).
void BM_MeshAndPicturesShared(benchmark::State& state) {
    const auto dir = scratchDir();
    for (auto _ : state)
        benchmark::DoNotOptimize(
            mesh::writeCaveMeshAndPictures(fixture(), dir.string(), (dir / "images").string(), 1024).faces);
}
BENCHMARK(BM_MeshAndPicturesShared)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);

}  // namespace

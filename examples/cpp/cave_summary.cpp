// Runs a scenario through the cavesim library and prints what came out: the breakthrough, the
// porosity at the first source, the mesh and the skeleton. Optionally sets keys first:
//   cave_summary SCENARIO.toml [KEY=NUMBER ...]      e.g. cave_summary small.toml stage2.p_rate=0.4
// Exit codes as the cavesim command's: 2 for bad input, 1 for a failure while running.
#include <cstdio>
#include <exception>
#include <string>

#include <cavesim/cavesim.h>

namespace api = cavesim::api;

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: cave_summary SCENARIO.toml [KEY=NUMBER ...]\n");
        return 2;
    }
    try {
        api::Scenario scenario = api::Scenario::fromTomlFile(argv[1]);
        for (int a = 2; a < argc; ++a) {
            const std::string arg = argv[a];
            const std::size_t eq = arg.find('=');
            if (eq == std::string::npos) throw cavesim::InputError(arg + ": expected KEY=NUMBER");
            scenario.set(arg.substr(0, eq), std::stod(arg.substr(eq + 1)));
        }

        api::RunOptions options;
        options.threads = 2;
        options.progress = [](const std::string& phase, long done, long total) {
            if (done == total) std::fprintf(stderr, "  %s: done\n", phase.c_str());
        };
        const api::Result result = api::run(scenario, options);

        const auto dims = result.dims();
        const api::Report& report = result.report();
        std::printf("cavesim %s: scenario '%s', grid %d x %d x %d, %.3g m voxels\n", api::version().c_str(),
                    report.scenario.c_str(), dims[0], dims[1], dims[2], result.voxelSize());
        if (report.breakthroughIteration)
            std::printf("breakthrough at iteration %d; %d of %d source(s) connected\n", *report.breakthroughIteration,
                        report.sourcesConnected, report.sourcesTotal);
        else
            std::printf("no breakthrough in %d iterations\n", report.iterations);

        // The first source voxel (a one-voxel source reads `at = [i, j, k]`), and where it is in the world.
        const api::Value source = scenario.get("source").items().at(0);
        const api::Value* at = source.find("at");
        if (!at) throw cavesim::InputError(scenario.sourceName() + ": the first [[source]] is a box, not one voxel");
        const int i = int(at->items()[0].asInt()), j = int(at->items()[1].asInt()), k = int(at->items()[2].asInt());
        const auto world = result.worldFromIndex(i, j, k);
        std::printf("porosity at source 1, voxel (%d, %d, %d) = (%.2f, %.2f, %.2f) m: %.3f\n", i, j, k, world[0],
                    world[1], world[2], result.porosity().at(i, j, k));

        long cave = 0;
        const api::GridView<std::uint8_t> mask = result.caveMask();
        for (std::size_t n = 0; n < mask.size(); ++n) cave += mask.data[n];
        std::printf("cave: %ld voxels; mesh %zu vertices, %zu triangles (closed: %s); skeleton %zu nodes, %zu edges\n",
                    cave, result.mesh().vertices.size(), result.mesh().triangles.size(),
                    report.meshClosed ? "yes" : "no", result.skeleton().nodes.size(), result.skeleton().edges.size());
        std::printf("network density %.3f m/m^2, areal coverage %.1f %%, W %.2f m, category %s\n",
                    report.networkDensityOpt, report.arealCoveragePctOpt, report.meanWidthM,
                    report.caveCategory.c_str());
        return 0;
    } catch (const cavesim::InputError& e) {
        std::fprintf(stderr, "cave_summary: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "cave_summary: %s\n", e.what());
        return 1;
    }
}

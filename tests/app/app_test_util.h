// Fixtures shared by the application test files: the small scenario, scratch folders, a run into a
// folder.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

#include "app/output_dir.h"
#include "app/pipeline.h"

namespace cavesim::apptest {

/// A 20 × 12 × 8 block, two sources, one sink wall, 40 iterations; without its name line and its
/// [output] table, which each scenario built on it adds.
inline constexpr const char* kSmallCave = R"(seed = 5
[domain]
size = [20, 12, 8]
voxel_size = 2.0
[[source]]
at = [2, 3, 6]
[[source]]
at = [2, 9, 6]
pressure = 0.5
[[sink]]
box = [[19, 0, 0], [19, 11, 7]]
[stage2]
iterations = 40
)";

/// The small scenario without pictures: small enough for a test.
inline const std::string kSmall = std::string("name = \"small\"\n") + kSmallCave + "[output]\nimages = false\n";

/// A fresh (absent) path `name` in this process's scratch folder, whose parent exists.
inline std::filesystem::path scratch(const std::string& name) {
    const std::filesystem::path p =
        std::filesystem::temp_directory_path() / ("cavesim_test_app_" + std::to_string(::getpid())) / name;
    std::filesystem::remove_all(p);
    std::filesystem::create_directories(p.parent_path());
    return p;
}

/// Runs the pipeline on `s` into the output folder `out` (replaced if present).
inline app::PipelineResult runInto(const Scenario& s, const std::filesystem::path& out,
                                   const app::PipelineOptions& o = {}) {
    app::OutputDir dir(out, true);
    dir.open();
    app::PipelineResult r = app::runPipeline(s, dir, o);
    dir.commit();
    return r;
}

}  // namespace cavesim::apptest

#include "cli/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "cli/report.h"
#include "mesh/cave_mesh.h"
#include "mesh/cave_pictures.h"
#include "mesh/vdb_io.h"
#include "morpho/analysis.h"
#include "render/pictures.h"
#include "render/png_io.h"
#include "sim/domain.h"
#include "sim/scenario_io.h"
#include "sim/stage1.h"
#include "sim/stage2.h"

namespace cavesim::cli {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

void writeStateVdb(const std::string& path, const Domain& dom, bool stage2) {
    Grid3<std::int32_t> flags(dom.dims, 0);
    for (std::size_t v = 0; v < flags.size(); ++v) flags[v] = dom.flags[v];
    std::vector<mesh::NamedGrid> grids{
        {"porosity", &dom.porosity, nullptr, "porosity R in [0,1] (water capacity)"},
        {"porosity0", &dom.porosity0, nullptr, "initial porosity"},
        {"zone", nullptr, &dom.zone, "stage-1 pressure zone: source index, -1 none"},
        {"flags", nullptr, &flags,
         "bits: 1 source, 2 sink, 4 protochannel, 8 channel, 16 obstacle, 32 fracture, 64 rock.channel"},
    };
    if (stage2) {
        grids.push_back({"pressure", &dom.pressure, nullptr, "stage-2 pressure"});
        grids.push_back({"flow", &dom.flow, nullptr, "stage-2 flow f of the last iteration (Eq. 2)"});
        grids.push_back({"water", &dom.water, nullptr, "stage-2 water contents"});
    }
    mesh::writeVdb(path, grids, dom.voxelSize);
}

PipelineResult runPipeline(const Scenario& s, int threads, const OutputDir& dir, ProgressBar& bar) {
    const auto t0 = Clock::now();
    RunRecord rec;
    rec.threads = threads;
    auto progress = [&bar](const std::string& phase, long done, long total) { bar.update(phase, done, total); };
    const int width = s.output.imageWidth;

    Rng rng(s.seed);
    Domain dom = buildDomain(s, rng);

    if (s.stage1.enabled) {
        const auto t1 = Clock::now();
        rec.stage1 = runStage1(dom, s, rng, progress);
        rec.timing.stage1 = since(t1);
        writeStateVdb(dir.file("stage1.vdb").string(), dom, false);
        if (s.output.images) render::writeZonesPicture(dom, dir.file("images/zones.png").string(), width);
        bar.log("stage 1: " + std::to_string(rec.stage1->zones) + " zone(s), " +
                std::to_string(rec.stage1->protochannelVoxels) + " protochannel voxels in " +
                std::to_string(rec.timing.stage1).substr(0, 5) + " s");
    }
    if (s.stage2.enabled) {
        const auto t2 = Clock::now();
        prepareStage2(dom, s);
        // images/sequence.png: up to 6 frames a row, at most kStripWidth pixels wide; each frame is
        // reduced as it is taken, so the frames kept for the strip stay small at any image width.
        constexpr int kPerRow = 6, kStripWidth = 8192;
        const int nFrames = int(s.stage2.snapshots.size());
        const int cols = std::clamp(nFrames, 1, kPerRow);
        const int reduce = std::max(1, (width * cols + kStripWidth - 1) / kStripWidth);
        std::vector<render::Image> frames;
        SnapshotFn snap;
        if (s.output.images && nFrames > 0) {
            snap = [&](int it, const Domain& d) {
                char name[64];
                std::snprintf(name, sizeof name, "images/iter_%04d.png", it);
                render::Image frame = render::stateFrame(d, "iteration " + std::to_string(it), width);
                render::writePng(dir.file(name).string(), frame);
                frames.push_back(render::downsample(frame, reduce));
            };
        }
        rec.stage2 = runStage2(dom, s, progress, snap);
        rec.timing.stage2 = since(t2);
        if (frames.size() > 1)
            render::writePng(dir.file("images/sequence.png").string(),
                             render::composeStrip(frames, (int(frames.size()) + kPerRow - 1) / kPerRow));
        const auto& r = *rec.stage2;
        bar.log("stage 2: " + std::to_string(r.iterations) + " iterations, breakthrough " +
                (r.breakthroughIteration ? "at iteration " + std::to_string(*r.breakthroughIteration)
                                         : std::string("none")) +
                ", " + std::to_string(r.history.empty() ? 0 : r.history.back().sourcesConnected) + " of " +
                std::to_string(dom.sourceVoxels.size()) + " source(s) connected, in " +
                std::to_string(rec.timing.stage2).substr(0, 5) + " s");
    }
    writeStateVdb(dir.file("state.vdb").string(), dom, s.stage2.enabled);
    // What `cavesim report` checks before it trusts the file: its bytes and the grid it holds.
    nlohmann::json stateRecord = fileFingerprint(dir.file("state.vdb").string());
    stateRecord["grid"] = {s.size[0], s.size[1], s.size[2]};
    stateRecord["voxel_size_m"] = s.voxelSize;
    rec.files["state.vdb"] = stateRecord;

    const auto tm = Clock::now();
    mesh::MeshOptions mo;
    mo.style = s.output.meshStyle;
    const std::string imagesDir = dir.file("images").string();
    if (s.output.mesh && s.output.images) {
        rec.mesh = meshJson(mesh::writeCaveMeshAndPictures(dom, dir.file("").string(), imagesDir, width, mo));
    } else if (s.output.mesh) {
        rec.mesh = meshJson(mesh::writeCaveMesh(dom, dir.file("").string(), mo));
    } else if (s.output.images) {
        mesh::writeCavePictures(dom, imagesDir, width);
    }
    if (s.output.images && s.stage2.enabled) render::writeFieldPictures(dom, imagesDir, width);
    rec.timing.mesh = since(tm);

    const auto tr = Clock::now();
    const morpho::CaveAnalysis analysis =
        morpho::analyseCave(dom, rec.stage2 ? rec.stage2->sourceConnectedIteration : std::vector<std::optional<int>>{});
    morpho::writeSkeletonFiles(analysis.skeleton, dir.file("").string(), dom.voxelSize, dom.dims);
    rec.analysis = analysisJson(analysis);
    rec.timing.report = since(tr);
    rec.timing.total = since(t0);
    writeReport(s, dom, rec, dir.file("").string());
    // The effective scenario also records the state.vdb it produced (a comment, ignored by the
    // parser), so `cavesim report` can check the file even when report.json is gone.
    writeTextFile(dir.file("scenario.toml"),
                  scenarioToToml(s) + "# state.vdb: " + rec.files["state.vdb"].dump() + "\n");

    PipelineResult out;
    out.totalSeconds = since(t0);
    if (rec.stage2) out.breakthroughIteration = rec.stage2->breakthroughIteration;
    out.report = rec.json;
    return out;
}

}  // namespace cavesim::cli

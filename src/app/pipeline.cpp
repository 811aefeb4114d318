#include "app/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "app/cave_maps.h"
#include "app/checkpoint.h"
#include "app/report.h"
#include "app/section_picture.h"
#include "app/speleo_report.h"
#include "app/state.h"
#include "core/timer.h"
#include "formats/exports.h"
#include "mesh/cave_mesh.h"
#include "mesh/cave_pictures.h"
#include "morpho/analysis.h"
#include "render/pictures.h"
#include "render/png_io.h"
#include "sim/cave.h"
#include "sim/connectivity.h"
#include "sim/domain.h"
#include "sim/scenario_io.h"
#include "sim/stage1.h"
#include "sim/stage2.h"

namespace cavesim::app {
namespace {

void say(const LogFn& log, const std::string& message) {
    if (log) log(message);
}

}  // namespace

Stage1Result runScenarioStage1(Domain& dom, const Scenario& s, Rng& rng, const ProgressFn& progress) {
    try {
        return runStage1(dom, s.stage1, rng, progress);
    } catch (const Stage1LimitError& e) {
        const int sourceLine =
            e.source >= 0 && std::size_t(e.source) < s.sources.size() ? s.sources[std::size_t(e.source)].line : 0;
        if (e.source < 0) {  // not the key's limit (the machine's memory): the file as a whole
            throw InputError(s.path + ": " + e.what());
        }
        // The key's own line when the file gives it; at its default, the source's line.
        const int line = keyLine(s, &s.stage1.maxGraphVoxels);
        std::string where = s.path + (line > 0         ? ":" + std::to_string(line)
                                      : sourceLine > 0 ? ":" + std::to_string(sourceLine)
                                                       : std::string());
        where +=
            ": key '" + scenarioKey(s, &s.stage1.maxGraphVoxels) + "' = " + std::to_string(s.stage1.maxGraphVoxels);
        std::string msg = where + ": " + e.what();
        if (line > 0 && sourceLine > 0) msg += " (the [[source]] entry at line " + std::to_string(sourceLine) + ")";
        throw InputError(msg);
    }
}

void runStages(Domain& dom, const Scenario& s, Rng& rng, RunRecord& rec, const ProgressFn& progress,
               const StageHooks& hooks) {
    if (s.stage1.enabled) {
        const Stopwatch t1;
        rec.stage1 = runScenarioStage1(dom, s, rng, progress);
        rec.timing.stage1 = t1.seconds();
        if (hooks.afterStage1) hooks.afterStage1(dom, rec);
    }
    if (s.stage2.enabled) {
        const Stopwatch t2;
        prepareStage2(dom, s.stage2);
        if (hooks.beforeStage2) hooks.beforeStage2(dom, rec);
        rec.stage2 = runStage2(dom, s.stage2, progress, hooks.snapshot, hooks.checkpoints);
        rec.timing.stage2 = t2.seconds();
    }
}

void wireCheckpoints(StageHooks& hooks, const Checkpoint* resume, const std::string& resumeName,
                     const std::string& advice, int every, const Checkpoint& base,
                     std::function<void(Checkpoint&)> save) {
    if (!resume && every <= 0) return;
    auto domainHash = std::make_shared<std::uint64_t>(0);  // the domain at the start of stage 2
    hooks.beforeStage2 = [domainHash, resume, resumeName, advice, then = std::move(hooks.beforeStage2)](const Domain& d,
                                                                                                        RunRecord& r) {
        *domainHash = domainFingerprint(d);
        if (resume) checkResumedDomain(*domainHash, *resume, resumeName, advice);
        if (then) then(d, r);
    };
    if (resume) {
        hooks.checkpoints.resume = &resume->stage2;
        hooks.checkpoints.resumeName = resumeName;
    }
    if (every > 0) {
        hooks.checkpoints.every = every;
        hooks.checkpoints.save = [domainHash, base, save = std::move(save)](int it, const std::string& state) {
            Checkpoint c = base;
            c.domainHash = *domainHash;
            c.iteration = it;
            c.stage2 = state;
            save(c);
        };
    }
}

std::vector<double> familyStrikes(const Scenario& s) {
    std::vector<double> strikes;
    for (const FractureFamily& f : s.fractureFamilies) {
        double strike = std::fmod(f.dipDirection - 90.0, 180.0);
        if (strike < 0) strike += 180.0;
        strikes.push_back(strike);
    }
    return strikes;
}

std::vector<std::optional<int>> connectedIterations(const RunRecord& rec) {
    return rec.stage2 ? rec.stage2->sourceConnectedIteration : std::vector<std::optional<int>>{};
}

morpho::CaveAnalysis analyseRun(const Cave& cave, const Domain& dom, const Scenario& s,
                                const std::vector<std::optional<int>>& connected) {
    morpho::CaveAnalysis a =
        morpho::analyseCave(cave, s.stage2.enabled ? &dom.pressure : nullptr, connected, {}, familyStrikes(s));
    addProtochannelProximity(a, dom, s);
    return a;
}

void addProtochannelProximity(morpho::CaveAnalysis& analysis, const Domain& dom, const Scenario& s) {
    if (!s.stage2.enabled) return;
    Grid3<std::uint8_t> proto(dom.dims, 0);
    for (std::size_t v = 0; v < proto.data.size(); ++v) proto[v] = (dom.flags[v] & kProtochannel) ? 1 : 0;
    analysis.nearProtochannels = morpho::nearMarked(analysis.skeleton, proto, kNearProtochannelVoxels);
}

PipelineResult runPipeline(const Scenario& s, const OutputDir& dir, const PipelineOptions& options) {
    const Stopwatch t0;
    RunRecord rec;
    rec.threads = options.threads;
    const ProgressFn& progress = options.progress;
    const int width = s.output.imageWidth;

    Rng rng(s.seed);
    Domain dom = buildDomain(s, rng);

    // images/sequence.png: up to 6 frames a row, at most kStripWidth pixels wide; each frame is
    // reduced as it is taken, so the frames kept for the strip stay small at any image width.
    constexpr int kPerRow = 6, kStripWidth = 8192;
    const int nFrames = int(s.stage2.snapshots.size());
    const int cols = std::clamp(nFrames, 1, kPerRow);
    const int reduce = std::max(1, (width * cols + kStripWidth - 1) / kStripWidth);
    std::vector<render::Image> frames;
    StageHooks hooks;
    hooks.afterStage1 = [&](const Domain& d, const RunRecord& r) {
        writeState(dir.file("stage1.vdb").string(), d, s, StateMoment::kAfterStage1);
        if (s.output.images) render::writeZonesPicture(d, dir.file("images/zones.png").string(), width);
        say(options.log, "stage 1: " + std::to_string(r.stage1->zones) + " zone(s), " +
                             std::to_string(r.stage1->protochannelVoxels) + " protochannel voxels in " +
                             std::to_string(r.timing.stage1).substr(0, 5) + " s");
    };
    std::vector<std::string> stage2Files;  // files stage 2 wrote so far: a checkpoint carries them
    hooks.beforeStage2 = [&](const Domain& d, RunRecord& r) {
        r.connectedAtStart = sourcesConnectedAtStart(d);
        if (!options.resume) return;
        for (const auto& [path, bytes] : options.resume->files) {
            writeFileAtomic(dir.file(path).string(), bytes);
            stage2Files.push_back(path);
        }
        frames = options.resume->frames;
    };
    if (s.output.images && nFrames > 0) {
        hooks.snapshot = [&](int it, const Domain& d) {
            char name[64];
            std::snprintf(name, sizeof name, "images/iter_%04d.png", it);
            render::Image frame =
                render::stateFrame(d, caveMask(d, s.output.cave), "iteration " + std::to_string(it), width);
            render::writePng(dir.file(name).string(), frame);
            stage2Files.push_back(name);
            frames.push_back(render::downsample(frame, reduce));
        };
    }
    wireCheckpoints(hooks, options.resume, options.resumeName, "rerun `cavesim run`", options.checkpoint.every,
                    options.checkpoint, [&](Checkpoint& c) {
                        const Stopwatch tc;
                        for (const std::string& f : stage2Files) c.files.emplace_back(f, readFileBytes(dir.file(f)));
                        c.frames = frames;
                        const std::string bytes = encodeCheckpoint(c);
                        const double encoded = tc.seconds();
                        writeFileAtomic((options.checkpointDir / kCheckpointFile).string(), bytes);
                        char line[160];
                        std::snprintf(line, sizeof line,
                                      "checkpoint after iteration %d: %.1f MB in %.3f s (%.3f s to encode)",
                                      c.iteration, double(bytes.size()) / 1e6, tc.seconds(), encoded);
                        say(options.log, line);
                    });
    runStages(dom, s, rng, rec, progress, hooks);
    if (rec.stage2) {
        if (frames.size() > 1)
            render::writePng(dir.file("images/sequence.png").string(),
                             render::composeStrip(frames, (int(frames.size()) + kPerRow - 1) / kPerRow));
        const auto& r = *rec.stage2;
        say(options.log, "stage 2: " + std::to_string(r.iterations) + " iterations, breakthrough " +
                             (r.breakthroughIteration ? "at iteration " + std::to_string(*r.breakthroughIteration)
                                                      : std::string("none")) +
                             ", " + std::to_string(r.history.empty() ? 0 : r.history.back().sourcesConnected) + " of " +
                             std::to_string(dom.sourceVoxels.size()) + " source(s) connected, in " +
                             std::to_string(rec.timing.stage2).substr(0, 5) + " s");
    }
    // state.cavesim is what `cavesim report` reads back, and checks before it decodes: its record
    // holds its bytes and the grid it holds.
    const std::string outDir = dir.file("").string();  // the staging directory, where every file goes
    rec.files = writeFinalState(outDir, dom, s);

    // The cave, once: every output below describes these voxels.
    const Cave cave = makeCave(dom, s.output.cave);

    reportProgress(progress, "mesh and pictures", 0, 1);  // also a safe point to stop at
    const Stopwatch tm;
    mesh::MeshOptions mo;
    mo.style = s.output.meshStyle;
    const std::string imagesDir = dir.file("images").string();
    SurfaceMesh surface;  // the cave mesh in world space, for the export formats
    if (s.output.mesh && s.output.images) {
        rec.mesh = meshJson(mesh::writeCaveMeshAndPictures(cave, outDir, imagesDir, width, mo, &surface));
    } else if (s.output.mesh) {
        rec.mesh = meshJson(mesh::writeCaveMesh(cave, outDir, mo, &surface));
    } else if (s.output.images) {
        mesh::writeCavePictures(cave, imagesDir, width);
    }
    if (s.output.images && s.stage2.enabled) render::writeFieldPictures(dom, cave.mask, imagesDir, width);
    if (s.speleothems.enabled) {
        const speleo::DecorationSummary decoration =
            speleo::decorateCave(cave, s.speleothems, outDir, width, s.output.images, s.output.mesh, progress);
        rec.speleothems = speleothemsJson(decoration);
        // The decorated meshes are recorded by their bytes beside the state files (none for an
        // empty cave or with [output] mesh = false).
        for (const std::string& f : decoration.meshFiles) rec.files[f] = fileFingerprint(dir.file(f).string());
    }
    rec.timing.mesh = tm.seconds();

    reportProgress(progress, "report", 0, 1);
    const Stopwatch tr;
    const morpho::CaveAnalysis analysis = analyseRun(cave, dom, s, connectedIterations(rec));
    morpho::writeSkeletonFiles(analysis.skeleton, outDir, dom.voxelSize, dom.dims);
    if (s.output.images) {
        writeCaveMaps(cave, analysis.skeleton, s.name, imagesDir, width);
        writeSectionsPicture(analysis.sections, s.name, imagesDir);
    }
    if (!s.fractureFamilies.empty()) rec.fractures = measuredFractureNetwork(s);
    if (s.output.images && rec.fractures)
        render::writeFracturesPicture(dom, cave.mask, *rec.fractures, dir.file("images/fractures.png").string(), width);
    rec.analysis = analysisJson(analysis);
    rec.timing.report = tr.seconds();

    reportProgress(progress, "exports", 0, 1);
    const Stopwatch te;
    formats::ExportInputs exports;
    exports.domain = &dom;
    exports.cave = &cave;
    exports.mesh = s.output.mesh ? &surface : nullptr;
    exports.skeleton = &analysis.skeleton;
    exports.network = &analysis.network;
    exports.stage2 = rec.stage2 ? &*rec.stage2 : nullptr;
    exports.meshOptions = mo;
    exports.glb.normals = s.output.meshNormals;
    exports.buildMeshIfMissing = false;  // `[output] mesh = false`: no mesh in any format
    rec.exports = formats::writeExports(exports, outDir, formats::formatSet(s.output.formats));
    rec.timing.exports = te.seconds();
    rec.timing.total = t0.seconds();
    writeReport(s, dom, rec, outDir);
    // The effective scenario also records the state file it produced (a comment, ignored by the
    // parser), so `cavesim report` can check the file even when report.json is gone.
    writeFileAtomic(dir.file("scenario.toml").string(),
                    scenarioToToml(s) + "# " + kCheckedStateFile + ": " + rec.files[kCheckedStateFile].dump() + "\n");

    PipelineResult out;
    if (options.alsoMeasure) {
        const Cave other = makeCave(dom, *options.alsoMeasure);
        out.alsoMeasured = analysisJson(analyseRun(other, dom, s, connectedIterations(rec)));
    }
    out.totalSeconds = t0.seconds();
    if (rec.stage2) out.breakthroughIteration = rec.stage2->breakthroughIteration;
    out.report = rec.json;
    return out;
}

}  // namespace cavesim::app

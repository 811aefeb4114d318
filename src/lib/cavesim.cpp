// The public API (include/cavesim/cavesim.h) on top of the application and simulation modules:
// scenarios as TOML documents parsed by the file parser, runs as app/pipeline.cpp runs them
// without writing files, results copied into plain structs.
#include "cavesim/cavesim.h"

#include <algorithm>
#include <filesystem>
#include <utility>

#include <tbb/global_control.h>
#include <tbb/info.h>

#include "app/checkpoint.h"
#include "app/commands.h"
#include "app/pipeline.h"
#include "app/report.h"
#include "app/state.h"
#include "core/atomic_file.h"
#include "core/timer.h"
#include "mesh/cave_mesh.h"
#include "morpho/analysis.h"
#include "sim/cave.h"
#include "sim/domain.h"
#include "sim/parameters.h"
#include "sim/scenario_io.h"
#include "sim/scenario_toml.h"
#include "sim/stage1.h"
#include "sim/stage2.h"
#include "site/site.h"

#ifndef CAVESIM_VERSION
#define CAVESIM_VERSION "unknown"
#endif

namespace cavesim::api {

static_assert(int(kFlagSource) == int(cavesim::kSource) && int(kFlagSink) == int(cavesim::kSink) &&
                  int(kFlagProtochannel) == int(cavesim::kProtochannel) &&
                  int(kFlagChannel) == int(cavesim::kChannel) && int(kFlagObstacle) == int(cavesim::kObstacle) &&
                  int(kFlagFracture) == int(cavesim::kFracture) &&
                  int(kFlagFeatureChannel) == int(cavesim::kFeatureChannel) && int(kFlagInert) == int(cavesim::kInert),
              "public flag bits must equal sim/domain.h's");

std::string version() {
    return CAVESIM_VERSION;
}

// ---------------------------------------------------------------------------------------------
// Value

namespace {

const char* kindName(Value::Kind k) {
    switch (k) {
        case Value::Kind::kBool:
            return "a boolean";
        case Value::Kind::kInt:
            return "an integer";
        case Value::Kind::kReal:
            return "a number";
        case Value::Kind::kString:
            return "a string";
        case Value::Kind::kList:
            return "a list";
        case Value::Kind::kTable:
            return "a table";
    }
    return "a value";
}

[[noreturn]] void wrongKind(Value::Kind has, Value::Kind wanted) {
    throw InputError(std::string("value is ") + kindName(has) + ", not " + kindName(wanted));
}

}  // namespace

Value Value::table(const std::vector<Entry>& entries) {
    Value v;
    v.kind_ = Kind::kTable;
    for (const Entry& e : entries) v.insert(e.first, e.second);
    return v;
}

bool Value::asBool() const {
    if (kind_ != Kind::kBool) wrongKind(kind_, Kind::kBool);
    return int_ != 0;
}
std::int64_t Value::asInt() const {
    if (kind_ != Kind::kInt) wrongKind(kind_, Kind::kInt);
    return int_;
}
double Value::asReal() const {
    if (kind_ == Kind::kInt) return double(int_);
    if (kind_ != Kind::kReal) wrongKind(kind_, Kind::kReal);
    return real_;
}
const std::string& Value::asString() const {
    if (kind_ != Kind::kString) wrongKind(kind_, Kind::kString);
    return string_;
}

const Value* Value::find(const std::string& key) const {
    for (std::size_t n = 0; n < keys_.size(); ++n)
        if (keys_[n] == key) return &items_[n];
    return nullptr;
}

void Value::insert(const std::string& key, Value value) {
    if (kind_ != Kind::kTable) {
        if (!(kind_ == Kind::kList && items_.empty())) wrongKind(kind_, Kind::kTable);
        kind_ = Kind::kTable;
    }
    for (std::size_t n = 0; n < keys_.size(); ++n)
        if (keys_[n] == key) {
            items_[n] = std::move(value);
            return;
        }
    keys_.push_back(key);
    items_.push_back(std::move(value));
}

// ---------------------------------------------------------------------------------------------
// Value ↔ TOML

namespace {

/// Assigns `v` to `t[key]`; a dotted key goes through its tables (made when missing); a table merges
/// into an existing table, anything else replaces.
void assignNode(toml::table& t, const std::string& key, const Value& v);

toml::table toTomlTable(const Value& v) {
    toml::table t;
    for (std::size_t n = 0; n < v.keys().size(); ++n) assignNode(t, v.keys()[n], v.items()[n]);
    return t;
}

toml::array toArray(const Value& v);

/// Calls `put` with `v` as a TOML value (a list as an array, a table as a table).
template <typename Put>
void putNode(const Value& v, Put&& put) {
    switch (v.kind()) {
        case Value::Kind::kBool:
            put(v.asBool());
            break;
        case Value::Kind::kInt:
            put(v.asInt());
            break;
        case Value::Kind::kReal:
            put(v.asReal());
            break;
        case Value::Kind::kString:
            put(v.asString());
            break;
        case Value::Kind::kList:
            put(toArray(v));
            break;
        case Value::Kind::kTable:
            put(toTomlTable(v));
            break;
    }
}

toml::array toArray(const Value& v) {
    toml::array a;
    for (const Value& e : v.items()) putNode(e, [&a](auto&& x) { a.push_back(std::forward<decltype(x)>(x)); });
    return a;
}

void assignNode(toml::table& t, const std::string& key, const Value& v) {
    const std::size_t dot = key.find('.');
    if (dot != std::string::npos && dot > 0 && dot + 1 < key.size()) {  // a dotted key: through its tables
        const std::string head = key.substr(0, dot);
        if (!t.get(head) || !t.get(head)->is_table()) t.insert_or_assign(head, toml::table{});
        assignNode(*t.get(head)->as_table(), key.substr(dot + 1), v);
        return;
    }
    if (v.kind() != Value::Kind::kTable) {
        putNode(v, [&](auto&& x) { t.insert_or_assign(key, std::forward<decltype(x)>(x)); });
        return;
    }
    toml::table* existing = t.get(key) ? t.get(key)->as_table() : nullptr;
    if (!existing) {
        t.insert_or_assign(key, toml::table{});
        existing = t.get(key)->as_table();
    }
    for (std::size_t n = 0; n < v.keys().size(); ++n) assignNode(*existing, v.keys()[n], v.items()[n]);
}

Value fromNode(const toml::node& n) {
    if (auto b = n.as_boolean()) return Value(b->get());
    if (auto i = n.as_integer()) return Value(i->get());
    if (auto f = n.as_floating_point()) return Value(f->get());
    if (auto s = n.as_string()) return Value(s->get());
    if (auto a = n.as_array()) {
        std::vector<Value> items;
        for (const toml::node& e : *a) items.push_back(fromNode(e));
        return Value(std::move(items));
    }
    Value t = Value::table({});
    if (auto tab = n.as_table())
        for (auto&& [k, v] : *tab) t.insert(std::string(k.str()), fromNode(v));
    return t;
}

/// Splits "a.b.c" into its parts.
std::vector<std::string> splitKey(const std::string& key) {
    std::vector<std::string> parts;
    std::size_t from = 0;
    while (true) {
        const std::size_t dot = key.find('.', from);
        parts.push_back(key.substr(from, dot == std::string::npos ? std::string::npos : dot - from));
        if (dot == std::string::npos) break;
        from = dot + 1;
    }
    return parts;
}

/// The table that holds the last part of dotted `key`, made when missing.
/// @throw InputError when a part on the way holds a value, not a table
toml::table& parentTable(toml::table& root, const std::vector<std::string>& parts, const std::string& source,
                         const std::string& key) {
    if (key.empty() || std::any_of(parts.begin(), parts.end(), [](const std::string& p) { return p.empty(); }))
        throw InputError(source + ": key '" + key + "': not a key (keys are names joined by dots, e.g. stage2.p_rate)");
    toml::table* t = &root;
    std::string at;
    for (std::size_t n = 0; n + 1 < parts.size(); ++n) {
        at += (at.empty() ? "" : ".") + parts[n];
        toml::node* next = t->get(parts[n]);
        if (!next) {
            t->insert_or_assign(parts[n], toml::table{});
            next = t->get(parts[n]);
        }
        if (!next->is_table()) throw InputError(source + ": key '" + key + "': '" + at + "' is not a table");
        t = next->as_table();
    }
    return *t;
}

/// Sets dotted `key` of `root` to `v`.
void setPath(toml::table& root, const std::string& key, const Value& v, const std::string& source) {
    const std::vector<std::string> parts = splitKey(key);
    assignNode(parentTable(root, parts, source, key), parts.back(), v);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Scenario

struct Scenario::Impl {
    toml::table doc;             ///< the scenario as given (file text or keys set), before defaults
    cavesim::Scenario scenario;  ///< `doc` parsed and validated
    std::string source;          ///< name in messages

    /// Applies `edit` to a copy of the document; commits only when it parses.
    template <typename F>
    void change(F edit) {
        toml::table next = doc;
        edit(next);
        cavesim::Scenario parsed = parseScenarioTable(next, source);
        doc = std::move(next);
        scenario = std::move(parsed);
    }
};

Scenario::Scenario() : impl_(std::make_unique<Impl>()) {
    impl_->scenario = defaultScenario();
    impl_->doc = scenarioTable(impl_->scenario);
    impl_->source = impl_->scenario.path;
}

Scenario::Scenario(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Scenario::Scenario(const Scenario& other) : impl_(std::make_unique<Impl>(*other.impl_)) {}
Scenario::Scenario(Scenario&& other) noexcept = default;
Scenario& Scenario::operator=(const Scenario& other) {
    if (this != &other) impl_ = std::make_unique<Impl>(*other.impl_);
    return *this;
}
Scenario& Scenario::operator=(Scenario&& other) noexcept = default;
Scenario::~Scenario() = default;

Scenario Scenario::fromTomlFile(const std::string& path) {
    auto impl = std::make_unique<Impl>();
    impl->scenario = parseScenarioFile(path);  // every check and message of `cavesim validate`
    impl->doc = toml::parse_file(path);        // parses: the file just did
    impl->source = path;
    return Scenario(std::move(impl));
}

Scenario Scenario::fromTomlString(const std::string& text, const std::string& sourceName) {
    auto impl = std::make_unique<Impl>();
    impl->scenario = parseScenarioString(text, sourceName);
    impl->doc = toml::parse(text, sourceName);
    impl->source = sourceName;
    return Scenario(std::move(impl));
}

Scenario Scenario::fromTable(const Value& table, const std::string& sourceName) {
    if (!table.isTable() && !(table.kind() == Value::Kind::kList && table.items().empty()))
        throw InputError(sourceName + ": a scenario is a table of keys, not " + kindName(table.kind()));
    auto impl = std::make_unique<Impl>();
    impl->source = sourceName;
    impl->change([&](toml::table& doc) {
        for (std::size_t n = 0; n < table.keys().size(); ++n)
            setPath(doc, table.keys()[n], table.items()[n], sourceName);
    });
    return Scenario(std::move(impl));
}

void Scenario::set(const std::string& key, const Value& value) {
    impl_->change([&](toml::table& doc) { setPath(doc, key, value, impl_->source); });
}

void Scenario::update(const Value& table) {
    if (!table.isTable())
        throw InputError(impl_->source + ": update takes a table of keys, not " + kindName(table.kind()));
    impl_->change([&](toml::table& doc) {
        for (std::size_t n = 0; n < table.keys().size(); ++n)
            setPath(doc, table.keys()[n], table.items()[n], impl_->source);
    });
}

void Scenario::add(const std::string& tableArray, const Value& entry) {
    impl_->change([&](toml::table& doc) {
        const std::vector<std::string> parts = splitKey(tableArray);
        toml::table& parent = parentTable(doc, parts, impl_->source, tableArray);
        if (!parent.get(parts.back())) parent.insert_or_assign(parts.back(), toml::array{});
        toml::array* a = parent.get(parts.back())->as_array();
        if (!a) throw InputError(impl_->source + ": key '" + tableArray + "' is not a table of arrays");
        if (!entry.isTable())
            throw InputError(impl_->source + ": key '" + tableArray + "': an entry is a table, not " +
                             kindName(entry.kind()));
        a->push_back(toTomlTable(entry));
    });
}

void Scenario::clear(const std::string& tableArray) {
    impl_->change([&](toml::table& doc) {
        const std::vector<std::string> parts = splitKey(tableArray);
        toml::table& parent = parentTable(doc, parts, impl_->source, tableArray);
        const toml::node* n = parent.get(parts.back());
        if (n && !n->is_array())
            throw InputError(impl_->source + ": key '" + tableArray + "' is not a table of arrays");
        parent.erase(parts.back());
    });
}

Value Scenario::get(const std::string& key) const {
    const toml::table all = scenarioTable(impl_->scenario, true);
    const toml::node* n = &all;
    for (const std::string& part : splitKey(key)) {
        n = n->is_table() ? n->as_table()->get(part) : nullptr;
        if (!n) break;
    }
    if (!n || key.empty()) throw InputError(impl_->source + ": unknown key '" + key + "'");
    return fromNode(*n);
}

Value Scenario::toTable() const {
    return fromNode(scenarioTable(impl_->scenario));
}
std::string Scenario::toToml() const {
    return scenarioToToml(impl_->scenario);
}
std::string Scenario::name() const {
    return impl_->scenario.name;
}
std::uint64_t Scenario::seed() const {
    return impl_->scenario.seed;
}
std::array<int, 3> Scenario::size() const {
    return impl_->scenario.size;
}
double Scenario::voxelSize() const {
    return impl_->scenario.voxelSize;
}
std::string Scenario::sourceName() const {
    return impl_->source;
}

std::vector<std::string> Scenario::keys() {
    std::vector<std::string> out;
    for (const ParamSection& section : scenarioParameters()) {
        if (section.isArray) {
            out.push_back(section.path);
            continue;
        }
        for (const Param& p : section.params) out.push_back(section.qualified(p.key));
    }
    return out;
}

// ---------------------------------------------------------------------------------------------
// Result and run

struct Result::Impl {
    Scenario scenario;
    Domain domain;
    Grid3<float> porosity;  ///< as state.vdb records it
    Grid3<std::uint8_t> caveMask;
    Mesh mesh;
    Skeleton skeleton;
    Report report;
};

Result::Result(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Result::Result(Result&&) noexcept = default;
Result& Result::operator=(Result&&) noexcept = default;
Result::~Result() = default;

namespace {

template <typename T>
GridView<T> view(const Grid3<T>& g) {
    return GridView<T>{g.data.data(), {g.dims.nx, g.dims.ny, g.dims.nz}};
}

}  // namespace

std::array<int, 3> Result::dims() const {
    const Dims& d = impl_->domain.dims;
    return {d.nx, d.ny, d.nz};
}
double Result::voxelSize() const {
    return impl_->domain.voxelSize;
}
std::array<double, 3> Result::worldFromIndex(double i, double j, double k) const {
    const double h = impl_->domain.voxelSize;
    return {(i + 0.5) * h, (j + 0.5) * h, (k + 0.5) * h};
}
std::array<double, 3> Result::indexFromWorld(double x, double y, double z) const {
    const double h = impl_->domain.voxelSize;
    return {x / h - 0.5, y / h - 0.5, z / h - 0.5};
}
GridView<float> Result::porosity() const {
    return view(impl_->porosity);
}
GridView<float> Result::porosity0() const {
    return view(impl_->domain.porosity0);
}
GridView<float> Result::pressure() const {
    return view(impl_->domain.pressure);
}
GridView<float> Result::flow() const {
    return view(impl_->domain.flow);
}
GridView<float> Result::water() const {
    return view(impl_->domain.water);
}
GridView<std::uint8_t> Result::flags() const {
    return view(impl_->domain.flags);
}
GridView<std::int32_t> Result::zone() const {
    return view(impl_->domain.zone);
}
GridView<std::uint8_t> Result::caveMask() const {
    return view(impl_->caveMask);
}
const Mesh& Result::mesh() const {
    return impl_->mesh;
}
const Skeleton& Result::skeleton() const {
    return impl_->skeleton;
}
const Report& Result::report() const {
    return impl_->report;
}
const Scenario& Result::scenario() const {
    return impl_->scenario;
}

void Result::writeState(const std::string& path) const {
    app::writeState(path, impl_->domain, impl_->scenario.impl().scenario, app::StateMoment::kFinal);
}

namespace {

/// The checks of `RunOptions`' checkpoint fields, before any work.
/// @throw InputError for a negative interval, an interval without a path or a path in no folder
void checkCheckpointOptions(const RunOptions& o) {
    if (o.checkpointEvery < 0)
        throw InputError("checkpoint interval " + std::to_string(o.checkpointEvery) +
                         ": must be 0 (no checkpoints) or a number of stage-2 iterations");
    if (o.checkpointEvery == 0) return;
    if (o.checkpointPath.empty())
        throw InputError("checkpoints every " + std::to_string(o.checkpointEvery) +
                         " iteration(s) need a checkpoint file path");
    namespace fs = std::filesystem;
    const fs::path parent = fs::path(o.checkpointPath).parent_path();
    std::error_code ec;
    if (!parent.empty() && !fs::is_directory(parent, ec))
        throw InputError(o.checkpointPath + ": cannot write a checkpoint there: " + parent.string() +
                         " is not a folder");
}

/// `scenario` with its [site]'s files read, checked and sampled onto the block.
cavesim::Scenario withSiteLoaded(const Scenario& scenario) {
    cavesim::Scenario s = scenario.impl().scenario;
    site::loadSite(s);
    return s;
}

/// `run` of `scenario` (`s`: withSiteLoaded(scenario), its options checked), or with `resume`
/// (read from the file `shown`, checked against `s` by app::checkResumable) its continuation.
std::unique_ptr<Result::Impl> runWith(const Scenario& scenario, const cavesim::Scenario& s, const RunOptions& options,
                                      const app::Checkpoint* resume, const std::string& shown) {
    const cavesim::Scenario& base = scenario.impl().scenario;
    const int threads = options.threads > 0 ? options.threads : int(tbb::info::default_concurrency());
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    const CancelToken cancel = options.cancel;
    const cavesim::ProgressFn progress = [&](const std::string& phase, long done, long total) {
        if (cancel.cancelled()) throw Cancelled("run of scenario '" + s.name + "' cancelled during " + phase);
        if (options.progress) options.progress(phase, done, total);
    };

    auto out = std::make_unique<Result::Impl>();
    out->scenario = scenario;
    Report& report = out->report;
    const Stopwatch t0;
    app::RunRecord rec;
    rec.threads = threads;

    // The simulation, as app/pipeline.cpp runs it (app::runStages: the same calls and random draws).
    reportProgress(progress, "domain", 0, 1);
    Rng rng(s.seed);
    Domain dom = buildDomain(s, rng);
    reportProgress(progress, "domain", 1, 1);
    app::StageHooks hooks;
    if (!options.stage1StatePath.empty())
        hooks.afterStage1 = [&](const Domain& d, const app::RunRecord&) {
            app::writeState(options.stage1StatePath, d, s, app::StateMoment::kAfterStage1);
        };
    // Checkpoints in the command's format (app/checkpoint.h): the effective scenario as its text
    // under the scenario's name, so that app::checkpointScenario reads it back; no pictures.
    app::Checkpoint made;
    if (options.checkpointEvery > 0) {
        made.scenarioPath = base.path.empty() ? std::string("<library>") : base.path;
        made.scenarioText = scenarioToToml(base);
        made.every = options.checkpointEvery;
        made.scenarioHash = app::scenarioHash(s);
    }
    app::wireCheckpoints(
        hooks, resume, shown, "start the run again", options.checkpointEvery, made, [&](app::Checkpoint& c) {
            writeFileAtomic(options.checkpointPath, app::encodeCheckpoint(c));  // RuntimeError when it fails
        });
    app::runStages(dom, s, rng, rec, progress, hooks);
    if (rec.stage1) {
        report.zones = rec.stage1->zones;
        report.protochannelVoxels = rec.stage1->protochannelVoxels;
    }
    if (rec.stage2) {
        report.iterations = rec.stage2->iterations;
        report.breakthroughIteration = rec.stage2->breakthroughIteration;
        report.sourceConnectedIteration = rec.stage2->sourceConnectedIteration;
        if (!rec.stage2->history.empty()) report.channelVoxels = rec.stage2->history.back().channelVoxels;
    }

    const Cave cave = makeCave(dom, s.output.cave);
    if (options.mesh) {
        reportProgress(progress, "mesh", 0, 1);
        const Stopwatch tm;
        const mesh::TriangleMesh triangles = mesh::buildCaveMesh(cave.mask, cave.voxelSize, mesh::MeshOptions{});
        mesh::MeshStats stats;
        if (!triangles.triangles.empty()) {
            stats = mesh::measureMesh(triangles);
            stats.seconds = tm.seconds();
            const SurfaceMesh surface = mesh::toSurfaceMesh(triangles);
            out->mesh = Mesh{surface.vertices, surface.normals, surface.triangles};
        }
        rec.mesh = app::meshJson(stats);
        rec.timing.mesh = tm.seconds();
        report.meshVertices = stats.vertices;
        report.meshFaces = stats.faces;
        report.meshAreaM2 = stats.areaM2;
        report.meshVolumeM3 = stats.volumeM3;
        report.meshClosed = stats.closed;
        reportProgress(progress, "mesh", 1, 1);
    }
    if (options.analysis) {
        reportProgress(progress, "analysis", 0, 1);
        const Stopwatch tr;
        const morpho::CaveAnalysis a = app::analyseRun(cave, dom, s, app::connectedIterations(rec));
        rec.analysis = app::analysisJson(a);
        rec.timing.report = tr.seconds();
        for (const morpho::SkeletonNode& n : a.skeleton.nodes) {
            const Index3 v = dom.dims.coord(n.voxel);
            out->skeleton.nodes.push_back({{n.position[0], n.position[1], n.position[2]}, n.radius, {v.i, v.j, v.k}});
        }
        out->skeleton.edges = a.skeleton.edges;
        const morpho::NetworkCounts& c = a.network;
        report.sourcesTotal = c.sourcesTotal;
        report.sourcesConnected = c.sourcesConnected;
        report.confluences = c.confluences;
        report.tributaryCaptures = c.tributaryCaptures;
        report.phreaticLoops = c.phreaticLoops;
        report.skeletonNodes = long(a.skeleton.nodes.size());
        report.skeletonEdges = long(a.skeleton.edges.size());
        const morpho::Morphometry& m = a.morphometry;
        report.lengthM = m.length_m;
        report.areaM2 = m.area_m2;
        report.volumeM3 = m.volume_m3;
        report.networkDensityOpt = m.network_density_opt;
        report.networkDensityRect = m.network_density_rect;
        report.arealCoveragePctOpt = m.areal_coverage_pct_opt;
        report.arealCoveragePctRect = m.areal_coverage_pct_rect;
        report.porosityPctOpt = m.porosity_pct_opt;
        report.porosityPctRect = m.porosity_pct_rect;
        report.meanWidthM = m.mean_width_m;
        report.caveCategory = morpho::caveCategory(m);
        reportProgress(progress, "analysis", 1, 1);
    }
    rec.timing.total = t0.seconds();

    report.scenario = s.name;
    report.seed = s.seed;
    report.threads = threads;
    report.timing = {rec.timing.stage1, rec.timing.stage2, rec.timing.mesh, rec.timing.report, rec.timing.total};
    if (!s.fractureFamilies.empty()) rec.fractures = app::measuredFractureNetwork(s);
    report.json = app::buildReportJson(s, dom, rec).dump(2);
    out->porosity = app::recordedPorosity(dom, s, app::StateMoment::kFinal);
    out->caveMask = cave.mask;
    out->domain = std::move(dom);
    return out;
}

}  // namespace

Result run(const Scenario& scenario, const RunOptions& options) {
    checkCheckpointOptions(options);
    return Result(runWith(scenario, withSiteLoaded(scenario), options, nullptr, std::string()));
}

Result resume(const std::string& checkpointPath, const RunOptions& options) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(checkpointPath, ec))
        throw InputError(checkpointPath + ": no checkpoint to resume from (no such file)");
    const app::Checkpoint c = app::decodeCheckpoint(readFileBytes(checkpointPath), checkpointPath);
    const cavesim::Scenario read = app::checkpointScenario(c);
    // The scenario as a public Scenario: its effective text (overrides included) under its name.
    const Scenario scenario = Scenario::fromTomlString(scenarioToToml(read), read.path);
    const cavesim::Scenario s = withSiteLoaded(scenario);
    app::checkResumable(c, s, checkpointPath);
    checkCheckpointOptions(options);
    return Result(runWith(scenario, s, options, &c, checkpointPath));
}

}  // namespace cavesim::api

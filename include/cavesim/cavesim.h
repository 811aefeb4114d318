/// @file cavesim.h
/// @brief cavesim as a library: build or read a scenario, run it, and read the grids, the cave
/// mesh, the skeleton and the report in memory (Pytel & Mann, JCGT 2015, the whole two-stage
/// process of §3–§4 and the measurements of §4.2). The one public header of `cavesim::cavesim`.
///
/// Only the standard library appears here (no OpenVDB, Eigen, TBB or toml++): a `Scenario` and a
/// `Result` keep their state behind a pointer. Errors are the library's exceptions
/// (cavesim/error.h): `InputError` for a bad scenario, key or value, with the message the
/// `cavesim` command prints; `RuntimeError` for a failure while running; `Cancelled` when a run
/// was cancelled; `InternalError` for a bug.
///
/// Spaces: grids are in index space, voxel (i, j, k) = (x, y, z), z up, stored x-fastest
/// (`index = i + nx·(j + ny·k)`, so a C array of shape (nz, ny, nx) views them without a copy).
/// World space is metres: voxel (i, j, k) has its centre at ((i, j, k) + 0.5) · voxelSize, so the
/// block spans [0, n · voxelSize] on each axis (`Result::worldFromIndex`). Meshes and skeletons are
/// in world space. The full guide: docs/library.md.
///
/// @code
/// cavesim::api::Scenario s = cavesim::api::Scenario::fromTomlFile("scenarios/fig10.toml");
/// s.set("stage2.p_rate", 0.4);
/// cavesim::api::Result r = cavesim::api::run(s);
/// float phi = r.porosity().at(30, 30, 10);
/// @endcode
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "cavesim/error.h"

namespace cavesim::api {

/// The library's version ("0.1.0"), the same as `cavesim --version`.
std::string version();

/// A scenario value as TOML holds it: a boolean, an integer, a real number, a string, a list or
/// a table (keys in order). Built implicitly from C++ values; `{1, 2, 3}` is a list,
/// `Value::table({{"at", {1, 2, 3}}, {"pressure", 1.0}})` a table, `Value::list({t})` a list of one
/// table.
class Value {
public:
    enum class Kind { kBool, kInt, kReal, kString, kList, kTable };
    using Entry = std::pair<std::string, Value>;

    Value() : Value(std::vector<Value>{}) {}  ///< an empty list
    Value(bool v) : kind_(Kind::kBool), int_(v) {}
    template <typename T, std::enable_if_t<std::is_integral_v<T> && !std::is_same_v<T, bool>, int> = 0>
    Value(T v) : kind_(Kind::kInt), int_(std::int64_t(v)) {}
    Value(double v) : kind_(Kind::kReal), real_(v) {}
    Value(const char* v) : kind_(Kind::kString), string_(v) {}
    Value(std::string v) : kind_(Kind::kString), string_(std::move(v)) {}
    Value(std::initializer_list<Value> items) : kind_(Kind::kList), items_(items) {}
    Value(std::vector<Value> items) : kind_(Kind::kList), items_(std::move(items)) {}
    /// A table of `entries` (keys may be dotted: {"stage2.p_rate", 0.4}).
    static Value table(const std::vector<Entry>& entries);
    /// A list of `items`. Needed for a list of one Value: C++ reads `{v}` as a copy of `v`, so a
    /// one-entry table of arrays is `Value::list({Value::table(…)})`.
    static Value list(std::vector<Value> items) { return Value(std::move(items)); }

    Kind kind() const { return kind_; }
    bool isTable() const { return kind_ == Kind::kTable; }
    /// The value; throws InputError naming the expected kind when it holds another.
    bool asBool() const;
    std::int64_t asInt() const;
    double asReal() const;  ///< an integer converts
    const std::string& asString() const;
    /// A list's elements, or a table's values (in the order of `keys()`).
    const std::vector<Value>& items() const { return items_; }
    /// A table's keys (empty otherwise).
    const std::vector<std::string>& keys() const { return keys_; }
    /// A table's value at `key`, or nullptr.
    const Value* find(const std::string& key) const;
    /// Appends `key = value` to a table (replacing an equal key).
    void insert(const std::string& key, Value value);

private:
    Kind kind_ = Kind::kList;
    std::int64_t int_ = 0;
    double real_ = 0;
    std::string string_;
    std::vector<Value> items_;
    std::vector<std::string> keys_;
};

/// A validated scenario: what a scenario file holds (docs/scenario-format.md). Always valid: a
/// change that would make it invalid throws InputError and leaves it as it was.
///
/// Keys are the TOML keys, dotted with their table: "seed", "domain.size", "stage2.p_rate",
/// "rock.noise.scale". The tables of arrays ("source", "sink", "rock.sphere", "rock.plane",
/// "rock.channel") are set as a whole (a list of tables) or entry by entry (`add`). Each change is
/// checked exactly as the file parser checks a file with that content (the same messages, without
/// line numbers for what was set in code).
class Scenario {
public:
    /// The built-in default scenario (the paper's Figure 10, scenarios/fig10.toml).
    Scenario();
    /// Reads a scenario file. @throw InputError as `cavesim validate` reports it
    static Scenario fromTomlFile(const std::string& path);
    /// Reads scenario text; `sourceName` stands for the file name in messages.
    static Scenario fromTomlString(const std::string& text, const std::string& sourceName = "<string>");
    /// A scenario from a table shaped like a scenario file's root table (nested tables, or dotted
    /// keys), e.g. {"name": "x", "domain": {"size": [40, 40, 10]}, "source": [{"at": [..]}], ...};
    /// absent keys take their defaults, as in a file.
    static Scenario fromTable(const Value& table, const std::string& sourceName = "<table>");

    Scenario(const Scenario& other);
    Scenario(Scenario&& other) noexcept;
    Scenario& operator=(const Scenario& other);
    Scenario& operator=(Scenario&& other) noexcept;
    ~Scenario();

    /// Sets one key ("stage2.p_rate" = 0.4), or replaces every entry of a table of arrays
    /// ("source" = a list of tables).
    /// @throw InputError for an unknown key or a value the key does not allow
    void set(const std::string& key, const Value& value);
    /// Sets every key of `table` (dotted keys or nested tables) at once, checked together (so
    /// related keys, e.g. "domain.size" and the sources, may change in one step).
    void update(const Value& table);
    /// Appends one entry to a table of arrays ("source", "sink", "rock.sphere", …).
    void add(const std::string& tableArray, const Value& entry);
    /// Removes every entry of a table of arrays.
    void clear(const std::string& tableArray);

    /// The value of a key, defaults filled in; for a table of arrays the list of its entries.
    /// @throw InputError for an unknown key
    Value get(const std::string& key) const;
    /// The whole effective scenario as nested tables, every default filled in.
    Value toTable() const;
    /// The effective scenario as TOML (what a run writes to scenario.toml).
    std::string toToml() const;

    std::string name() const;
    std::uint64_t seed() const;
    std::array<int, 3> size() const;  ///< voxels (nx, ny, nz)
    double voxelSize() const;         ///< metres
    /// Where the scenario came from (file path, or the source name given).
    std::string sourceName() const;

    /// Every key `set` accepts, dotted, in file order (tables of arrays as their path).
    static std::vector<std::string> keys();

    struct Impl;
    /// Internal state (for the library's own code).
    const Impl& impl() const { return *impl_; }

private:
    explicit Scenario(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

/// Called during a run: `phase` names the work ("stage 1: flow networks", "stage 2", "mesh",
/// "analysis"), `done` of `total` units are finished. Calls never overlap; during stage 1 they
/// may come from worker threads. An exception thrown from it stops the run and is rethrown by
/// `run`.
using ProgressFn = std::function<void(const std::string& phase, long done, long total)>;

/// Cancels a run from any thread: copies share one flag; `run` (and `resume`) checks it at every
/// progress step (every stage-2 iteration) and throws `cavesim::Cancelled`; a checkpoint written
/// before stays complete.
class CancelToken {
public:
    CancelToken() : flag_(std::make_shared<std::atomic<bool>>(false)) {}
    void cancel() const { flag_->store(true); }
    bool cancelled() const { return flag_->load(); }

private:
    std::shared_ptr<std::atomic<bool>> flag_;
};

struct RunOptions {
    int threads = 0;  ///< worker threads; 0: all cores. Results do not depend on it.
    ProgressFn progress;
    CancelToken cancel;
    bool mesh = true;      ///< build the smooth cave mesh (cave.obj's triangles)
    bool analysis = true;  ///< skeletonize and measure the cave (the report's indices and metrics)
    /// When not empty, stage1.vdb is written there after stage 1, as `cavesim run` writes it.
    std::string stage1StatePath;
    /// Checkpoints: after every `checkpointEvery`-th stage-2 iteration (0: none; the last
    /// iteration takes none), stage 2's whole state is written to `checkpointPath`, replacing the
    /// previous checkpoint atomically, so the file always holds the newest complete one, whenever
    /// the run stops. `resume(checkpointPath)` finishes the run from it with the grids and report
    /// numbers of a run that never stopped. The file is the one `cavesim run --checkpoint-every`
    /// writes (docs/checkpoints.md); it stays after the run (remove it when it is no longer needed).
    std::string checkpointPath;
    int checkpointEvery = 0;  ///< stage-2 iterations between checkpoints; 0: none
};

/// Bits of the `flags` grid (the same as the run's `flags` grid in state.vdb).
enum VoxelFlag : std::uint8_t {
    kFlagSource = 1u << 0,
    kFlagSink = 1u << 1,
    kFlagProtochannel = 1u << 2,  ///< traced by stage 1 or given as [[rock.channel]]
    kFlagChannel = 1u << 3,       ///< eroded past the channel threshold in stage 2
    kFlagObstacle = 1u << 4,
    kFlagFracture = 1u << 5,
    kFlagFeatureChannel = 1u << 6,
    kFlagInert = 1u << 7,  ///< [site]: air above the land surface or insoluble rock (porosity 0, never eroded)
};

/// A read-only view of a dense grid owned by a `Result` (valid while the Result lives).
template <typename T>
struct GridView {
    const T* data = nullptr;
    std::array<int, 3> dims{};  ///< (nx, ny, nz)

    std::size_t size() const { return std::size_t(dims[0]) * std::size_t(dims[1]) * std::size_t(dims[2]); }
    /// Voxel (i, j, k), index space.
    const T& at(int i, int j, int k) const {
        return data[std::size_t(i) + std::size_t(dims[0]) * (std::size_t(j) + std::size_t(dims[1]) * std::size_t(k))];
    }
};

/// The smooth, closed cave surface (cave.obj's triangles): world space, metres, z up; triangles
/// counter-clockwise seen from the rock, normals out of the cave. Empty when there is no cave.
struct Mesh {
    std::vector<std::array<float, 3>> vertices;
    std::vector<std::array<float, 3>> normals;  ///< unit, one per vertex
    std::vector<std::array<int, 3>> triangles;  ///< indices into `vertices`
};

/// The cave's centreline graph (skeleton.json): nodes on centreline voxels, sorted by voxel.
struct Skeleton {
    struct Node {
        std::array<double, 3> position{};  ///< metres, world space (smoothed)
        double radius = 0;                 ///< metres: distance to the nearest wall
        std::array<int, 3> voxel{};        ///< (i, j, k) of its centreline voxel
    };
    std::vector<Node> nodes;
    std::vector<std::array<int, 2>> edges;  ///< undirected, a < b, sorted
};

/// What a run produced, as numbers; everything else is in `json` (report.json's document).
struct Report {
    std::string scenario;
    std::uint64_t seed = 0;
    int threads = 1;
    struct Timing {
        double stage1 = 0, stage2 = 0, mesh = 0, report = 0, total = 0;  ///< seconds
    } timing;
    // Stage 1 (zero when disabled).
    int zones = 0;
    long protochannelVoxels = 0;
    // Stage 2 (zero / empty when disabled).
    int iterations = 0;
    std::optional<int> breakthroughIteration;
    std::vector<std::optional<int>> sourceConnectedIteration;  ///< per source, scenario order
    long channelVoxels = 0;
    // The cave (with `RunOptions::analysis`): network counts (docs/network-definitions.md) …
    int sourcesTotal = 0, sourcesConnected = 0, confluences = 0, tributaryCaptures = 0, phreaticLoops = 0;
    long skeletonNodes = 0, skeletonEdges = 0;
    // … and morphometric indices (paper Tables 2–4): optimised field (Klimchouk: the plan with a
    // margin of half the mean passage spacing, within the convex hull) and rectangular field.
    double lengthM = 0, areaM2 = 0, volumeM3 = 0;
    double networkDensityOpt = 0, networkDensityRect = 0;      ///< m/m²
    double arealCoveragePctOpt = 0, arealCoveragePctRect = 0;  ///< %
    double porosityPctOpt = 0, porosityPctRect = 0;            ///< %
    double meanWidthM = 0;                                     ///< W
    std::string caveCategory;
    // The mesh (with `RunOptions::mesh`).
    long meshVertices = 0, meshFaces = 0;
    double meshAreaM2 = 0, meshVolumeM3 = 0;
    bool meshClosed = false;
    /// The report.json document of this run (pretty-printed): as `cavesim run` writes it, except
    /// "files", which is empty (nothing was written).
    std::string json;
};

/// The outcome of `run`: the final grids, the cave, its mesh, skeleton and report.
class Result {
public:
    Result(Result&&) noexcept;
    Result& operator=(Result&&) noexcept;
    ~Result();

    std::array<int, 3> dims() const;  ///< (nx, ny, nz)
    double voxelSize() const;         ///< metres
    /// World position (metres) of index-space point (i, j, k): ((i, j, k) + 0.5) · voxelSize, so
    /// integer (i, j, k) gives voxel (i, j, k)'s centre.
    std::array<double, 3> worldFromIndex(double i, double j, double k) const;
    /// The inverse: x / voxelSize − 0.5, …; the voxel holding a world point is the nearest integer.
    std::array<double, 3> indexFromWorld(double x, double y, double z) const;

    /// Porosity R in [0, 1] as state.vdb records it (after stage 1 alone the protochannels show
    /// opened, see app/state.h).
    GridView<float> porosity() const;
    GridView<float> porosity0() const;        ///< porosity as built, before the stages
    GridView<float> pressure() const;         ///< stage 2's pressure (zero without stage 2)
    GridView<float> flow() const;             ///< stage 2's flow of the last iteration
    GridView<float> water() const;            ///< stage 2's water contents
    GridView<std::uint8_t> flags() const;     ///< `VoxelFlag` bits
    GridView<std::int32_t> zone() const;      ///< stage-1 zone (source index), −1 where none
    GridView<std::uint8_t> caveMask() const;  ///< 1 where a voxel is cave (the [output] cave definition)

    const Mesh& mesh() const;          ///< empty without `RunOptions::mesh`
    const Skeleton& skeleton() const;  ///< empty without `RunOptions::analysis`
    const Report& report() const;
    const Scenario& scenario() const;

    /// Writes the final state as `cavesim run` writes state.vdb: byte for byte the same file for
    /// the same scenario and seed.
    /// @throw RuntimeError when the file cannot be written
    void writeState(const std::string& path) const;

    struct Impl;

private:
    friend Result run(const Scenario& scenario, const RunOptions& options);
    friend Result resume(const std::string& checkpointPath, const RunOptions& options);
    explicit Result(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

/// Runs `scenario`: the domain, the enabled stages, then (as asked) the mesh and the analysis.
/// The grids equal those of `cavesim run` for the same scenario and seed, whatever `threads`.
/// @throw InputError for a limit the scenario exceeds (with the command's message); RuntimeError
///        on a failure while running; Cancelled when `options.cancel` was cancelled; whatever the
///        progress callback threw
Result run(const Scenario& scenario, const RunOptions& options = {});

/// Finishes a run from its checkpoint at `checkpointPath` (written by `run` with
/// `RunOptions::checkpointPath`, or by `cavesim run --checkpoint-every`: the file
/// `.DIR.checkpoint/checkpoint.cavesim`): the checkpoint holds the scenario (its text, seed and
/// overrides), so none is given. Builds the domain and runs stage 1 again (deterministic), checks
/// that they are the ones the checkpoint was made from, then continues stage 2 after the
/// checkpoint's iteration. The grids and the report's numbers (timings aside; `timing.stage2`
/// counts the resumed part only) equal those of a run that never stopped, whatever `threads`.
/// `options` are those of `run`; with `checkpointPath` (it may be the file resumed from) the
/// resumed run writes checkpoints in turn. `Result::scenario()` is the checkpoint's scenario.
/// @throw InputError when the file is missing, is not a complete checkpoint (cut, damaged, not a
///        checkpoint), or no longer matches its scenario or domain; otherwise as `run`
Result resume(const std::string& checkpointPath, const RunOptions& options = {});

}  // namespace cavesim::api

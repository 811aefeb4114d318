#include "app/state.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <new>
#include <stdexcept>

#include "app/state_file.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/fnv.h"
#include "mesh/vdb_io.h"
#include "sim/stage1.h"

namespace fs = std::filesystem;

namespace cavesim::app {
namespace {

std::string shortNumber(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

/// The `# state.cavesim: {...}` comment a run appends to its scenario.toml, or null.
nlohmann::json recordedInScenario(const fs::path& scenario) {
    std::ifstream in(scenario);
    const std::string tag = std::string("# ") + kCheckedStateFile + ": ";
    for (std::string line; std::getline(in, line);) {
        if (line.compare(0, tag.size(), tag) != 0) continue;
        if (line.size() > 4096) return nullptr;  // a record is one short line
        try {
            return nlohmann::json::parse(line.substr(tag.size()),
                                         [](int depth, nlohmann::json::parse_event_t, nlohmann::json&) {
                                             if (depth > 8) throw std::length_error("nested");
                                             return true;
                                         });
        } catch (const std::exception&) {
            return nullptr;
        }
    }
    return nullptr;
}

/// Throws unless every value of `g` satisfies `ok`: a grid that holds what no run writes is damage.
template <typename T, typename Ok>
void checkGrid(const Grid3<T>& g, const std::string& vdb, const char* name, const char* allowed, Ok ok) {
    for (std::size_t v = 0; v < g.size(); ++v)
        if (!ok(g[v]))
            throw InputError(vdb + ": grid '" + name + "' holds " + shortNumber(double(g[v])) + " at voxel " +
                             std::to_string(v) + " (" + allowed + "): the file is damaged; rerun `cavesim run`");
}

}  // namespace

Grid3<float> recordedPorosity(const Domain& dom, const Scenario& s, StateMoment moment) {
    if (moment == StateMoment::kAfterStage1 || !s.stage2.enabled)
        return stage1DisplayPorosity(dom, s.stage1.protochannelPorosity);
    return dom.porosity;
}

namespace {

/// The grids of a state file, in the order they are written.
struct StateGrids {
    Grid3<float> porosity;
    Grid3<std::int32_t> flags;
    std::vector<mesh::NamedGrid> grids;
};

void collectGrids(StateGrids& out, const Domain& dom, const Scenario& s, StateMoment moment) {
    const bool stage2 = moment == StateMoment::kFinal && s.stage2.enabled;
    out.porosity = recordedPorosity(dom, s, moment);
    const Grid3<float>& porosity = out.porosity;
    out.flags = Grid3<std::int32_t>(dom.dims, 0);
    Grid3<std::int32_t>& flags = out.flags;
    for (std::size_t v = 0; v < flags.size(); ++v) flags[v] = dom.flags[v];
    std::vector<mesh::NamedGrid>& grids = out.grids;
    grids = {
        {"porosity", &porosity, nullptr, "porosity R in [0,1] (water capacity)"},
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
}

nlohmann::json fingerprintJson(std::uint64_t bytes, const Fnv1a64& h) {
    return {{"bytes", bytes}, {"fnv1a64", h.hex()}};
}

/// A file read once: its fingerprint (as fileFingerprint) and its bytes, kept only while there are
/// at most `keepLimit` of them (`tooLarge` then says they were dropped).
struct FileRead {
    nlohmann::json fingerprint;
    std::string bytes;
    bool tooLarge = false;
};

FileRead readFile(const std::string& path, std::uint64_t keepLimit) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw RuntimeError("cannot read " + path);
    FileRead out;
    Fnv1a64 h;
    std::uint64_t bytes = 0;
    char buf[1 << 16];
    while (in) {
        in.read(buf, sizeof buf);
        const std::streamsize n = in.gcount();
        h.add(buf, std::size_t(n));
        bytes += std::uint64_t(n);
        if (out.tooLarge) continue;
        out.bytes.append(buf, std::size_t(n));
        if (out.bytes.size() > keepLimit) {
            out.tooLarge = true;
            std::string().swap(out.bytes);
        }
    }
    out.fingerprint = fingerprintJson(bytes, h);
    return out;
}

}  // namespace

void writeState(const std::string& path, const Domain& dom, const Scenario& s, StateMoment moment) {
    StateGrids g;
    collectGrids(g, dom, s, moment);
    mesh::writeVdb(path, g.grids, dom.voxelSize, dom.origin);
}

nlohmann::json writeFinalState(const fs::path& dir, const Domain& dom, const Scenario& s) {
    StateGrids g;
    collectGrids(g, dom, s, StateMoment::kFinal);
    const std::string vdbPath = (dir / "state.vdb").string();
    mesh::writeVdb(vdbPath, g.grids, dom.voxelSize, dom.origin);
    std::vector<StateGridRef> refs;
    for (const mesh::NamedGrid& n : g.grids) refs.push_back({n.name, n.floats, n.ints});
    const std::string checked = encodeState(dom.dims, dom.voxelSize, refs);
    writeFileAtomic((dir / kCheckedStateFile).string(), checked);
    Fnv1a64 h;  // the bytes just written: no need to read them back
    h.add(checked.data(), checked.size());
    return {{"state.vdb", stateRecord(fileFingerprint(vdbPath), s)},
            {kCheckedStateFile, stateRecord(fingerprintJson(checked.size(), h), s)}};
}

nlohmann::json fileFingerprint(const std::string& path) {
    return readFile(path, 0).fingerprint;
}

nlohmann::json stateRecord(const nlohmann::json& fingerprint, const Scenario& s) {
    nlohmann::json r = fingerprint;
    r["grid"] = {s.size[0], s.size[1], s.size[2]};
    r["voxel_size_m"] = s.voxelSize;
    return r;
}

Domain loadState(const fs::path& dir, const Scenario& s, const nlohmann::json& report) {
    const std::string file = (dir / kCheckedStateFile).string();
    // The run recorded the file's size, checksum and grid in report.json and in the last line of
    // scenario.toml; a file that does not match its record is refused before it is decoded.
    std::error_code ec;
    if (!fs::is_regular_file(file, ec))
        throw InputError(file + ": not a regular file; `cavesim report` needs the run's " + kCheckedStateFile);
    const auto usable = [](const nlohmann::json& r) {
        return r.is_object() && r.contains("bytes") && r["bytes"].is_number_unsigned() && r.contains("fnv1a64") &&
               r["fnv1a64"].is_string() && r.contains("grid") && r["grid"].is_array() && r["grid"].size() == 3 &&
               r.contains("voxel_size_m") && r["voxel_size_m"].is_number();
    };
    nlohmann::json then;
    if (report.contains("files") && report["files"].is_object() && report["files"].contains(kCheckedStateFile))
        then = report["files"][kCheckedStateFile];
    if (!usable(then)) then = recordedInScenario(dir / "scenario.toml");
    if (!usable(then))
        throw InputError(file +
                         ": no usable record of it (report.json `files` and the last line of scenario.toml "
                         "are missing or damaged), so it cannot be checked before reading; rerun `cavesim run`");
    const Dims dims{s.size[0], s.size[1], s.size[2]};
    // No state file is larger than its grids stored uncompressed (zlib adds 0.1 % at worst) plus headers.
    const std::uint64_t limit = std::uint64_t(kMaxStateGrids) * (dims.count() * 4 * 1002 / 1000 + 4096) + 4096;
    FileRead read;
    try {
        read = readFile(file, limit);  // once: checked against the record, then decoded
    } catch (const std::bad_alloc&) {
        throw InputError(file + ": cannot be read (it asks for more memory than there is)");
    }
    const nlohmann::json& now = read.fingerprint;
    if (now["bytes"] != then["bytes"] || now["fnv1a64"] != then["fnv1a64"])
        throw InputError(file + ": changed since the run wrote it (now " + now.dump() + ", the run recorded " +
                         then.dump() + "); rerun `cavesim run`");
    if (then["grid"] != nlohmann::json{s.size[0], s.size[1], s.size[2]} || then["voxel_size_m"] != s.voxelSize)
        throw InputError((dir / "scenario.toml").string() + ": describes a grid of " + std::to_string(s.size[0]) +
                         " x " + std::to_string(s.size[1]) + " x " + std::to_string(s.size[2]) + " voxels of " +
                         shortNumber(s.voxelSize) + " m, but the run's " + kCheckedStateFile + " holds " +
                         then["grid"].dump() + " of " + then["voxel_size_m"].dump() +
                         " m: the scenario was edited; rerun `cavesim run`");
    Domain dom = emptyDomain(dims, s.voxelSize, 0.f);
    dom.origin = {s.site.origin[0], s.site.origin[1], s.site.origin[2]};
    placeTerminals(dom, s);
    if (read.tooLarge)
        throw InputError(file + ": larger than any state file of this grid; damaged, or not written by `cavesim run`");
    StateContents state;
    try {
        state = decodeState(read.bytes, file, dom.dims);
    } catch (const std::bad_alloc&) {
        throw InputError(file + ": cannot be read (it asks for more memory than there is)");
    }
    std::string().swap(read.bytes);
    if (state.voxelSize != s.voxelSize)
        throw InputError(file + ": holds voxels of " + shortNumber(state.voxelSize) + " m where the scenario says " +
                         shortNumber(s.voxelSize) + " m; rerun `cavesim run`");
    const auto take = [&](const char* name, bool isFloat) -> StateGrid& {
        for (StateGrid& g : state.grids)
            if (g.name == name) {
                if (g.isFloat != isFloat)
                    throw InputError(file + ": grid '" + name +
                                     "' has the wrong type; damaged, or not written by `cavesim run`");
                return g;
            }
        throw InputError(file + ": has no grid '" + name + "'; damaged, or not written by `cavesim run`");
    };
    dom.porosity = std::move(take("porosity", true).floats);
    dom.porosity0 = std::move(take("porosity0", true).floats);
    dom.zone = std::move(take("zone", false).ints);
    const Grid3<std::int32_t> flags = std::move(take("flags", false).ints);
    checkGrid(flags, file, "flags", "flags are 0-255", [](std::int32_t f) { return f >= 0 && f <= 255; });
    for (std::size_t v = 0; v < flags.size(); ++v) dom.flags[v] = std::uint8_t(flags[v]);
    if (s.stage2.enabled) {
        dom.pressure = std::move(take("pressure", true).floats);
        dom.flow = std::move(take("flow", true).floats);
        dom.water = std::move(take("water", true).floats);
    }
    const std::string& vdb = file;
    const auto unit = [](float r) { return r >= 0.f && r <= 1.f; };  // false for NaN
    const auto nonNegative = [](float r) { return std::isfinite(r) && r >= 0.f; };
    checkGrid(dom.porosity, vdb, "porosity", "porosity is in [0, 1]", unit);
    checkGrid(dom.porosity0, vdb, "porosity0", "porosity is in [0, 1]", unit);
    const int nSources = int(dom.sourceVoxels.size());  // with a site's sinkholes
    checkGrid(dom.zone, vdb, "zone", "zones are -1 or a source index",
              [nSources](std::int32_t z) { return z >= -1 && z < nSources; });
    checkGrid(dom.pressure, vdb, "pressure", "pressure is finite and not negative", nonNegative);
    checkGrid(dom.flow, vdb, "flow", "flow is finite and not negative", nonNegative);
    // Water is stored to round-off: a transfer that empties a voxel can leave -1e-18.
    checkGrid(dom.water, vdb, "water", "water is finite and not below -1e-6",
              [](float w) { return std::isfinite(w) && w >= -1e-6f; });
    return dom;
}

}  // namespace cavesim::app

#include "formats/exports.h"

#include <array>
#include <filesystem>
#include <optional>

#include "core/error.h"
#include "formats/csv_formats.h"
#include "formats/gocad_formats.h"
#include "formats/survey_formats.h"
#include "formats/vtk_formats.h"
#include "mesh/vdb_io.h"
#include "sim/cave.h"

namespace cavesim::formats {
namespace {

constexpr std::array<const char*, 8> kNames{"glb", "vtk", "stl", "svx", "th", "gocad", "csv", "vdb"};

std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(" \t");
    if (b == std::string::npos) return "";
    return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

}  // namespace

FormatSet parseFormatSet(const std::string& list) {
    FormatSet set;
    std::string allowed;
    for (const char* n : kNames) allowed += std::string(allowed.empty() ? "" : ", ") + n;
    allowed += ", all, none";
    std::size_t at = 0;
    for (;;) {
        const std::size_t comma = list.find(',', at);
        const std::string item = trim(list.substr(at, comma == std::string::npos ? std::string::npos : comma - at));
        if (item == "none" && (at > 0 || comma != std::string::npos))
            throw InputError("formats \"" + list + "\": \"none\" stands alone (it was ignored beside other entries)");
        // A format listed twice is refused, as in the scenario's `[output] formats` ("all" lists each).
        const auto addOnce = [&](std::size_t f) {
            if (set.has(Format(f)))
                throw InputError("formats \"" + list + "\": \"" + kNames[f] +
                                 "\" is listed twice (give each format once; \"all\" lists every one)");
            set.add(Format(f));
        };
        if (item == "all") {
            for (std::size_t f = 0; f < kNames.size(); ++f) addOnce(f);
        } else if (item != "none") {
            std::size_t f = 0;
            while (f < kNames.size() && item != kNames[f]) ++f;
            if (f == kNames.size())
                throw InputError("formats \"" + list + "\": " +
                                 (item.empty() ? std::string("empty entry") : "unknown format \"" + item + "\"") +
                                 " (allowed: " + allowed + ")");
            addOnce(f);
        }
        if (comma == std::string::npos) break;
        at = comma + 1;
    }
    return set;
}

FormatSet formatSet(const std::vector<Format>& list) {
    FormatSet set;
    for (const Format f : list) set.add(f);
    return set;
}

std::vector<Format> formatList(const FormatSet& set) {
    std::vector<Format> out;
    for (std::size_t f = 0; f < kNames.size(); ++f)
        if (set.has(Format(f))) out.push_back(Format(f));
    return out;
}

std::string toString(const FormatSet& set) {
    std::string s;
    for (std::size_t f = 0; f < kNames.size(); ++f)
        if (set.has(Format(f))) s += std::string(s.empty() ? "" : ",") + kNames[f];
    return s.empty() ? "none" : s;
}

std::vector<std::string> writeExports(const ExportInputs& in, const std::string& dir, const FormatSet& formats) {
    namespace fs = std::filesystem;
    if (!fs::is_directory(dir)) throw RuntimeError("cannot write exports into " + dir + ": not a directory");
    const fs::path base(dir);
    std::vector<std::string> written;
    auto file = [&](const char* name) {
        written.emplace_back(name);
        return (base / name).string();
    };

    std::optional<Cave> ownCave;
    const Cave* cave = in.cave;
    if (!cave && in.domain) {
        ownCave = makeCave(*in.domain, CaveExtent::kChannels);
        cave = &*ownCave;
    }
    // The mesh, built here only when asked for and missing.
    const bool wantMesh = formats.has(Format::kGlb) || formats.has(Format::kStl) || formats.has(Format::kGocad);
    std::optional<SurfaceMesh> built;
    const SurfaceMesh* mesh = in.mesh;
    if (!mesh && wantMesh && in.buildMeshIfMissing && cave) {
        built = mesh::buildCaveSurfaceMesh(*cave, in.meshOptions);
        mesh = &*built;
    }
    const bool haveMesh = mesh && !mesh->triangles.empty();
    const bool haveSkeleton = in.skeleton && !in.skeleton->edges.empty();

    if (formats.has(Format::kGlb) && haveMesh) writeGlb(*mesh, file("cave.glb"), in.glb);
    if (formats.has(Format::kVtk)) {
        if (in.domain) writeStateVti(*in.domain, file("state.vti"), cave);
        if (haveSkeleton) writeSkeletonVtp(*in.skeleton, file("skeleton.vtp"), in.domain);
    }
    if (formats.has(Format::kStl) && haveMesh) writeStl(*mesh, file("cave.stl"));
    if (formats.has(Format::kSvx) && haveSkeleton && cave)
        writeSurvex(*in.skeleton, cave->mask, cave->voxelSize, file("cave.svx"));
    if (formats.has(Format::kTh) && haveSkeleton && cave)
        writeTherion(*in.skeleton, cave->mask, cave->voxelSize, file("cave.th"));
    if (formats.has(Format::kGocad)) {
        if (haveMesh) writeGocadTSurf(*mesh, file("cave.ts"));
        if (haveSkeleton) writeGocadPLine(*in.skeleton, file("skeleton.pl"), in.domain);
    }
    if (formats.has(Format::kCsv)) {
        if (in.stage2) writeHistoryCsv(in.stage2->history, file("history.csv"));
        if (haveSkeleton && cave)
            writeBranchesCsv(branchRows(*in.skeleton, cave->mask, cave->voxelSize,
                                        in.stage2 && in.domain ? &in.domain->flow : nullptr, in.network),
                             file("branches.csv"));
    }
    if (formats.has(Format::kVdb) && in.domain)
        mesh::writeExportVdb(file("cave.vdb"), *in.domain, *cave, in.meshOptions);
    return written;
}

}  // namespace cavesim::formats

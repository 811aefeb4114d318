#include "formats/survey_formats.h"

#include <cctype>
#include <cmath>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "formats/detail.h"
#include "formats/passages.h"

namespace cavesim::formats {
namespace {

enum class Dialect { kSurvex, kTherion };

void checkName(const std::string& name, const std::string& path) {
    bool ok = !name.empty();
    for (unsigned char c : name) ok = ok && (std::isalnum(c) || c == '_');
    if (!ok) throw RuntimeError("cannot write " + path + ": survey name '" + name + "' must be letters, digits and _");
}

// The first node of each connected piece of the skeleton (lowest node index), in node order.
std::vector<int> pieceRoots(const morpho::Skeleton& s) {
    const std::vector<int> piece = pieceOfNodes(s);
    std::vector<char> hasEdge(s.nodes.size(), 0);
    for (const auto& e : s.edges) hasEdge[std::size_t(e[0])] = hasEdge[std::size_t(e[1])] = 1;
    std::vector<int> roots;
    for (std::size_t v = 0; v < s.nodes.size(); ++v)
        if (hasEdge[v] && piece[v] == int(v)) roots.push_back(int(v));
    return roots;
}

std::string writeSurvey(const morpho::Skeleton& skeleton, const Grid3<std::uint8_t>& cave, double voxelSize,
                        const std::string& path, const SurveyOptions& options, Dialect dialect) {
    checkName(options.name, path);
    if (!(voxelSize > 0) || !std::isfinite(voxelSize))
        throw RuntimeError("cannot write " + path + ": voxel size must be finite and positive");
    if (cave.size() != cave.dims.count())
        throw RuntimeError("cannot write " + path + ": cave mask does not match its dims");
    const std::vector<morpho::Branch> passages = findPassages(skeleton);
    if (skeleton.edges.empty()) throw RuntimeError("cannot write " + path + ": the centreline has no legs");
    const bool sx = dialect == Dialect::kSurvex;
    const std::vector<std::string> names = stationNames(skeleton, passages, "p", sx ? "." : "_");
    auto pos = [&skeleton](int v) { return skeleton.nodes[std::size_t(v)].position; };

    std::string out;
    const std::string c = sx ? "; " : "# ";
    if (!sx) out += "encoding utf-8\n";
    out += c + options.title + " (" + std::to_string(skeleton.nodes.size()) + " stations, " +
           std::to_string(skeleton.edges.size()) + " legs, " + std::to_string(passages.size()) + " passages)\n";
    out += c + "written by cavesim from the cave's centreline; metres; fixed stations in world coordinates\n";
    out += c + "(x east, y north, z up); compass from grid north (+y); stations p<passage>" + (sx ? "." : "_") +
           "<station>\n";
    if (sx) {
        out += "*begin " + options.name + "\n";
        out += "*units tape metres\n*units compass degrees\n*units clino degrees\n";
    } else {
        out += "survey " + options.name + " -title \"" + options.title + "\"\n";
        out += "  centreline\n    units length meters\n    units compass clino degrees\n";
    }
    const std::string ind = sx ? "" : "    ";
    for (int root : pieceRoots(skeleton)) {
        const auto p = pos(root);
        out += ind + (sx ? "*fix " : "fix ") + names[std::size_t(root)] + " " + detail::fixed(p[0], 4) + " " +
               detail::fixed(p[1], 4) + " " + detail::fixed(p[2], 4) + "\n";
    }
    for (std::size_t b = 0; b < passages.size(); ++b) {
        const auto& nodes = passages[b].nodes;
        out += "\n" + ind + c + "passage " + std::to_string(b) + ": " + std::to_string(nodes.size() - 1) + " legs, " +
               detail::fixed(passages[b].length_m, 3) + " m\n";
        out += ind + (sx ? "*data normal from to tape compass clino\n" : "data normal from to length compass clino\n");
        for (std::size_t s = 0; s + 1 < nodes.size(); ++s) {
            const LegReading r = legReading(pos(nodes[s]), pos(nodes[s + 1]));
            out += ind + names[std::size_t(nodes[s])] + " " + names[std::size_t(nodes[s + 1])] + " " +
                   detail::fixed(r.tape, 4) + " ";
            if (r.plumbed)
                out += std::string("- ") + (pos(nodes[s + 1])[2] >= pos(nodes[s])[2] ? "up" : "down");
            else
                out += detail::fixed(r.compass, 3) + " " + detail::fixed(r.clino, 3);
            out += "\n";
        }
        out +=
            ind + (sx ? "*data passage station left right up down\n" : "data dimensions station left right up down\n");
        for (std::size_t s = 0; s < nodes.size(); ++s) {
            if (s + 1 == nodes.size() && passages[b].loop()) break;  // the loop's first station again
            const Lrud d = measureLrud(cave, voxelSize, pos(nodes[s]), passageHeading(skeleton, passages[b], s));
            out += ind + names[std::size_t(nodes[s])] + " " + detail::fixed(d.left, 3) + " " +
                   detail::fixed(d.right, 3) + " " + detail::fixed(d.up, 3) + " " + detail::fixed(d.down, 3) + "\n";
        }
    }
    out += sx ? "*end " + options.name + "\n" : "  endcentreline\nendsurvey\n";
    return out;
}

}  // namespace

void writeSurvex(const morpho::Skeleton& skeleton, const Grid3<std::uint8_t>& cave, double voxelSize,
                 const std::string& path, const SurveyOptions& options) {
    writeFileAtomic(path, writeSurvey(skeleton, cave, voxelSize, path, options, Dialect::kSurvex));
}

void writeTherion(const morpho::Skeleton& skeleton, const Grid3<std::uint8_t>& cave, double voxelSize,
                  const std::string& path, const SurveyOptions& options) {
    writeFileAtomic(path, writeSurvey(skeleton, cave, voxelSize, path, options, Dialect::kTherion));
}

}  // namespace cavesim::formats

#include "formats/gocad_formats.h"

#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "formats/detail.h"
#include "formats/passages.h"

namespace cavesim::formats {
namespace {

std::string header(const std::string& kind, const std::string& name) {
    return "GOCAD " + kind + " 1\nHEADER {\nname: " + name +
           "\n}\nGOCAD_ORIGINAL_COORDINATE_SYSTEM\nNAME Default\nAXIS_NAME \"X\" \"Y\" \"Z\"\n"
           "AXIS_UNIT \"m\" \"m\" \"m\"\nZPOSITIVE Elevation\nEND_ORIGINAL_COORDINATE_SYSTEM\n";
}

}  // namespace

void writeGocadTSurf(const SurfaceMesh& mesh, const std::string& path, const std::string& name) {
    if (mesh.triangles.empty()) throw RuntimeError("cannot write " + path + ": the mesh is empty");
    const long nv = long(mesh.vertices.size());
    std::string out = header("TSurf", name) + "TFACE\n";
    out.reserve(out.size() + mesh.vertices.size() * 40 + mesh.triangles.size() * 24);
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        const auto& p = mesh.vertices[v];
        out += "VRTX " + std::to_string(v + 1) + " " + detail::num(p[0]) + " " + detail::num(p[1]) + " " +
               detail::num(p[2]) + "\n";
    }
    for (const auto& t : mesh.triangles) {
        for (int c : t)
            if (c < 0 || c >= nv)
                throw RuntimeError("cannot write " + path + ": a triangle refers to vertex " + std::to_string(c) +
                                   " of " + std::to_string(nv));
        out +=
            "TRGL " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " + std::to_string(t[2] + 1) + "\n";
    }
    out += "END\n";
    writeFileAtomic(path, out);
}

void writeGocadPLine(const morpho::Skeleton& skeleton, const std::string& path, const Domain* domain,
                     const std::string& name) {
    const std::vector<morpho::Branch> passages = findPassages(skeleton);  // validates the skeleton
    const std::size_t n = skeleton.nodes.size();
    const std::vector<int> passageOf = passageOfNodes(skeleton, passages);
    const bool withFields =
        domain && domain->flow.size() == domain->dims.count() && domain->pressure.size() == domain->dims.count();
    if (withFields)
        for (const auto& node : skeleton.nodes)
            if (node.voxel >= domain->dims.count())
                throw RuntimeError("cannot write " + path + ": a skeleton node stands outside the domain");

    // Connected pieces, each an ILINE in order of its lowest node: its nodes in index order, its
    // edges in skeleton order (isolated nodes are in no edge and left out).
    const std::vector<int> piece = pieceOfNodes(skeleton);
    std::vector<std::vector<int>> nodesOf(n), edgesOf(n);
    for (std::size_t e = 0; e < skeleton.edges.size(); ++e)
        edgesOf[std::size_t(piece[std::size_t(skeleton.edges[e][0])])].push_back(int(e));
    std::vector<char> used(n, 0);
    for (const auto& e : skeleton.edges) used[std::size_t(e[0])] = used[std::size_t(e[1])] = 1;
    for (std::size_t v = 0; v < n; ++v)
        if (used[v]) nodesOf[std::size_t(piece[v])].push_back(int(v));

    std::string out = header("PLine", name);
    out += withFields ? "PROPERTIES radius passage_id flow pressure\nESIZES 1 1 1 1\n"
                      : "PROPERTIES radius passage_id\nESIZES 1 1\n";
    for (std::size_t root = 0; root < n; ++root) {
        if (nodesOf[root].empty()) continue;
        out += "ILINE\n";
        for (int v : nodesOf[root]) {
            const auto& node = skeleton.nodes[std::size_t(v)];
            out += "PVRTX " + std::to_string(v + 1) + " " + detail::num(node.position[0]) + " " +
                   detail::num(node.position[1]) + " " + detail::num(node.position[2]) + " " +
                   detail::num(node.radius) + " " + std::to_string(passageOf[std::size_t(v)]);
            if (withFields)
                out += " " + detail::num(domain->flow[node.voxel]) + " " + detail::num(domain->pressure[node.voxel]);
            out += "\n";
        }
        for (int e : edgesOf[root]) {
            const auto& ed = skeleton.edges[std::size_t(e)];
            out += "SEG " + std::to_string(ed[0] + 1) + " " + std::to_string(ed[1] + 1) + "\n";
        }
    }
    out += "END\n";
    writeFileAtomic(path, out);
}

}  // namespace cavesim::formats

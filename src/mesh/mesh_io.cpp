// OpenMesh: clean-up of the extracted surface, OBJ/PLY output and input.
// GCC 12 warns inside OpenMesh's property vectors (a value-initialised VectorT); not ours.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <system_error>

#include "core/atomic_file.h"

#include "core/check.h"
#include "mesh/cave_mesh.h"
#include "mesh/mesh_cleanup.h"

namespace cavesim::mesh {
namespace {

struct Traits : OpenMesh::DefaultTraits {
    using Point = OpenMesh::Vec3d;
    using Normal = OpenMesh::Vec3d;
    VertexAttributes(OpenMesh::Attributes::Status);
    EdgeAttributes(OpenMesh::Attributes::Status);
    HalfedgeAttributes(OpenMesh::Attributes::PrevHalfedge);
    FaceAttributes(OpenMesh::Attributes::Status);
};
using OmMesh = OpenMesh::TriMesh_ArrayKernelT<Traits>;

// OpenMesh reports refused faces and every file it writes on its log streams; library code
// must not print.
void silenceOpenMesh() {
    omlog().disable();
    omout().disable();
    omerr().disable();
}

// Builds an OpenMesh mesh. Faces OpenMesh refuses (a complex edge or vertex) get their own
// copies of their vertices, so the geometry is kept whole.
OmMesh toOpenMesh(const TriangleMesh& mesh) {
    silenceOpenMesh();
    OmMesh m;
    std::vector<OmMesh::VertexHandle> vh;
    vh.reserve(mesh.vertices.size());
    for (const auto& p : mesh.vertices) vh.push_back(m.add_vertex(OmMesh::Point(p[0], p[1], p[2])));
    const int nv = int(mesh.vertices.size());
    for (const auto& t : mesh.triangles) {
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
        CAVESIM_CHECK(std::min({t[0], t[1], t[2]}) >= 0 && std::max({t[0], t[1], t[2]}) < nv,
                      "triangle mesh refers to a vertex that does not exist");
        if (m.add_face(vh[t[0]], vh[t[1]], vh[t[2]]).is_valid()) continue;
        std::array<OmMesh::VertexHandle, 3> copies;
        for (int c = 0; c < 3; ++c) copies[c] = m.add_vertex(m.point(vh[t[c]]));
        m.add_face(copies[0], copies[1], copies[2]);
    }
    return m;
}

TriangleMesh fromOpenMesh(const OmMesh& m) {
    TriangleMesh out;
    std::vector<int> index(m.n_vertices(), -1);
    for (const auto f : m.faces()) {
        if (m.status(f).deleted()) continue;
        std::array<int, 3> tri{};
        int c = 0;
        for (const auto v : m.fv_range(f)) {
            int& id = index[v.idx()];
            if (id < 0) {
                id = int(out.vertices.size());
                const auto& p = m.point(v);
                out.vertices.push_back({p[0], p[1], p[2]});
            }
            tri[c++] = id;
        }
        out.triangles.push_back(tri);
    }
    return out;
}

std::string lowerExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

}  // namespace

namespace detail {

TriangleMesh cleanMesh(const TriangleMesh& mesh, double minEdge) {
    OmMesh m = toOpenMesh(mesh);
    m.request_vertex_status();
    m.request_edge_status();
    m.request_face_status();
    const double min2 = minEdge * minEdge;
    for (const auto e : m.edges()) {
        if (m.status(e).deleted()) continue;
        const auto h0 = m.halfedge_handle(e, 0);
        const auto h1 = m.halfedge_handle(e, 1);
        if ((m.point(m.to_vertex_handle(h0)) - m.point(m.from_vertex_handle(h0))).sqrnorm() >= min2) continue;
        if (m.is_collapse_ok(h0))
            m.collapse(h0);
        else if (m.is_collapse_ok(h1))
            m.collapse(h1);
    }
    m.garbage_collection();
    return fromOpenMesh(m);
}

}  // namespace detail

namespace {

// The mesh with area-weighted vertex normals (the sum of unnormalised face normals), outward.
OmMesh withNormals(const TriangleMesh& mesh) {
    OmMesh m = toOpenMesh(mesh);
    m.request_vertex_normals();
    std::vector<OpenMesh::Vec3d> normal(m.n_vertices(), OpenMesh::Vec3d(0, 0, 0));
    for (const auto f : m.faces()) {
        auto it = m.cfv_iter(f);
        const auto a = *it, b = *++it, c = *++it;
        const OpenMesh::Vec3d n = OpenMesh::cross(m.point(b) - m.point(a), m.point(c) - m.point(a));
        normal[a.idx()] += n;
        normal[b.idx()] += n;
        normal[c.idx()] += n;
    }
    for (const auto v : m.vertices()) {
        const OpenMesh::Vec3d n = normal[v.idx()];
        const double len = n.norm();
        m.set_normal(v, len > 0 ? n / len : OpenMesh::Vec3d(0, 0, 1));
    }
    return m;
}

void checkExtension(const std::string& path) {
    const std::string ext = lowerExtension(path);
    CAVESIM_CHECK(ext == ".obj" || ext == ".ply", "cannot write mesh " + path + ": the name must end in .obj or .ply");
}

// Encodes in memory with the writer for the extension, then writes with every write checked, synced
// and renamed into place (core/atomic_file.h). OBJ as text with 8 significant digits (the points are
// single precision), PLY binary.
void writeOne(const OmMesh& m, const std::string& path) {
    const std::string ext = lowerExtension(path);
    OpenMesh::IO::Options options(OpenMesh::IO::Options::VertexNormal);
    if (ext == ".ply") options += OpenMesh::IO::Options::Binary;
    silenceOpenMesh();
    std::ostringstream out(std::ios::out | std::ios::binary);
    out << std::fixed;  // as OpenMesh's writer to a named file sets it
    if (!OpenMesh::IO::write_mesh(m, out, ext, options, 8) || !out)
        throw RuntimeError("cannot write mesh " + path + ": OpenMesh could not encode it");
    writeFileAtomic(path, out.str());
}

}  // namespace

namespace detail {

void writeMeshFiles(const TriangleMesh& mesh, const std::vector<std::string>& paths) {
    for (const std::string& p : paths) checkExtension(p);
    const OmMesh m = withNormals(mesh);
    for (const std::string& p : paths) writeOne(m, p);
}

}  // namespace detail

void writeMeshFile(const TriangleMesh& mesh, const std::string& path) {
    detail::writeMeshFiles(mesh, {path});
}

TriangleMesh readMeshFile(const std::string& path) {
    if (!std::filesystem::exists(path)) throw RuntimeError("cannot read mesh " + path + ": no such file");
    silenceOpenMesh();
    OmMesh m;
    OpenMesh::IO::Options options;
    if (!OpenMesh::IO::read_mesh(m, path, options)) throw RuntimeError("cannot read mesh " + path);
    return fromOpenMesh(m);
}

}  // namespace cavesim::mesh

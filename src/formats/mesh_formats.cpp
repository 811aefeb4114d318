#include "formats/mesh_formats.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "formats/detail.h"

namespace cavesim::formats {
namespace {

void checkMesh(const SurfaceMesh& mesh, const std::string& path, bool needNormals) {
    if (mesh.triangles.empty() || mesh.vertices.empty())
        throw RuntimeError("cannot write " + path + ": the mesh is empty");
    if (needNormals && mesh.normals.size() != mesh.vertices.size())
        throw RuntimeError("cannot write " + path + ": " + std::to_string(mesh.normals.size()) + " normals for " +
                         std::to_string(mesh.vertices.size()) + " vertices");
    const long nv = long(mesh.vertices.size());
    for (const auto& t : mesh.triangles)
        for (int c : t)
            if (c < 0 || c >= nv)
                throw RuntimeError("cannot write " + path + ": a triangle refers to vertex " + std::to_string(c) +
                                 " of " + std::to_string(nv));
}

// cavesim (z up) to glTF (y up): (x, y, z) → (x, z, −y).
std::array<float, 3> yUpFromZUp(const std::array<float, 3>& p) {
    return {p[0], p[2], -p[1]};
}

}  // namespace

void writeGlb(const SurfaceMesh& mesh, const std::string& path, const GlbOptions& options) {
    checkMesh(mesh, path, true);
    const bool inward = options.normals == NormalSide::kInward;
    const std::size_t nv = mesh.vertices.size(), nt = mesh.triangles.size();

    std::string bin;
    bin.reserve(nv * 24 + nt * 12);
    std::array<float, 3> lo{std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
                            std::numeric_limits<float>::max()};
    std::array<float, 3> hi{-lo[0], -lo[1], -lo[2]};
    for (const auto& v : mesh.vertices) {
        const auto p = yUpFromZUp(v);
        for (int c = 0; c < 3; ++c) {
            lo[c] = std::min(lo[c], p[c]);
            hi[c] = std::max(hi[c], p[c]);
        }
        detail::appendBytes(bin, p.data(), 3);
    }
    const std::size_t normalsAt = bin.size();
    for (const auto& n : mesh.normals) {
        auto q = yUpFromZUp(n);
        if (inward)
            for (float& c : q) c = -c;
        detail::appendBytes(bin, q.data(), 3);
    }
    const std::size_t indicesAt = bin.size();
    for (const auto& t : mesh.triangles) {
        const std::uint32_t idx[3] = {std::uint32_t(t[0]), std::uint32_t(inward ? t[2] : t[1]),
                                      std::uint32_t(inward ? t[1] : t[2])};
        detail::appendBytes(bin, idx, 3);
    }

    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = "cavesim";
    model.asset.copyright = "";
    tinygltf::Buffer buffer;
    buffer.data.assign(bin.begin(), bin.end());
    model.buffers.push_back(std::move(buffer));

    auto addView = [&model](std::size_t offset, std::size_t length, int target) {
        tinygltf::BufferView view;
        view.buffer = 0;
        view.byteOffset = offset;
        view.byteLength = length;
        view.target = target;
        model.bufferViews.push_back(view);
        return int(model.bufferViews.size()) - 1;
    };
    const int positionView = addView(0, normalsAt, TINYGLTF_TARGET_ARRAY_BUFFER);
    const int normalView = addView(normalsAt, indicesAt - normalsAt, TINYGLTF_TARGET_ARRAY_BUFFER);
    const int indexView = addView(indicesAt, bin.size() - indicesAt, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);

    auto addAccessor = [&model](int view, int componentType, std::size_t count, int type) {
        tinygltf::Accessor a;
        a.bufferView = view;
        a.byteOffset = 0;
        a.componentType = componentType;
        a.count = count;
        a.type = type;
        model.accessors.push_back(a);
        return int(model.accessors.size()) - 1;
    };
    const int position = addAccessor(positionView, TINYGLTF_COMPONENT_TYPE_FLOAT, nv, TINYGLTF_TYPE_VEC3);
    model.accessors[std::size_t(position)].minValues = {lo[0], lo[1], lo[2]};
    model.accessors[std::size_t(position)].maxValues = {hi[0], hi[1], hi[2]};
    const int normal = addAccessor(normalView, TINYGLTF_COMPONENT_TYPE_FLOAT, nv, TINYGLTF_TYPE_VEC3);
    const int indices = addAccessor(indexView, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, 3 * nt, TINYGLTF_TYPE_SCALAR);

    tinygltf::Material material;
    material.name = "rock";
    material.pbrMetallicRoughness.baseColorFactor = {0.62, 0.58, 0.52, 1.0};
    material.pbrMetallicRoughness.metallicFactor = 0.0;
    material.pbrMetallicRoughness.roughnessFactor = 0.9;
    material.doubleSided = false;
    model.materials.push_back(material);

    tinygltf::Primitive primitive;
    primitive.attributes["POSITION"] = position;
    primitive.attributes["NORMAL"] = normal;
    primitive.indices = indices;
    primitive.material = 0;
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    tinygltf::Mesh gmesh;
    gmesh.name = options.name;
    gmesh.primitives.push_back(primitive);
    model.meshes.push_back(gmesh);

    tinygltf::Node node;
    node.name = options.name;
    node.mesh = 0;
    model.nodes.push_back(node);
    tinygltf::Scene scene;
    scene.name = options.name;
    scene.nodes.push_back(0);
    model.scenes.push_back(scene);
    model.defaultScene = 0;

    std::ostringstream out;
    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToStream(&model, out, false, true) || !out)
        throw RuntimeError("cannot write " + path + ": tinygltf could not encode the model");
    writeFileAtomic(path, out.str());
}

void writeStl(const SurfaceMesh& mesh, const std::string& path) {
    checkMesh(mesh, path, false);
    std::string bytes;
    bytes.reserve(84 + 50 * mesh.triangles.size());
    std::string header = "cavesim cave: metres, world space, z up, normals out";
    header.resize(80, ' ');
    bytes += header;
    if (mesh.triangles.size() > 0xffffffffu) throw RuntimeError("cannot write " + path + ": too many triangles for STL");
    detail::appendValue(bytes, std::uint32_t(mesh.triangles.size()));
    for (const auto& t : mesh.triangles) {
        const auto& a = mesh.vertices[std::size_t(t[0])];
        const auto& b = mesh.vertices[std::size_t(t[1])];
        const auto& c = mesh.vertices[std::size_t(t[2])];
        const auto n = faceNormal(a, b, c);
        detail::appendBytes(bytes, n.data(), 3);
        detail::appendBytes(bytes, a.data(), 3);
        detail::appendBytes(bytes, b.data(), 3);
        detail::appendBytes(bytes, c.data(), 3);
        detail::appendValue(bytes, std::uint16_t(0));
    }
    writeFileAtomic(path, bytes);
}

}  // namespace cavesim::formats

// The smooth cave mesh: level set (cave_level_set.cpp) → volumeToMesh → OpenMesh clean-up.
#include "mesh/cave_mesh.h"

#include <openvdb/tools/VolumeToMesh.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <utility>

#include "core/check.h"
#include "core/timer.h"
#include "mesh/cave_level_set.h"
#include "mesh/level_set_mesh.h"
#include "mesh/mesh_cleanup.h"
#include "sim/cave.h"

namespace cavesim::mesh {
namespace {

double length2(const openvdb::Vec3s& a, const openvdb::Vec3s& b) {
    return double((a - b).lengthSqr());
}

}  // namespace

namespace detail {

TriangleMesh meshLevelSet(const openvdb::FloatGrid& grid, double iso, double adaptivity) {
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(grid, points, triangles, quads, iso, adaptivity, true);
    TriangleMesh mesh;
    mesh.vertices.reserve(points.size());
    for (const openvdb::Vec3s& p : points) mesh.vertices.push_back({double(p[0]), double(p[1]), double(p[2])});
    mesh.triangles.reserve(triangles.size() + 2 * quads.size());
    for (const openvdb::Vec3I& t : triangles) mesh.triangles.push_back({int(t[0]), int(t[2]), int(t[1])});
    for (const openvdb::Vec4I& q : quads) {
        if (length2(points[q[0]], points[q[2]]) <= length2(points[q[1]], points[q[3]])) {
            mesh.triangles.push_back({int(q[0]), int(q[2]), int(q[1])});
            mesh.triangles.push_back({int(q[0]), int(q[3]), int(q[2])});
        } else {
            mesh.triangles.push_back({int(q[0]), int(q[3]), int(q[1])});
            mesh.triangles.push_back({int(q[1]), int(q[3]), int(q[2])});
        }
    }
    return mesh;
}

}  // namespace detail

namespace {

// Surface area and signed volume of a triangle mesh (the two measures the offset needs).
std::pair<double, double> areaAndVolume(const TriangleMesh& mesh) {
    double area = 0.0, volume = 0.0;
    for (const auto& t : mesh.triangles) {
        const auto& a = mesh.vertices[t[0]];
        const auto& b = mesh.vertices[t[1]];
        const auto& c = mesh.vertices[t[2]];
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        area += 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
                   a[2] * (b[0] * c[1] - b[1] * c[0])) /
                  6.0;
    }
    return {area, volume};
}

}  // namespace

namespace detail {

CaveSurface buildCaveSurface(const Grid3<std::uint8_t>& mask, double voxelSize, const MeshOptions& options,
                             bool wantMesh) {
    CaveSurface out;
    out.levelSet = buildCaveLevelSet(mask, voxelSize, options);
    CaveLevelSet& ls = out.levelSet;
    if (!ls.grid) return out;
    TriangleMesh mesh = meshLevelSet(*ls.grid, ls.isoValue, options.adaptivity);
    if (options.preserveVolume) {
        // Newton steps on V(iso) = voxel volume with dV/diso = area; a second step only when the
        // first missed by more than 1 % (small pieces, whose area grows fast with the offset).
        for (int step = 0; step < 2; ++step) {
            const auto [area, volume] = areaAndVolume(mesh);
            if (!(area > 0.0) || std::abs(volume - ls.voxelVolume) <= 0.01 * ls.voxelVolume) break;
            const double iso = std::clamp(ls.isoValue + (ls.voxelVolume - volume) / area, 0.0, ls.maxIsoValue);
            if (std::abs(iso - ls.isoValue) <= 1e-3 * voxelSize) break;
            ls.isoValue = iso;
            if (step == 0 || wantMesh) mesh = meshLevelSet(*ls.grid, ls.isoValue, options.adaptivity);
        }
    }
    if (wantMesh) out.mesh = cleanMesh(mesh, 1e-4 * voxelSize / options.subdivision);
    return out;
}

}  // namespace detail

TriangleMesh buildCaveMesh(const Grid3<std::uint8_t>& mask, double voxelSize, const MeshOptions& options) {
    return detail::buildCaveSurface(mask, voxelSize, options, true).mesh;
}

namespace detail {

MeshStats writeMeshOutputs(const TriangleMesh& mesh, const Grid3<std::uint8_t>& mask, double voxelSize,
                           const std::string& dir, const MeshOptions& options) {
    if (mesh.triangles.empty()) return {};
    const std::filesystem::path base(dir);
    writeMeshFiles(mesh, {(base / "cave.obj").string(), (base / "cave.ply").string()});
    if (options.style == MeshStyle::kVoxel)
        writeMeshFile(buildVoxelMesh(mask, voxelSize), (base / "cave_voxels.obj").string());
    return measureMesh(mesh);
}

}  // namespace detail

MeshStats writeCaveMesh(const Cave& cave, const std::string& dir, const MeshOptions& options, SurfaceMesh* built) {
    const Stopwatch watch;
    detail::validateMeshOptions(options, cave.voxelSize);
    const Grid3<std::uint8_t>& mask = cave.mask;
    const TriangleMesh mesh = buildCaveMesh(mask, cave.voxelSize, options);
    MeshStats stats = detail::writeMeshOutputs(mesh, mask, cave.voxelSize, dir, options);
    if (built) *built = toSurfaceMesh(mesh);
    if (stats.faces > 0) stats.seconds = watch.seconds();
    return stats;
}

SurfaceMesh toSurfaceMesh(const TriangleMesh& mesh) {
    SurfaceMesh out;
    const std::size_t nv = mesh.vertices.size();
    std::vector<std::array<double, 3>> sum(nv, {0.0, 0.0, 0.0});
    for (const auto& t : mesh.triangles) {
        for (int c = 0; c < 3; ++c)
            CAVESIM_CHECK(t[c] >= 0 && std::size_t(t[c]) < nv, "triangle mesh refers to a vertex that does not exist");
        const auto& a = mesh.vertices[std::size_t(t[0])];
        const auto& b = mesh.vertices[std::size_t(t[1])];
        const auto& c = mesh.vertices[std::size_t(t[2])];
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        for (int corner = 0; corner < 3; ++corner)
            for (int d = 0; d < 3; ++d) sum[std::size_t(t[corner])][d] += n[d];
    }
    out.vertices.reserve(nv);
    out.normals.reserve(nv);
    for (std::size_t v = 0; v < nv; ++v) {
        const auto& p = mesh.vertices[v];
        out.vertices.push_back({float(p[0]), float(p[1]), float(p[2])});
        const auto& n = sum[v];
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (len > 0.0)
            out.normals.push_back({float(n[0] / len), float(n[1] / len), float(n[2] / len)});
        else
            out.normals.push_back({0.f, 0.f, 1.f});
    }
    out.triangles = mesh.triangles;
    return out;
}

SurfaceMesh buildCaveSurfaceMesh(const Cave& cave, const MeshOptions& options) {
    detail::validateMeshOptions(options, cave.voxelSize);
    return toSurfaceMesh(buildCaveMesh(cave.mask, cave.voxelSize, options));
}

}  // namespace cavesim::mesh

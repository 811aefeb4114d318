// The smooth cave mesh: level set (cave_level_set.cpp) → volumeToMesh → OpenMesh clean-up.
#include "mesh/cave_mesh.h"

#include <openvdb/tools/VolumeToMesh.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <utility>

#include "core/timer.h"
#include "mesh/cave_level_set.h"
#include "mesh/mesh_cleanup.h"
#include "sim/cave.h"

namespace cavesim::mesh {
namespace {

double length2(const openvdb::Vec3s& a, const openvdb::Vec3s& b) {
    return double((a - b).lengthSqr());
}

}  // namespace

namespace {

// volumeToMesh at `iso`, faces turned outward (OpenVDB winds them inward), quads split along
// their shorter diagonal.
TriangleMesh extract(const openvdb::FloatGrid& grid, double iso, double adaptivity) {
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
    TriangleMesh mesh = extract(*ls.grid, ls.isoValue, options.adaptivity);
    if (options.preserveVolume) {
        // Newton steps on V(iso) = voxel volume with dV/diso = area; a second step only when the
        // first missed by more than 1 % (small pieces, whose area grows fast with the offset).
        for (int step = 0; step < 2; ++step) {
            const auto [area, volume] = areaAndVolume(mesh);
            if (!(area > 0.0) || std::abs(volume - ls.voxelVolume) <= 0.01 * ls.voxelVolume) break;
            const double iso = std::clamp(ls.isoValue + (ls.voxelVolume - volume) / area, 0.0, ls.maxIsoValue);
            if (std::abs(iso - ls.isoValue) <= 1e-3 * voxelSize) break;
            ls.isoValue = iso;
            if (step == 0 || wantMesh) mesh = extract(*ls.grid, ls.isoValue, options.adaptivity);
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
    if (options.style == MeshStyle::kVoxel) writeMeshFile(buildVoxelMesh(mask, voxelSize), (base / "cave_voxels.obj").string());
    return measureMesh(mesh);
}

}  // namespace detail

MeshStats writeCaveMesh(const Cave& cave, const std::string& dir, const MeshOptions& options) {
    const Stopwatch watch;
    detail::validateMeshOptions(options, cave.voxelSize);
    const Grid3<std::uint8_t>& mask = cave.mask;
    MeshStats stats =
        detail::writeMeshOutputs(buildCaveMesh(mask, cave.voxelSize, options), mask, cave.voxelSize, dir, options);
    if (stats.faces > 0) stats.seconds = watch.seconds();
    return stats;
}

}  // namespace cavesim::mesh

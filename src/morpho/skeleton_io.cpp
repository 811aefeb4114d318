#include "morpho/skeleton_io.h"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/check.h"
#include "core/error.h"
#include "core/text.h"

namespace cavesim::morpho {
namespace {

namespace fs = std::filesystem;

/// Shortest decimal form of `x` that reads back to the same double.
void appendNumber(std::string& out, double x) {
    out += shortestText(x);
}

/// Writes `text` to `dir/name` through a unique temporary file and a rename.
void writeAtomic(const fs::path& dir, const std::string& name, const std::string& text) {
    writeFileAtomic((dir / name).string(), text);
}

void checkSkeleton(const Skeleton& s, double voxelSize, const Dims& grid) {
    CAVESIM_CHECK(std::isfinite(voxelSize) && voxelSize > 0,
                  "skeleton files: voxel size must be a finite positive length, got " + std::to_string(voxelSize));
    const std::size_t n = s.nodes.size();
    for (std::size_t i = 0; i < n; ++i) {
        const SkeletonNode& node = s.nodes[i];
        for (const double c : node.position)
            CAVESIM_CHECK(std::isfinite(c), "skeleton files: node " + std::to_string(i) + " has a non-finite position");
        CAVESIM_CHECK(
            std::isfinite(node.radius) && node.radius >= 0,
            "skeleton files: node " + std::to_string(i) + " has an invalid radius " + std::to_string(node.radius));
        CAVESIM_CHECK(node.voxel < grid.count(), "skeleton files: node " + std::to_string(i) + " stands on voxel " +
                                                     std::to_string(node.voxel) + ", outside the " +
                                                     std::to_string(grid.nx) + "×" + std::to_string(grid.ny) + "×" +
                                                     std::to_string(grid.nz) + " grid");
    }
    for (std::size_t e = 0; e < s.edges.size(); ++e) {
        const auto& ed = s.edges[e];
        CAVESIM_CHECK(ed[0] >= 0 && ed[1] >= 0 && std::size_t(ed[0]) < n && std::size_t(ed[1]) < n && ed[0] < ed[1],
                      "skeleton files: edge " + std::to_string(e) + " (" + std::to_string(ed[0]) + ", " +
                          std::to_string(ed[1]) + ") must join two distinct nodes a < b of " + std::to_string(n));
    }
}

}  // namespace

void writeSkeletonFiles(const Skeleton& skeleton, const std::string& dir, double voxelSize, const Dims& grid) {
    checkSkeleton(skeleton, voxelSize, grid);
    const fs::path d(dir);
    std::error_code ec;
    if (!fs::is_directory(d, ec)) throw RuntimeError("skeleton files: " + dir + " is not a directory");

    nlohmann::json j;
    j["format"] = "cavesim-skeleton";
    j["version"] = 1;
    j["voxel_size_m"] = voxelSize;
    j["grid"] = {grid.nx, grid.ny, grid.nz};
    j["node_count"] = skeleton.nodes.size();
    j["edge_count"] = skeleton.edges.size();
    nlohmann::json nodes = nlohmann::json::array(), edges = nlohmann::json::array(), radius = nlohmann::json::array(),
                   voxels = nlohmann::json::array();
    for (const SkeletonNode& node : skeleton.nodes) {
        nodes.push_back({node.position[0], node.position[1], node.position[2]});
        radius.push_back(node.radius);
        const Index3 c = grid.coord(node.voxel);
        voxels.push_back({c.i, c.j, c.k});
    }
    for (const auto& e : skeleton.edges) edges.push_back({e[0], e[1]});
    j["nodes"] = std::move(nodes);
    j["edges"] = std::move(edges);
    j["radius"] = std::move(radius);
    j["voxels"] = std::move(voxels);

    std::string nodeText, linkText;
    for (const SkeletonNode& node : skeleton.nodes) {
        appendNumber(nodeText, node.position[0]);
        nodeText += ' ';
        appendNumber(nodeText, node.position[1]);
        nodeText += ' ';
        appendNumber(nodeText, node.position[2]);
        nodeText += '\n';
    }
    for (const auto& e : skeleton.edges) {
        linkText += std::to_string(e[0] + 1);
        linkText += ' ';
        linkText += std::to_string(e[1] + 1);
        linkText += '\n';
    }
    writeAtomic(d, "skeleton.json", j.dump() + "\n");
    writeAtomic(d, "skeleton_nodes.dat", nodeText);
    writeAtomic(d, "skeleton_links.dat", linkText);
}

SkeletonFile readSkeletonJson(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw RuntimeError("cannot read " + path);
    std::stringstream buffer;
    buffer << in.rdbuf();
    if (in.bad()) throw RuntimeError("cannot read " + path);
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(buffer.str());
    } catch (const nlohmann::json::exception& e) {
        throw InputError(path + ": not valid JSON: " + e.what());
    }
    auto fail = [&](const std::string& what) { return InputError(path + ": " + what); };
    auto key = [&](const char* name) -> const nlohmann::json& {
        if (!j.is_object() || !j.contains(name)) throw fail(std::string("missing key \"") + name + "\"");
        return j.at(name);
    };
    auto number = [&](const nlohmann::json& v, const std::string& where) {
        if (!v.is_number()) throw fail(where + " must be a number");
        return v.get<double>();
    };
    auto integer = [&](const nlohmann::json& v, const std::string& where) {
        if (!v.is_number_integer()) throw fail(where + " must be an integer");
        return v.get<long long>();
    };
    auto tuple = [&](const nlohmann::json& v, std::size_t size, const std::string& where) -> const nlohmann::json& {
        if (!v.is_array() || v.size() != size) throw fail(where + " must be an array of " + std::to_string(size));
        return v;
    };

    SkeletonFile f;
    f.voxelSize = number(key("voxel_size_m"), "voxel_size_m");
    if (!(std::isfinite(f.voxelSize) && f.voxelSize > 0)) throw fail("voxel_size_m must be positive");
    const auto& grid = tuple(key("grid"), 3, "grid");
    const long long gx = integer(grid[0], "grid[0]"), gy = integer(grid[1], "grid[1]"),
                    gz = integer(grid[2], "grid[2]");
    if (gx < 0 || gy < 0 || gz < 0 || gx > (1 << 30) || gy > (1 << 30) || gz > (1 << 30))
        throw fail("grid extents must be non-negative");
    f.grid = {int(gx), int(gy), int(gz)};

    const auto& nodes = key("nodes");
    const auto& radius = key("radius");
    const auto& voxels = key("voxels");
    if (!nodes.is_array()) throw fail("nodes must be an array");
    const std::size_t n = nodes.size();
    if (!radius.is_array() || radius.size() != n) throw fail("radius must be an array with one value per node");
    if (!voxels.is_array() || voxels.size() != n) throw fail("voxels must be an array with one entry per node");
    f.skeleton.nodes.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::string at = "[" + std::to_string(i) + "]";
        SkeletonNode& node = f.skeleton.nodes[i];
        const auto& p = tuple(nodes[i], 3, "nodes" + at);
        for (std::size_t c = 0; c < 3; ++c) node.position[c] = number(p[c], "nodes" + at);
        node.radius = number(radius[i], "radius" + at);
        const auto& v = tuple(voxels[i], 3, "voxels" + at);
        const long long vi = integer(v[0], "voxels" + at), vj = integer(v[1], "voxels" + at),
                        vk = integer(v[2], "voxels" + at);
        if (!f.grid.contains(int(vi), int(vj), int(vk)) || vi != int(vi) || vj != int(vj) || vk != int(vk))
            throw fail("voxels" + at + " lies outside the grid");
        node.voxel = f.grid.index(int(vi), int(vj), int(vk));
    }
    const auto& edges = key("edges");
    if (!edges.is_array()) throw fail("edges must be an array");
    f.skeleton.edges.resize(edges.size());
    for (std::size_t e = 0; e < edges.size(); ++e) {
        const std::string at = "edges[" + std::to_string(e) + "]";
        const auto& t = tuple(edges[e], 2, at);
        const long long a = integer(t[0], at), b = integer(t[1], at);
        if (a < 0 || b < 0 || a >= (long long)n || b >= (long long)n || a >= b)
            throw fail(at + " must join two distinct nodes a < b");
        f.skeleton.edges[e] = {int(a), int(b)};
    }
    return f;
}

}  // namespace cavesim::morpho

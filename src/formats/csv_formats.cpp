#include "formats/csv_formats.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "core/atomic_file.h"
#include "core/error.h"
#include "formats/detail.h"
#include "formats/passages.h"

namespace cavesim::formats {
namespace {

std::string opt(const std::optional<double>& v) {
    return v ? detail::num(*v) : std::string();
}

// Role priority: lower wins.
int rank(const std::string& role) {
    if (role == "main") return 0;
    if (role == "tributary") return 1;
    if (role == "unconnected") return 2;
    return 3;
}

}  // namespace

void writeHistoryCsv(const std::vector<Stage2Record>& history, const std::string& path) {
    std::string out =
        "iteration,injected,drained,stored,flow,eroded,channel_voxels,pressure_updates,sources_connected,balance_"
        "error\n";
    for (const Stage2Record& r : history) {
        out += std::to_string(r.iteration) + "," + detail::num(r.injected) + "," + detail::num(r.drained) + "," +
               detail::num(r.stored) + "," + detail::num(r.flow) + "," + detail::num(r.eroded) + "," +
               std::to_string(r.channelVoxels) + "," + std::to_string(r.pressureUpdates) + "," +
               std::to_string(r.sourcesConnected) + "," + detail::num(r.balanceError) + "\n";
    }
    writeFileAtomic(path, out);
}

std::vector<BranchRow> branchRows(const morpho::Skeleton& skeleton, const Grid3<std::uint8_t>& cave, double voxelSize,
                                  const Grid3<float>* flow, const morpho::NetworkCounts* network) {
    constexpr double kDeg = 180.0 / 3.14159265358979323846;
    if (!(voxelSize > 0) || !std::isfinite(voxelSize)) throw RuntimeError("branch table: voxel size must be positive");
    const std::vector<morpho::Branch> passages = findPassages(skeleton);
    // Roles of the skeleton edges along the flow paths.
    std::map<std::pair<int, int>, std::string> edgeRole;
    std::set<int> troughs;
    if (network) {
        for (const morpho::FlowPath& fp : network->paths) {
            for (int t : fp.loopTroughs) troughs.insert(t);
            bool beforeJoin = fp.capturedBy.has_value();
            for (std::size_t s = 0; s + 1 < fp.nodes.size(); ++s) {
                if (fp.joinNode && fp.nodes[s] == *fp.joinNode) beforeJoin = false;
                const std::string role = !fp.sink ? "unconnected" : (beforeJoin ? "tributary" : "main");
                const std::pair<int, int> key{std::min(fp.nodes[s], fp.nodes[s + 1]),
                                              std::max(fp.nodes[s], fp.nodes[s + 1])};
                auto it = edgeRole.find(key);
                if (it == edgeRole.end() || rank(role) < rank(it->second)) edgeRole[key] = role;
            }
        }
    }
    std::vector<BranchRow> rows;
    rows.reserve(passages.size());
    for (std::size_t b = 0; b < passages.size(); ++b) {
        const morpho::Branch& br = passages[b];
        BranchRow r;
        r.id = int(b);
        r.fromNode = br.nodes.front();
        r.toNode = br.nodes.back();
        r.nodes = int(br.nodes.size());
        r.length_m = br.length_m;
        const auto& a = skeleton.nodes[std::size_t(r.fromNode)].position;
        const auto& z = skeleton.nodes[std::size_t(r.toNode)].position;
        double d[3] = {z[0] - a[0], z[1] - a[1], z[2] - a[2]};
        r.straight_m = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (!br.loop() && r.straight_m > 0) {
            if (d[2] > 0 || (d[2] == 0 && (d[0] < 0 || (d[0] == 0 && d[1] < 0))))
                for (double& c : d) c = -c;  // point down (a horizontal line: towards [0°, 180°))
            double az = std::atan2(d[0], d[1]) * kDeg;
            if (az < 0) az += 360.0;
            if (az >= 360.0) az -= 360.0;
            const double horizontal = std::hypot(d[0], d[1]);
            r.azimuth_deg = horizontal > 0 ? az : 0.0;
            r.dip_deg = std::atan2(-d[2], horizontal) * kDeg + 0.0;  // + 0.0: no "-0"
        }
        // Per-node means (a loop's first node counted once).
        const std::size_t count = br.loop() && br.nodes.size() > 1 ? br.nodes.size() - 1 : br.nodes.size();
        double radius = 0, width = 0, height = 0, f = 0;
        for (std::size_t s = 0; s < count; ++s) {
            const morpho::SkeletonNode& node = skeleton.nodes[std::size_t(br.nodes[s])];
            radius += node.radius;
            const Lrud l = measureLrud(cave, voxelSize, node.position, passageHeading(skeleton, br, s));
            width += l.left + l.right;
            height += l.up + l.down;
            if (flow && node.voxel < flow->size()) f += (*flow)[node.voxel];
            if (troughs.count(br.nodes[s])) ++r.loopTroughs;
        }
        r.meanRadius_m = radius / double(count);
        r.meanWidth_m = width / double(count);
        r.meanHeight_m = height / double(count);
        if (flow && flow->size() == flow->dims.count()) r.meanFlow = f / double(count);
        if (network) {
            r.role = "side";
            for (std::size_t s = 0; s + 1 < br.nodes.size(); ++s) {
                auto it =
                    edgeRole.find({std::min(br.nodes[s], br.nodes[s + 1]), std::max(br.nodes[s], br.nodes[s + 1])});
                if (it != edgeRole.end() && rank(it->second) < rank(r.role)) r.role = it->second;
            }
        }
        rows.push_back(std::move(r));
    }
    return rows;
}

void writeBranchesCsv(const std::vector<BranchRow>& rows, const std::string& path) {
    std::string out =
        "id,from_node,to_node,nodes,length_m,straight_m,mean_radius_m,mean_width_m,mean_height_m,"
        "azimuth_deg,dip_deg,mean_flow,role,loop_troughs\n";
    for (const BranchRow& r : rows) {
        out += std::to_string(r.id) + "," + std::to_string(r.fromNode) + "," + std::to_string(r.toNode) + "," +
               std::to_string(r.nodes) + "," + detail::num(r.length_m) + "," + detail::num(r.straight_m) + "," +
               detail::num(r.meanRadius_m) + "," + detail::num(r.meanWidth_m) + "," + detail::num(r.meanHeight_m) +
               "," + opt(r.azimuth_deg) + "," + opt(r.dip_deg) + "," + opt(r.meanFlow) + "," + r.role + "," +
               std::to_string(r.loopTroughs) + "\n";
    }
    writeFileAtomic(path, out);
}

}  // namespace cavesim::formats

/// @file pattern.cpp
/// @brief Cave pattern classification from the centreline.
#include "morpho/pattern.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "core/check.h"

namespace cavesim::morpho {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Horizontal length and azimuth in [0°, 180°) of every edge with horizontal length.
struct HorizontalEdge {
    double weight;
    double azimuth;
};

std::vector<HorizontalEdge> horizontalEdges(const Skeleton& s) {
    std::vector<HorizontalEdge> out;
    for (const auto& e : s.edges) {
        const Vec3d& a = s.nodes[std::size_t(e[0])].position;
        const Vec3d& b = s.nodes[std::size_t(e[1])].position;
        const double dx = b[0] - a[0], dy = b[1] - a[1];
        const double w = std::hypot(dx, dy);
        if (!(w > 0)) continue;
        double az = std::atan2(dx, dy) * 180.0 / kPi;  // clockwise from north
        az = std::fmod(az + 360.0, 180.0);
        if (az >= 180.0) az -= 180.0;
        out.push_back({w, az});
    }
    return out;
}

/// Angular distance of two azimuths modulo 180°, degrees in [0, 90].
double axialDistance(double a, double b) {
    double d = std::fmod(std::fabs(a - b), 180.0);
    return std::min(d, 180.0 - d);
}

double shareNear(const std::vector<HorizontalEdge>& edges, const std::vector<double>& dirs, double tol) {
    double total = 0, near = 0;
    for (const HorizontalEdge& e : edges) {
        total += e.weight;
        for (double d : dirs)
            if (axialDistance(e.azimuth, d) <= tol + 1e-9) {
                near += e.weight;
                break;
            }
    }
    return total > 0 ? near / total : 0.0;
}

}  // namespace

std::optional<double> alignedShare(const Skeleton& skeleton, const std::vector<double>& azimuthsDeg,
                                   double toleranceDeg) {
    const auto edges = horizontalEdges(skeleton);
    if (edges.empty()) return std::nullopt;
    return shareNear(edges, azimuthsDeg, toleranceDeg);
}

PatternResult classifyPattern(const Skeleton& skeleton, const GraphMetrics& metrics, double planCoverage,
                              const PatternOptions& o, const std::vector<double>& familyStrikesDeg) {
    CAVESIM_CHECK(o.minBranches >= 1 && o.mazeLoopsPerBranch > 0 && o.mazeLoopsPerBranch <= 1 &&
                      o.alignedToleranceDeg > 0 && o.alignedToleranceDeg <= 45 && o.networkAlignedShare > 0 &&
                      o.networkAlignedShare <= 1 && o.planarBedShare > 0 && o.planarBedShare <= 1 &&
                      o.slabDiameters > 0 && o.ramiformWidthCv > 0 && o.voxelSize >= 0,
                  "pattern options out of range");
    const double nLen =
        std::sqrt(o.bedNormal[0] * o.bedNormal[0] + o.bedNormal[1] * o.bedNormal[1] + o.bedNormal[2] * o.bedNormal[2]);
    CAVESIM_CHECK(nLen > 0 && std::isfinite(nLen), "bed normal must be a finite non-zero vector");
    const Vec3d n{o.bedNormal[0] / nLen, o.bedNormal[1] / nLen, o.bedNormal[2] / nLen};

    PatternResult r;
    r.orientation_entropy = metrics.h_or;
    r.plan_coverage = planCoverage;

    // Degrees.
    std::vector<int> degree(skeleton.nodes.size(), 0);
    for (const auto& e : skeleton.edges) {
        ++degree[std::size_t(e[0])];
        ++degree[std::size_t(e[1])];
    }
    for (int d : degree)
        if (d == 1) ++r.dead_ends;

    // Chamber stubs: a branch between two junctions shorter than their two radii (+ one voxel) lies inside one
    // junction chamber; its ends are merged into one junction (union-find, in branch order), and a
    // stub whose ends are merged already (a pillar inside the chamber) drops its loop.
    const std::vector<Branch> branches = findBranches(skeleton);
    std::vector<int> parent(skeleton.nodes.size());
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&parent](int v) {
        while (parent[std::size_t(v)] != v) v = parent[std::size_t(v)] = parent[std::size_t(parent[std::size_t(v)])];
        return v;
    };
    std::vector<bool> chamber(branches.size(), false);
    long droppedLoops = 0;
    for (std::size_t i = 0; i < branches.size(); ++i) {
        const Branch& br = branches[i];
        const int u = br.nodes.front(), v = br.nodes.back();
        if (br.loop() || degree[std::size_t(u)] < 3 || degree[std::size_t(v)] < 3) continue;
        const double reach =
            skeleton.nodes[std::size_t(u)].radius + skeleton.nodes[std::size_t(v)].radius + o.voxelSize;
        if (!(br.length_m < reach)) continue;
        chamber[i] = true;
        ++r.chamber_branches;
        const int fu = find(u), fv = find(v);
        if (fu == fv)
            ++droppedLoops;
        else
            parent[std::size_t(std::max(fu, fv))] = std::min(fu, fv);
    }
    r.branches = metrics.branches - r.chamber_branches;
    r.loops = metrics.loops - droppedLoops;

    // Junctions after merging: degree of a merged junction = Σ degrees − 2 · its chamber stubs.
    std::vector<long> junctionDegree(skeleton.nodes.size(), 0);
    for (std::size_t v = 0; v < degree.size(); ++v)
        if (degree[v] >= 3) junctionDegree[std::size_t(find(int(v)))] += degree[v];
    for (std::size_t i = 0; i < branches.size(); ++i)
        if (chamber[i]) junctionDegree[std::size_t(find(branches[i].nodes.front()))] -= 2;
    long degreeSum = 0;
    for (std::size_t v = 0; v < degree.size(); ++v)
        if (degree[v] >= 3 && find(int(v)) == int(v)) {
            ++r.junctions;
            degreeSum += junctionDegree[v];
        }
    if (r.junctions > 0) r.junction_degree_mean = double(degreeSum) / double(r.junctions);

    // Branches (chamber stubs aside): blind ends and width variation.
    if (r.branches > 0) {
        long blind = 0;
        std::vector<double> widths;
        for (std::size_t i = 0; i < branches.size(); ++i) {
            if (chamber[i]) continue;
            const Branch& b = branches[i];
            if (degree[std::size_t(b.nodes.front())] == 1 || degree[std::size_t(b.nodes.back())] == 1) ++blind;
            double sum = 0;
            for (int v : b.nodes) sum += skeleton.nodes[std::size_t(v)].radius;
            widths.push_back(sum / double(b.nodes.size()));
        }
        r.dead_end_share = double(blind) / double(r.branches);
        if (widths.size() >= 2) {
            const double mean = std::accumulate(widths.begin(), widths.end(), 0.0) / double(widths.size());
            double ss = 0;
            for (double w : widths) ss += (w - mean) * (w - mean);
            if (mean > 0) r.width_cv = std::sqrt(ss / double(widths.size() - 1)) / mean;
        }
    }

    // Length, mean radius, elevation along the bed normal.
    struct Mid {
        double s, w;
    };
    std::vector<Mid> mids;
    double radiusWeighted = 0;
    for (const auto& e : skeleton.edges) {
        const SkeletonNode& a = skeleton.nodes[std::size_t(e[0])];
        const SkeletonNode& b = skeleton.nodes[std::size_t(e[1])];
        const double len = distance(a.position, b.position);
        if (!(len > 0)) continue;
        const double s = 0.5 * ((a.position[0] + b.position[0]) * n[0] + (a.position[1] + b.position[1]) * n[1] +
                                (a.position[2] + b.position[2]) * n[2]);
        mids.push_back({s, len});
        r.length_m += len;
        radiusWeighted += len * 0.5 * (a.radius + b.radius);
    }
    if (r.length_m > 0) {
        r.loops_per_km = double(r.loops) / (r.length_m / 1000.0);
        const double meanRadius = radiusWeighted / r.length_m;
        r.slab_thickness_m = o.slabDiameters * 2.0 * meanRadius;
        std::sort(mids.begin(), mids.end(), [](const Mid& a, const Mid& b) { return a.s < b.s; });
        double best = 0, window = 0, mean = 0;
        std::size_t lo = 0;
        for (std::size_t hi = 0; hi < mids.size(); ++hi) {
            window += mids[hi].w;
            while (mids[hi].s - mids[lo].s > r.slab_thickness_m + 1e-12) window -= mids[lo++].w;
            best = std::max(best, window);
        }
        r.bed_share = best / r.length_m;
        for (const Mid& m : mids) mean += m.w * m.s;
        mean /= r.length_m;
        double var = 0;
        for (const Mid& m : mids) var += m.w * (m.s - mean) * (m.s - mean);
        r.vertical_spread_m = std::sqrt(var / r.length_m);
    }
    if (r.branches > 0) r.loops_per_branch = double(r.loops) / double(r.branches);

    // Orientation.
    const auto edges = horizontalEdges(skeleton);
    if (!edges.empty()) {
        // Largest share; among equal shares, the pair nearest the aligned edges (least
        // length-weighted distance), then the smallest θ.
        double best = -1, bestSpread = 0;
        for (int theta = 0; theta < 90; ++theta) {
            const double share = shareNear(edges, {double(theta), double(theta + 90)}, o.alignedToleranceDeg);
            double spread = 0;
            for (const HorizontalEdge& e : edges) {
                const double dist = std::min(axialDistance(e.azimuth, theta), axialDistance(e.azimuth, theta + 90.0));
                if (dist <= o.alignedToleranceDeg + 1e-9) spread += e.weight * dist;
            }
            if (share > best + 1e-12 || (share > best - 1e-12 && spread < bestSpread - 1e-9)) {
                best = std::max(best, share);
                bestSpread = spread;
                r.orthogonal_azimuth_deg = double(theta);
            }
        }
        r.orthogonal_share = best;
        if (!familyStrikesDeg.empty()) r.family_share = shareNear(edges, familyStrikesDeg, o.alignedToleranceDeg);
    }

    // Rules.
    const bool planar = r.bed_share && *r.bed_share >= o.planarBedShare;
    const std::optional<double> aligned = familyStrikesDeg.empty() ? r.orthogonal_share : r.family_share;
    const char* alignedName = familyStrikesDeg.empty() ? "orthogonal share" : "family share";
    auto text = [](double v) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.3g", v);
        return std::string(buf);
    };
    if (r.branches == 0) {
        r.pattern = "none";
        r.rule = "no passage";
    } else if (r.branches < o.minBranches) {
        if (r.junctions == 0) {
            r.pattern = "single passage";
            r.rule = "fewer than " + std::to_string(o.minBranches) + " branches and no junction";
        } else {
            r.pattern = "branchwork";
            r.rule = "fewer than " + std::to_string(o.minBranches) + " branches, with junctions: too small for a maze";
        }
    } else if (r.loops_per_branch >= o.mazeLoopsPerBranch) {
        const std::string maze = "loops per branch " + text(r.loops_per_branch) + " ≥ " + text(o.mazeLoopsPerBranch);
        if (aligned && *aligned >= o.networkAlignedShare) {
            r.pattern = "network maze";
            r.rule = maze + "; " + alignedName + " " + text(*aligned) + " ≥ " + text(o.networkAlignedShare);
        } else if (planar) {
            r.pattern = "anastomotic maze";
            r.rule =
                maze + "; no dominant directions; bed share " + text(*r.bed_share) + " ≥ " + text(o.planarBedShare);
        } else {
            r.pattern = "spongework";
            r.rule = maze + "; no dominant directions; not planar (bed share " + text(r.bed_share.value_or(0)) + " < " +
                     text(o.planarBedShare) + ")";
        }
    } else {
        const std::string branching =
            "loops per branch " + text(r.loops_per_branch) + " < " + text(o.mazeLoopsPerBranch);
        if (!planar && r.width_cv && *r.width_cv >= o.ramiformWidthCv) {
            r.pattern = "ramiform";
            r.rule = branching + "; not planar (bed share " + text(r.bed_share.value_or(0)) + " < " +
                     text(o.planarBedShare) + "); width variation " + text(*r.width_cv) + " ≥ " +
                     text(o.ramiformWidthCv);
        } else {
            r.pattern = "branchwork";
            r.rule = branching;
        }
    }
    return r;
}

nlohmann::json toJson(const PatternResult& p) {
    auto opt = [](const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); };
    return {{"class", p.pattern},
            {"rule", p.rule},
            {"criteria",
             {{"length_m", p.length_m},
              {"branches", p.branches},
              {"chamber_branches", p.chamber_branches},
              {"loops", p.loops},
              {"loops_per_km", p.loops_per_km},
              {"loops_per_branch", p.loops_per_branch},
              {"junctions", p.junctions},
              {"junction_degree_mean", opt(p.junction_degree_mean)},
              {"dead_ends", p.dead_ends},
              {"dead_end_share", opt(p.dead_end_share)},
              {"orientation_entropy", opt(p.orientation_entropy)},
              {"orthogonal_share", opt(p.orthogonal_share)},
              {"orthogonal_azimuth_deg", opt(p.orthogonal_azimuth_deg)},
              {"family_share", opt(p.family_share)},
              {"slab_thickness_m", p.slab_thickness_m},
              {"bed_share", opt(p.bed_share)},
              {"vertical_spread_m", p.vertical_spread_m},
              {"plan_coverage", p.plan_coverage},
              {"width_cv", opt(p.width_cv)}}}};
}

}  // namespace cavesim::morpho

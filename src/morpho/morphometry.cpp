// Morphometric indices of the cave (paper §4.2). Conventions: morphometry.h.
#include "morpho/morphometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <boost/geometry.hpp>
#include <boost/geometry/geometries/multi_point.hpp>
#include <boost/geometry/geometries/point_xy.hpp>
#include <boost/geometry/geometries/polygon.hpp>

#include "core/check.h"
#include "morpho/graph_metrics.h"
#include "morpho/skeleton.h"

namespace cavesim::morpho {
namespace {

double indexValue(const Morphometry& m, const std::string& index) {
    if (index == "network_density_opt") return m.network_density_opt;
    if (index == "network_density_rect") return m.network_density_rect;
    if (index == "areal_coverage_pct_opt") return m.areal_coverage_pct_opt;
    if (index == "areal_coverage_pct_rect") return m.areal_coverage_pct_rect;
    if (index == "porosity_pct_opt") return m.porosity_pct_opt;
    if (index == "porosity_pct_rect") return m.porosity_pct_rect;
    if (index == "mean_width_m") return m.mean_width_m;
    CAVESIM_CHECK(false, "morphometry: unknown index '" + index + "'");  // unreachable with categoryRanges()
    return 0.0;
}

/// a / b, or 0 when b is 0 (an empty cave).
double ratio(double a, double b) {
    return b > 0.0 ? a / b : 0.0;
}

namespace bg = boost::geometry;
using Point = bg::model::d2::point_xy<double>;
using Polygon = bg::model::polygon<Point>;

/// The convex hull of the plan cells' corners (cell units). Only the first and the last cell of
/// each row can put a corner on the hull, so 4 points per row suffice.
Polygon planHull(const std::vector<int>& rowMin, const std::vector<int>& rowMax) {
    bg::model::multi_point<Point> corners;
    for (std::size_t j = 0; j < rowMin.size(); ++j) {
        if (rowMin[j] > rowMax[j]) continue;  // empty row
        const double y0 = double(j), y1 = double(j) + 1.0;
        const double x0 = double(rowMin[j]), x1 = double(rowMax[j]) + 1.0;
        bg::append(corners, Point(x0, y0));
        bg::append(corners, Point(x0, y1));
        bg::append(corners, Point(x1, y0));
        bg::append(corners, Point(x1, y1));
    }
    Polygon hull;
    if (!corners.empty()) bg::convex_hull(corners, hull);
    return hull;
}

/// Cells (cell units) of the optimised field: cells of the plan's bounding box whose centre lies
/// within `margin` cells of the centre of a plan cell and inside or on the hull.
long optimisedFieldCells(const std::vector<char>& column, int nx, int iMin, int iMax, int jMin, int jMax, double margin,
                         const Polygon& hull) {
    const int w = iMax - iMin + 1, hgt = jMax - jMin + 1;
    const double big = double(w) * w + double(hgt) * hgt + 1.0;
    std::vector<double> dist(std::size_t(w) * std::size_t(hgt));
    std::vector<double> line, d(std::size_t(std::max(w, hgt)));
    std::vector<int> vtx;
    std::vector<double> z;
    for (int j = 0; j < hgt; ++j) {  // rows
        line.assign(std::size_t(w), big);
        for (int i = 0; i < w; ++i)
            if (column[std::size_t(i + iMin) + std::size_t(nx) * std::size_t(j + jMin)]) line[std::size_t(i)] = 0;
        envelope1d(line.data(), w, d.data(), vtx, z);
        for (int i = 0; i < w; ++i) dist[std::size_t(i) + std::size_t(w) * std::size_t(j)] = d[std::size_t(i)];
    }
    for (int i = 0; i < w; ++i) {  // columns
        line.resize(std::size_t(hgt));
        for (int j = 0; j < hgt; ++j) line[std::size_t(j)] = dist[std::size_t(i) + std::size_t(w) * std::size_t(j)];
        envelope1d(line.data(), hgt, d.data(), vtx, z);
        for (int j = 0; j < hgt; ++j) dist[std::size_t(i) + std::size_t(w) * std::size_t(j)] = d[std::size_t(j)];
    }
    const double m2 = margin * margin;
    long cells = 0;
    for (int j = 0; j < hgt; ++j)
        for (int i = 0; i < w; ++i) {
            if (dist[std::size_t(i) + std::size_t(w) * std::size_t(j)] > m2) continue;
            const Point centre(double(i + iMin) + 0.5, double(j + jMin) + 0.5);
            if (bg::covered_by(centre, hull)) ++cells;
        }
    return cells;
}

}  // namespace

Morphometry computeMorphometry(const Grid3<std::uint8_t>& mask, const Skeleton& skeleton, double voxelSize) {
    CAVESIM_CHECK(voxelSize > 0.0 && std::isfinite(voxelSize),
                  "morphometry: the voxel size must be a positive number of metres, got " + std::to_string(voxelSize));
    const Dims d = mask.dims;
    CAVESIM_CHECK(d.nx >= 0 && d.ny >= 0 && d.nz >= 0, "morphometry: negative mask dimensions " + std::to_string(d.nx) +
                                                           "×" + std::to_string(d.ny) + "×" + std::to_string(d.nz));
    CAVESIM_CHECK(mask.data.size() == d.count(), "morphometry: the mask holds " + std::to_string(mask.data.size()) +
                                                     " values for " + std::to_string(d.nx) + "×" +
                                                     std::to_string(d.ny) + "×" + std::to_string(d.nz) + " voxels");
    validateSkeleton(skeleton);

    Morphometry m;
    const double h = voxelSize;
    for (const auto& e : skeleton.edges) {
        const auto& a = skeleton.nodes[std::size_t(e[0])].position;
        const auto& b = skeleton.nodes[std::size_t(e[1])].position;
        m.length_m += distance(a, b);
    }

    // Plan (columns), per-row extent, bounding box and vertical extent of the cave voxels.
    std::vector<char> column(std::size_t(d.nx) * std::size_t(d.ny), 0);
    std::vector<int> rowMin(std::size_t(d.ny), std::numeric_limits<int>::max());
    std::vector<int> rowMax(std::size_t(d.ny), std::numeric_limits<int>::min());
    int kMin = std::numeric_limits<int>::max(), kMax = std::numeric_limits<int>::min();
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                if (!mask.at(i, j, k)) continue;
                ++m.cave_voxels;
                kMin = std::min(kMin, k);
                kMax = std::max(kMax, k);
                char& c = column[std::size_t(i) + std::size_t(d.nx) * std::size_t(j)];
                if (!c) {
                    c = 1;
                    ++m.plan_cells;
                    rowMin[std::size_t(j)] = std::min(rowMin[std::size_t(j)], i);
                    rowMax[std::size_t(j)] = std::max(rowMax[std::size_t(j)], i);
                }
            }
    if (m.cave_voxels == 0) return m;  // no cave: every index stays 0 (a stray skeleton's length is kept)
    int iMin = std::numeric_limits<int>::max(), iMax = std::numeric_limits<int>::min();
    int jMin = std::numeric_limits<int>::max(), jMax = std::numeric_limits<int>::min();
    for (int j = 0; j < d.ny; ++j) {
        if (rowMin[std::size_t(j)] > rowMax[std::size_t(j)]) continue;
        iMin = std::min(iMin, rowMin[std::size_t(j)]);
        iMax = std::max(iMax, rowMax[std::size_t(j)]);
        jMin = std::min(jMin, j);
        jMax = std::max(jMax, j);
    }

    const double h2 = h * h;
    m.area_m2 = double(m.plan_cells) * h2;
    m.volume_m3 = double(m.cave_voxels) * h2 * h;
    m.vertical_range_m = double(kMax - kMin + 1) * h;
    m.a_field_rect_m2 = double(iMax - iMin + 1) * double(jMax - jMin + 1) * h2;
    const Polygon hull = planHull(rowMin, rowMax);
    m.a_field_hull_m2 = std::abs(bg::area(hull)) * h2;
    if (m.length_m > 0) {
        m.passage_spacing_m = m.a_field_hull_m2 / m.length_m;
        m.field_margin_m = m.passage_spacing_m / 2;
        m.a_field_opt_m2 =
            double(optimisedFieldCells(column, d.nx, iMin, iMax, jMin, jMax, m.field_margin_m / h, hull)) * h2;
    } else {
        m.a_field_opt_m2 = m.a_field_hull_m2;  // no centreline, no spacing: the hull
    }
    m.v_block_rect_m3 = m.a_field_rect_m2 * m.vertical_range_m;
    m.v_block_hull_m3 = m.a_field_hull_m2 * m.vertical_range_m;
    m.v_block_opt_m3 = m.a_field_opt_m2 * m.vertical_range_m;
    m.network_density_rect = ratio(m.length_m, m.a_field_rect_m2);
    m.network_density_opt = ratio(m.length_m, m.a_field_opt_m2);
    m.network_density_hull = ratio(m.length_m, m.a_field_hull_m2);
    m.areal_coverage_pct_hull = 100.0 * ratio(m.area_m2, m.a_field_hull_m2);
    m.porosity_pct_hull = 100.0 * ratio(m.volume_m3, m.v_block_hull_m3);
    m.areal_coverage_pct_rect = 100.0 * ratio(m.area_m2, m.a_field_rect_m2);
    m.areal_coverage_pct_opt = 100.0 * ratio(m.area_m2, m.a_field_opt_m2);
    m.porosity_pct_rect = 100.0 * ratio(m.volume_m3, m.v_block_rect_m3);
    m.porosity_pct_opt = 100.0 * ratio(m.volume_m3, m.v_block_opt_m3);
    m.mean_width_m = ratio(m.area_m2, m.length_m);
    return m;
}

nlohmann::json toJson(const Morphometry& m) {
    return nlohmann::json{
        {"length_m", m.length_m},
        {"area_m2", m.area_m2},
        {"volume_m3", m.volume_m3},
        {"a_field_rect_m2", m.a_field_rect_m2},
        {"a_field_opt_m2", m.a_field_opt_m2},
        {"a_field_hull_m2", m.a_field_hull_m2},
        {"passage_spacing_m", m.passage_spacing_m},
        {"field_margin_m", m.field_margin_m},
        {"v_block_rect_m3", m.v_block_rect_m3},
        {"v_block_opt_m3", m.v_block_opt_m3},
        {"v_block_hull_m3", m.v_block_hull_m3},
        {"network_density_hull", m.network_density_hull},
        {"areal_coverage_pct_hull", m.areal_coverage_pct_hull},
        {"porosity_pct_hull", m.porosity_pct_hull},
        {"network_density_opt", m.network_density_opt},
        {"network_density_rect", m.network_density_rect},
        {"areal_coverage_pct_opt", m.areal_coverage_pct_opt},
        {"areal_coverage_pct_rect", m.areal_coverage_pct_rect},
        {"porosity_pct_opt", m.porosity_pct_opt},
        {"porosity_pct_rect", m.porosity_pct_rect},
        {"mean_width_m", m.mean_width_m},
        {"vertical_range_m", m.vertical_range_m},
        {"cave_voxels", m.cave_voxels},
        {"plan_cells", m.plan_cells},
        {"field_opt_method", "plan_margin_in_hull"},
    };
}

NearMarked nearMarked(const Skeleton& skeleton, const Grid3<std::uint8_t>& marked, double radius) {
    validateSkeleton(skeleton);
    const Dims d = marked.dims;
    CAVESIM_CHECK(marked.data.size() == d.count(), "nearMarked: the grid's data does not match its dims");
    CAVESIM_CHECK(radius >= 0 && std::isfinite(radius), "nearMarked: negative or non-finite radius");
    NearMarked out;
    out.radius_vox = radius;
    const int r = int(std::floor(radius));
    std::vector<Index3> stamp;
    for (int dk = -r; dk <= r; ++dk)
        for (int dj = -r; dj <= r; ++dj)
            for (int di = -r; di <= r; ++di)
                if (double(di * di + dj * dj + dk * dk) <= radius * radius) stamp.push_back({di, dj, dk});
    std::vector<char> near(d.count(), 0);
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                if (!marked.at(i, j, k)) continue;
                for (const Index3& o : stamp)
                    if (d.contains(i + o.i, j + o.j, k + o.k)) near[d.index(i + o.i, j + o.j, k + o.k)] = 1;
            }
    out.block_voxels = long(d.count());
    for (char c : near) out.block_voxels_near += c;
    if (out.block_voxels > 0) out.block_share = double(out.block_voxels_near) / double(out.block_voxels);
    for (const auto& e : skeleton.edges) {
        const SkeletonNode& a = skeleton.nodes[std::size_t(e[0])];
        const SkeletonNode& b = skeleton.nodes[std::size_t(e[1])];
        CAVESIM_CHECK(a.voxel < d.count() && b.voxel < d.count(), "nearMarked: a skeleton node lies outside the grid");
        const double len = distance(a.position, b.position);
        out.length_m += len;
        out.length_near_m += 0.5 * len * (double(near[a.voxel]) + double(near[b.voxel]));
    }
    if (out.length_m > 0) out.centreline_share = out.length_near_m / out.length_m;
    return out;
}

nlohmann::json toJson(const NearMarked& n) {
    auto opt = [](const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); };
    return {{"radius_vox", n.radius_vox},
            {"centreline_share", opt(n.centreline_share)},
            {"block_share", opt(n.block_share)},
            {"length_near_m", n.length_near_m},
            {"block_voxels_near", n.block_voxels_near}};
}

CategoryVotes categoryVotes(const Morphometry& m) {
    CategoryVotes v;
    for (const ReferenceRange& r : categoryRanges()) {
        const double x = indexValue(m, r.key);
        if (!(x >= r.low && x <= r.high)) continue;
        const std::string c = r.category;
        if (c == "unconfined")
            ++v.unconfined;
        else if (c == "confined")
            ++v.confined;
        else
            ++v.chamber;
    }
    return v;
}

std::string caveCategory(const Morphometry& m) {
    const CategoryVotes v = categoryVotes(m);
    const int best = std::max({v.unconfined, v.confined, v.chamber});
    if (best == 0) return "none";
    const int ties = (v.unconfined == best) + (v.confined == best) + (v.chamber == best);
    if (ties > 1) return "mixed";
    if (v.confined == best) return "confined";
    if (v.unconfined == best) return "unconfined";
    return "chamber";
}

}  // namespace cavesim::morpho

/// @file cross_sections.cpp
/// @brief Passage cross-sections sampled from the cave voxels across the centreline.
#include "morpho/cross_sections.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

#include "core/check.h"
#include "morpho/graph_metrics.h"

namespace cavesim::morpho {

const char* sectionClassName(SectionClass c) {
    switch (c) {
        case SectionClass::kTube:
            return "tube";
        case SectionClass::kCanyon:
            return "canyon";
        case SectionClass::kKeyhole:
            return "keyhole";
        case SectionClass::kOther:
            return "other";
        case SectionClass::kShort:
            break;
    }
    return "short";
}

SectionShape measureSection(const SectionSlice& s, const SectionOptions& o) {
    SectionShape shape;
    std::vector<int> width(std::size_t(std::max(s.rows, 0)), 0);
    int top = -1, bottom = -1;
    long count = 0;
    for (int r = 0; r < s.rows; ++r) {
        for (int c = 0; c < s.cols; ++c)
            width[std::size_t(r)] += s.cells[std::size_t(r) * std::size_t(s.cols) + std::size_t(c)] ? 1 : 0;
        if (width[std::size_t(r)] > 0) {
            if (top < 0) top = r;
            bottom = r;
            count += width[std::size_t(r)];
        }
    }
    if (top < 0) return shape;
    const int rows = bottom - top + 1;
    int maxWidth = 0;
    for (int r = top; r <= bottom; ++r) maxWidth = std::max(maxWidth, width[std::size_t(r)]);
    shape.height_m = rows * s.step;
    shape.width_m = maxWidth * s.step;
    shape.area_m2 = double(count) * s.step * s.step;

    // Keyhole: a split with a rounded upper part over a narrow slot.
    for (int k = top + 1; k <= bottom; ++k) {
        const int nUpper = k - top, nLower = bottom - k + 1;
        if (nUpper < o.keyholeMinPart * rows || nLower < o.keyholeMinPart * rows) continue;
        int maxUpper = 0, maxLower = 0;
        for (int r = top; r < k; ++r) maxUpper = std::max(maxUpper, width[std::size_t(r)]);
        for (int r = k; r <= bottom; ++r) maxLower = std::max(maxLower, width[std::size_t(r)]);
        if (maxLower <= o.keyholeSlotRatio * maxUpper && width[std::size_t(top)] <= o.keyholeTopRatio * maxUpper) {
            shape.cls = SectionClass::kKeyhole;
            return shape;
        }
    }
    const double w = shape.width_m, h = shape.height_m;
    if (h >= o.canyonRatio * w) {
        shape.cls = SectionClass::kCanyon;
    } else if (w >= o.tubeLow * h && w <= o.tubeHigh * h && shape.area_m2 >= o.tubeFill * w * h) {
        shape.cls = SectionClass::kTube;
    } else {
        shape.cls = SectionClass::kOther;
    }
    return shape;
}

SectionSlice sliceAcross(const Grid3<std::uint8_t>& mask, double voxelSize, const Vec3d& position, const Vec3d& heading,
                         int halfCols, int halfRows, int samplesPerVoxel) {
    CAVESIM_CHECK(voxelSize > 0 && halfCols >= 0 && halfRows >= 0 && samplesPerVoxel >= 1, "bad slice arguments");
    SectionSlice s;
    s.cols = 2 * halfCols + 1;
    s.rows = 2 * halfRows + 1;
    s.step = voxelSize / samplesPerVoxel;
    s.cells.assign(std::size_t(s.cols) * std::size_t(s.rows), 0);
    double hx = heading[0], hy = heading[1];
    const double len = std::hypot(hx, hy);
    if (!(len > 1e-9)) {
        hx = 0;
        hy = 1;
    } else {
        hx /= len;
        hy /= len;
    }
    // Columns left to right looking along the heading: right = (hy, −hx, 0); rows top down.
    const Dims& d = mask.dims;
    std::vector<std::uint8_t> cave(s.cells.size(), 0);
    for (int r = 0; r < s.rows; ++r) {
        const double v = (halfRows - r) * s.step;
        for (int c = 0; c < s.cols; ++c) {
            const double u = (c - halfCols) * s.step;
            const double p[3] = {position[0] + u * hy, position[1] - u * hx, position[2] + v};
            const double fi = std::floor(p[0] / voxelSize), fj = std::floor(p[1] / voxelSize),
                         fk = std::floor(p[2] / voxelSize);
            if (fi < 0 || fj < 0 || fk < 0 || fi >= d.nx || fj >= d.ny || fk >= d.nz) continue;
            cave[std::size_t(r) * std::size_t(s.cols) + std::size_t(c)] = mask.at(int(fi), int(fj), int(fk)) ? 1 : 0;
        }
    }
    // Seed: the centre, or the nearest cave sample to it (ties: lowest index).
    long seed = -1;
    const std::size_t centre = std::size_t(halfRows) * std::size_t(s.cols) + std::size_t(halfCols);
    if (cave[centre]) {
        seed = long(centre);
    } else {
        long best = std::numeric_limits<long>::max();
        for (int r = 0; r < s.rows; ++r)
            for (int c = 0; c < s.cols; ++c) {
                const std::size_t n = std::size_t(r) * std::size_t(s.cols) + std::size_t(c);
                const long dd = long(r - halfRows) * (r - halfRows) + long(c - halfCols) * (c - halfCols);
                if (cave[n] && dd < best) {
                    best = dd;
                    seed = long(n);
                }
            }
    }
    if (seed < 0) return s;
    std::vector<std::size_t> stack{std::size_t(seed)};
    s.cells[std::size_t(seed)] = 1;
    while (!stack.empty()) {
        const std::size_t n = stack.back();
        stack.pop_back();
        const int r = int(n / std::size_t(s.cols)), c = int(n % std::size_t(s.cols));
        if (r == 0 || c == 0 || r == s.rows - 1 || c == s.cols - 1) s.clipped = true;
        const int nr[4] = {r - 1, r + 1, r, r}, nc[4] = {c, c, c - 1, c + 1};
        for (int q = 0; q < 4; ++q) {
            if (nr[q] < 0 || nc[q] < 0 || nr[q] >= s.rows || nc[q] >= s.cols) continue;
            const std::size_t m = std::size_t(nr[q]) * std::size_t(s.cols) + std::size_t(nc[q]);
            if (cave[m] && !s.cells[m]) {
                s.cells[m] = 1;
                stack.push_back(m);
            }
        }
    }
    return s;
}

namespace {

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const std::size_t m = v.size() / 2;
    return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

double distance(const Vec3d& a, const Vec3d& b) {
    const double dx = b[0] - a[0], dy = b[1] - a[1], dz = b[2] - a[2];
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

}  // namespace

CrossSections measureCrossSections(const Grid3<std::uint8_t>& mask, double voxelSize, const Skeleton& skeleton,
                                   const SectionOptions& o) {
    CAVESIM_CHECK(voxelSize > 0 && std::isfinite(voxelSize), "voxel size must be finite and positive");
    CAVESIM_CHECK(o.samplesPerVoxel >= 1 && o.stationStride >= 1, "section options out of range");
    CrossSections out;
    const std::vector<Branch> branches = findBranches(skeleton);
    std::vector<int> degree(skeleton.nodes.size(), 0);
    for (const auto& e : skeleton.edges) {
        ++degree[std::size_t(e[0])];
        ++degree[std::size_t(e[1])];
    }
    const int spv = o.samplesPerVoxel;
    const int cap = 64 * spv;
    out.passages.resize(branches.size());
    std::vector<int> stationCount(branches.size(), 0);
    // Each passage writes only its own slot: the result does not depend on the thread count.
    tbb::parallel_for(std::size_t(0), branches.size(), [&](std::size_t b) {
        const Branch& br = branches[b];
        const std::size_t m = br.nodes.size();
        auto pos = [&](std::size_t i) -> const Vec3d& { return skeleton.nodes[std::size_t(br.nodes[i])].position; };
        PassageSection ps;
        ps.passage = int(b);
        ps.length_m = br.length_m;
        ps.z_min_m = std::numeric_limits<double>::infinity();
        ps.z_max_m = -std::numeric_limits<double>::infinity();
        double zSum = 0;
        for (std::size_t i = 0; i < m; ++i) {
            zSum += pos(i)[2];
            ps.z_min_m = std::min(ps.z_min_m, pos(i)[2]);
            ps.z_max_m = std::max(ps.z_max_m, pos(i)[2]);
        }
        ps.z_m = zSum / double(m);

        // Arc length along the chain, and the stations.
        std::vector<double> arc(m, 0.0);
        for (std::size_t i = 1; i < m; ++i) arc[i] = arc[i - 1] + distance(pos(i - 1), pos(i));
        const double total = arc[m - 1];
        const SkeletonNode& front = skeleton.nodes[std::size_t(br.nodes.front())];
        const SkeletonNode& back = skeleton.nodes[std::size_t(br.nodes.back())];
        const double keepFront = degree[std::size_t(br.nodes.front())] >= 3 ? 1.5 * front.radius + voxelSize : 0.0;
        const double keepBack = degree[std::size_t(br.nodes.back())] >= 3 ? 1.5 * back.radius + voxelSize : 0.0;
        std::vector<std::size_t> allowed;
        for (std::size_t i = 1; i + 1 < m; ++i)
            if (arc[i] >= keepFront && total - arc[i] >= keepBack) allowed.push_back(i);
        std::vector<std::size_t> stations;
        // Every stationStride-th node, and at least the last station's passage radius along the chain
        // from it (sections about one radius apart in wide passages).
        for (std::size_t a = 0; a < allowed.size(); a += std::size_t(o.stationStride)) {
            const std::size_t i = allowed[a];
            if (!stations.empty()) {
                const std::size_t last = stations.back();
                if (arc[i] - arc[last] < skeleton.nodes[std::size_t(br.nodes[last])].radius) continue;
            }
            stations.push_back(i);
        }
        if (stations.empty()) {
            ps.cls = SectionClass::kShort;
            out.passages[b] = std::move(ps);
            return;
        }

        std::vector<SectionSlice> slices;
        std::vector<SectionShape> shapes;
        for (std::size_t i : stations) {
            const SkeletonNode& node = skeleton.nodes[std::size_t(br.nodes[i])];
            const std::size_t i0 = i >= 2 ? i - 2 : 0, i1 = std::min(i + 2, m - 1);
            const Vec3d heading{pos(i1)[0] - pos(i0)[0], pos(i1)[1] - pos(i0)[1], pos(i1)[2] - pos(i0)[2]};
            const double rv = node.radius / voxelSize;
            const int halfCols = std::min(cap, int(std::ceil((4.0 * rv + 2.0) * spv)));
            const int halfRows = std::min(cap, int(std::ceil((8.0 * rv + 2.0) * spv)));
            Vec3d at = node.position;
            {  // the smoothed node may sit just outside the cave: fall back to its voxel's centre
                const Index3 v = mask.dims.coord(node.voxel);
                const double fi = std::floor(at[0] / voxelSize), fj = std::floor(at[1] / voxelSize),
                             fk = std::floor(at[2] / voxelSize);
                const bool inside = fi >= 0 && fj >= 0 && fk >= 0 && fi < mask.dims.nx && fj < mask.dims.ny &&
                                    fk < mask.dims.nz && mask.at(int(fi), int(fj), int(fk));
                if (!inside) at = {(v.i + 0.5) * voxelSize, (v.j + 0.5) * voxelSize, (v.k + 0.5) * voxelSize};
            }
            slices.push_back(sliceAcross(mask, voxelSize, at, heading, halfCols, halfRows, spv));
            shapes.push_back(measureSection(slices.back(), o));
            ++ps.votes[std::size_t(shapes.back().cls)];
        }
        stationCount[b] = int(stations.size());
        int best = 0;
        for (int c = 1; c < kSectionClasses; ++c)
            if (ps.votes[std::size_t(c)] > ps.votes[std::size_t(best)]) best = c;
        ps.cls = SectionClass(best);
        std::vector<double> ws, hs;
        for (const SectionShape& s : shapes) {
            ws.push_back(s.width_m);
            hs.push_back(s.height_m);
        }
        ps.width_m = median(ws);
        ps.height_m = median(hs);
        double bestScore = std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < shapes.size(); ++k) {
            if (shapes[k].cls != ps.cls) continue;
            const double score =
                std::fabs(shapes[k].width_m - ps.width_m) + std::fabs(shapes[k].height_m - ps.height_m);
            if (score < bestScore) {
                bestScore = score;
                ps.example = slices[k];
                ps.exampleShape = shapes[k];
            }
        }
        out.passages[b] = std::move(ps);
    });
    for (int n : stationCount) out.stations += n;
    return out;
}

nlohmann::json toJson(const CrossSections& c) {
    nlohmann::json summary = nlohmann::json::array();
    for (int k = 0; k <= int(SectionClass::kShort); ++k) {
        long n = 0;
        double length = 0, w = 0, h = 0, ratio = 0, zw = 0, zMin = 0, zMax = 0;
        for (const PassageSection& p : c.passages) {
            if (int(p.cls) != k) continue;
            if (n == 0 || p.z_min_m < zMin) zMin = p.z_min_m;
            if (n == 0 || p.z_max_m > zMax) zMax = p.z_max_m;
            ++n;
            length += p.length_m;
            w += p.width_m;
            h += p.height_m;
            ratio += p.height_m > 0 ? p.width_m / p.height_m : 0.0;
            zw += p.z_m * p.length_m;
        }
        const bool shapes = k < kSectionClasses;
        auto meanOr = [n, shapes](double v) {
            return n > 0 && shapes ? nlohmann::json(v / double(n)) : nlohmann::json(nullptr);
        };
        summary.push_back({{"class", sectionClassName(SectionClass(k))},
                           {"passages", n},
                           {"length_m", length},
                           {"mean_width_m", meanOr(w)},
                           {"mean_height_m", meanOr(h)},
                           {"mean_w_over_h", meanOr(ratio)},
                           {"z_mean_m", length > 0 ? nlohmann::json(zw / length) : nlohmann::json(nullptr)},
                           {"z_min_m", n > 0 ? nlohmann::json(zMin) : nlohmann::json(nullptr)},
                           {"z_max_m", n > 0 ? nlohmann::json(zMax) : nlohmann::json(nullptr)}});
    }
    nlohmann::json passages = nlohmann::json::array();
    for (const PassageSection& p : c.passages) {
        const bool measured = p.cls != SectionClass::kShort;
        auto size = [measured](double v) { return measured ? nlohmann::json(v) : nlohmann::json(nullptr); };
        passages.push_back(
            {{"id", p.passage},
             {"class", sectionClassName(p.cls)},
             {"length_m", p.length_m},
             {"width_m", size(p.width_m)},
             {"height_m", size(p.height_m)},
             {"w_over_h", p.height_m > 0 ? nlohmann::json(p.width_m / p.height_m) : nlohmann::json(nullptr)},
             {"z_m", p.z_m},
             {"z_min_m", p.z_min_m},
             {"z_max_m", p.z_max_m},
             {"votes",
              {{"tube", p.votes[0]}, {"canyon", p.votes[1]}, {"keyhole", p.votes[2]}, {"other", p.votes[3]}}}});
    }
    return {{"stations", c.stations}, {"summary", summary}, {"passages", passages}};
}

}  // namespace cavesim::morpho

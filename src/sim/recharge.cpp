#include "sim/recharge.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "core/error.h"
#include "core/text.h"
#include "sim/domain.h"
#include "sim/fractures.h"
#include "sim/parameters.h"
#include "sim/scenario_io.h"

namespace cavesim {
namespace {


/// "file:line: key 'k' = value: allowed".
[[noreturn]] void fail(const Scenario& s, int line, const void* field, const std::string& value,
                       const std::string& allowed) {
    if (const int own = keyLine(s, field); own > 0) line = own;  // the key's line, else its entry's
    std::ostringstream os;
    os << s.path;
    if (line > 0) os << ":" << line;
    os << ": key '" << scenarioKey(s, field) << "' = " << value << ": " << allowed;
    throw InputError(os.str());
}

std::string intsText(const std::vector<int>& v) {
    std::string out = "[";
    for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + std::to_string(v[i]);
    return out + "]";
}

std::string pointsText(const std::vector<Vec3d>& v) {
    std::string out = "[";
    for (std::size_t i = 0; i < v.size() && i < 3; ++i)
        out += std::string(i ? ", " : "") + "[" + shortestText(v[i][0]) + ", " + shortestText(v[i][1]) + ", " +
               shortestText(v[i][2]) + "]";
    return out + (v.size() > 3 ? ", ...]" : "]");
}

/// The entry's `kind` as the file gives it, quoted: "\"sinkholes\"".
std::string kindValue(RechargeKind k) {
    return k == RechargeKind::kSinkholes ? "\"sinkholes\"" : k == RechargeKind::kDiffuse ? "\"diffuse\"" : "\"stream\"";
}

/// A uniform integer in [0, n) from one draw (the high half of draw × n).
std::size_t uniformIndex(Rng& rng, std::size_t n) {
    return std::size_t((static_cast<unsigned __int128>(rng()) * n) >> 64);
}

struct Area {
    int x0, y0, x1, y1;
};

Area areaOf(const Scenario& s, const RechargeSpec& r) {
    if (r.area.size() == 4) return {r.area[0], r.area[1], r.area[2], r.area[3]};
    return {0, 0, s.size[0] - 1, s.size[1] - 1};
}

SourceSpec oneVoxel(int i, int j, int k, double pressure, int line) {
    SourceSpec src;
    src.box.lo = src.box.hi = {i, j, k};
    src.pressure = pressure;
    src.line = line;
    return src;
}

/// The highest rock voxel of column (i, j): the top layer, or with a `[site] dem` its
/// landSurfaceLayer. A column whose every voxel is air is an error naming the entry.
int landTop(const Scenario& s, const RechargeSpec& r, int i, int j) {
    if (!s.siteData || s.siteData->landSurface.empty()) return s.size[2] - 1;
    const double land = s.siteData->landSurface[std::size_t(i) + std::size_t(s.size[0]) * std::size_t(j)];
    const int k = landSurfaceLayer(s, land);
    if (k < 0)
        fail(s, r.line, &r.kind, kindValue(r.kind),
             "an input falls on column x " + std::to_string(i) + ", y " + std::to_string(j) +
                 ", where the land surface ([site] dem, " + shortestText(land) +
                 " m) lies below every voxel centre: the column is air");
    return k;
}

/// Checks that every voxel of `box` (an input of entry `r`) is karst rock: none lies below a
/// `[site] base_of_limestone` (insoluble, inert: no place for a source, as for a site's sinkhole).
/// (The base is shown to the millimetre: inverse-distance weighting leaves round-off in it.)
void checkSoluble(const Scenario& s, const RechargeSpec& r, const VoxelBox& box) {
    if (!s.siteData || s.siteData->baseOfLimestone.empty()) return;
    const double z = s.site.origin[2] + (box.lo[2] + 0.5) * s.voxelSize;  // the box's lowest voxel centre
    for (int j = box.lo[1]; j <= box.hi[1]; ++j)
        for (int i = box.lo[0]; i <= box.hi[0]; ++i) {
            const double base = s.siteData->baseOfLimestone[std::size_t(i) + std::size_t(s.size[0]) * std::size_t(j)];
            if (z < base)
                fail(s, r.line, &r.kind, kindValue(r.kind),
                     "an input reaches voxel [" + std::to_string(i) + ", " + std::to_string(j) + ", " +
                         std::to_string(box.lo[2]) + "] (centre " + shortestText(z) +
                         " m), below the base of the limestone there ([site] base_of_limestone, " +
                         shortestText(std::round(base * 1000) / 1000) + " m): its voxel is insoluble rock" +
                         (r.kind == RechargeKind::kSinkholes ? "; lower radius or move the area" : ""));
        }
}

/// The sources of entry `index`; an empty result from sinkholes that do not fit.
std::vector<SourceSpec> expand(const Scenario& s, const RechargeSpec& r, std::size_t index, bool& fits) {
    fits = true;
    Rng rng(familySeed(s.seed ^ 0x5245434841524745ull /* "RECHARGE" */, index));
    const Area a = areaOf(s, r);
    std::vector<SourceSpec> out;
    switch (r.kind) {
        case RechargeKind::kSinkholes: {
            // Columns drawn from the whole area; one within r of its edge is passed over, so that every
            // box lies whole in the area (and in the block) and the centres are uniform over the
            // columns that allow that (validateRecharge has checked that 2r + 1 columns fit).
            const int w = a.x1 - a.x0 + 1, h = a.y1 - a.y0 + 1;
            if (w < 2 * r.radius + 1 || h < 2 * r.radius + 1) {
                fits = false;
                return {};
            }
            std::vector<std::size_t> cells(std::size_t(w) * std::size_t(h));
            std::iota(cells.begin(), cells.end(), std::size_t(0));
            std::vector<std::array<int, 2>> taken;
            for (std::size_t n = 0; n < cells.size() && int(taken.size()) < r.count; ++n) {
                std::swap(cells[n], cells[n + uniformIndex(rng, cells.size() - n)]);  // Fisher-Yates, lazily
                const int i = a.x0 + int(cells[n] % std::size_t(w)), j = a.y0 + int(cells[n] / std::size_t(w));
                if (i < a.x0 + r.radius || i > a.x1 - r.radius || j < a.y0 + r.radius || j > a.y1 - r.radius) continue;
                const bool apart = std::all_of(taken.begin(), taken.end(), [&](const std::array<int, 2>& t) {
                    return std::max(std::abs(t[0] - i), std::abs(t[1] - j)) >= 2 * r.radius + 1;
                });
                if (apart) taken.push_back({i, j});
            }
            if (int(taken.size()) < r.count) {
                fits = false;
                return {};
            }
            for (const auto& t : taken) {
                SourceSpec src;
                const int x0 = t[0] - r.radius, y0 = t[1] - r.radius, x1 = t[0] + r.radius, y1 = t[1] + r.radius;
                // Under uneven land the box hangs from the lowest surface voxel of its columns, so
                // every voxel of it is rock.
                int top = s.size[2] - 1;
                for (int j = y0; j <= y1; ++j)
                    for (int i = x0; i <= x1; ++i) top = std::min(top, landTop(s, r, i, j));
                if (top < r.radius)
                    fail(s, r.line, &r.radius, std::to_string(r.radius),
                         "a sinkhole of radius r is a (2r+1) × (2r+1) × (r+1) box under the land surface; at "
                         "columns x " +
                             std::to_string(x0) + ".." + std::to_string(x1) + ", y " + std::to_string(y0) + ".." +
                             std::to_string(y1) + " the [site] dem leaves " + std::to_string(top + 1) +
                             " layer(s) of rock, so it would reach below the block's bottom: must be at most " +
                             std::to_string(top) + " there");
                src.box.lo = {x0, y0, top - r.radius};
                src.box.hi = {x1, y1, top};
                src.pressure = r.pressure;
                src.line = r.line;
                checkSoluble(s, r, src.box);
                out.push_back(src);
            }
            break;
        }
        case RechargeKind::kDiffuse: {
            const int w = a.x1 - a.x0 + 1, h = a.y1 - a.y0 + 1;
            const int cu = int(std::ceil(w / r.spacing - 1e-9)), cv = int(std::ceil(h / r.spacing - 1e-9));
            const auto edge = [&](int c, int len) { return std::min(len, int(std::floor(c * r.spacing + 1e-9))); };
            for (int v = 0; v < cv; ++v)
                for (int u = 0; u < cu; ++u) {
                    const int i0 = edge(u, w), i1 = std::max(i0 + 1, edge(u + 1, w));
                    const int j0 = edge(v, h), j1 = std::max(j0 + 1, edge(v + 1, h));
                    const int i = a.x0 + i0 + int(uniformIndex(rng, std::size_t(i1 - i0)));
                    const int j = a.y0 + j0 + int(uniformIndex(rng, std::size_t(j1 - j0)));
                    out.push_back(oneVoxel(i, j, landTop(s, r, i, j), 0.0, r.line));
                }
            break;
        }
        case RechargeKind::kStream: {
            std::vector<double> at{0.0};  // arc length at each point
            for (std::size_t p = 0; p + 1 < r.points.size(); ++p) {
                const Vec3d& A = r.points[p];
                const Vec3d& B = r.points[p + 1];
                at.push_back(at.back() + std::hypot(B[0] - A[0], B[1] - A[1], B[2] - A[2]));
            }
            std::size_t seg = 0;
            for (long m = 0; double(m) * r.spacing <= at.back() + 1e-9; ++m) {
                const double t = double(m) * r.spacing;
                while (seg + 2 < r.points.size() && t > at[seg + 1]) ++seg;
                const Vec3d& A = r.points[seg];
                const Vec3d& B = r.points[seg + 1];
                const double len = at[seg + 1] - at[seg];
                const double f = len > 0 ? std::clamp((t - at[seg]) / len, 0.0, 1.0) : 0.0;
                std::array<int, 3> v{int(std::lround(A[0] + f * (B[0] - A[0]))),
                                     int(std::lround(A[1] + f * (B[1] - A[1]))),
                                     int(std::lround(A[2] + f * (B[2] - A[2])))};
                v[2] = std::min(v[2], landTop(s, r, v[0], v[1]));  // sinks into the rock under the land
                const bool repeat =
                    std::any_of(out.begin(), out.end(), [&](const SourceSpec& q) { return q.box.lo == v; });
                if (!repeat) out.push_back(oneVoxel(v[0], v[1], v[2], 0.0, r.line));
                if (out.size() > 4 * kMaxSources) break;  // far too many already: validateRecharge says so
            }
            break;
        }
    }
    if (r.kind != RechargeKind::kSinkholes)
        for (SourceSpec& src : out) {
            checkSoluble(s, r, src.box);
            src.pressure = r.pressure / double(out.size());
        }
    return out;
}

}  // namespace

int landSurfaceLayer(const Scenario& s, double land) {
    const double z0 = s.site.origin[2], h = s.voxelSize;
    int k = s.size[2] - 1;
    while (k >= 0 && z0 + (k + 0.5) * h > land) --k;
    return k;
}

std::vector<SourceSpec> rechargeSources(const Scenario& s, std::vector<std::size_t>* perEntry) {
    std::vector<SourceSpec> all;
    if (perEntry) perEntry->clear();
    for (std::size_t e = 0; e < s.recharge.size(); ++e) {
        bool fits = true;
        std::vector<SourceSpec> part = expand(s, s.recharge[e], e, fits);
        if (!fits)
            throw InputError(s.path + ": [[recharge]] entry " + std::to_string(e + 1) + ": sinkholes do not fit");
        all.insert(all.end(), part.begin(), part.end());
        if (perEntry) perEntry->push_back(part.size());
    }
    return all;
}

std::vector<SourceSpec> allSources(const Scenario& s) {
    std::vector<SourceSpec> all = s.sources;
    if (!s.recharge.empty()) {
        const std::vector<SourceSpec> inputs = rechargeSources(s);
        all.insert(all.end(), inputs.begin(), inputs.end());
    }
    if (s.siteData) all.insert(all.end(), s.siteData->sources.begin(), s.siteData->sources.end());
    return all;
}

void validateRecharge(const Scenario& s) {
    std::size_t total = s.sources.size() + (s.siteData ? s.siteData->sources.size() : 0);
    const int nx = s.size[0], ny = s.size[1], nz = s.size[2];
    const std::string face = std::string(s.site.dem.empty() ? "the land surface is the block's top face"
                                                            : "the land surface is the [site] dem over the block") +
                             ": columns x 0.." + std::to_string(nx - 1) + ", y 0.." + std::to_string(ny - 1);
    for (std::size_t e = 0; e < s.recharge.size(); ++e) {
        const RechargeSpec& r = s.recharge[e];
        const bool stream = r.kind == RechargeKind::kStream;
        if (!r.area.empty()) {
            if (stream)
                fail(s, r.line, &r.area, intsText(r.area), "a stream follows `points`; give area = [] (or omit it)");
            if (r.area.size() != 4) fail(s, r.line, &r.area, intsText(r.area), "must be [] or [x0, y0, x1, y1]");
            if (r.area[0] > r.area[2] || r.area[1] > r.area[3])
                fail(s, r.line, &r.area, intsText(r.area), "the corners must satisfy x0 <= x1, y0 <= y1");
            if (r.area[2] >= nx || r.area[3] >= ny)
                fail(s, r.line, &r.area, intsText(r.area), "recharge outside the land surface: " + face);
        }
        if (stream) {
            if (r.points.size() < 2)
                fail(s, r.line, &r.points, pointsText(r.points), "a stream needs at least 2 points [x, y, z]");
            for (const Vec3d& p : r.points)
                if (p[0] < 0 || p[1] < 0 || p[2] < 0 || p[0] > nx - 1 || p[1] > ny - 1 || p[2] > nz - 1)
                    fail(s, r.line, &r.points, pointsText(r.points),
                         "recharge outside the land surface: every point must lie inside the block (x 0.." +
                             std::to_string(nx - 1) + ", y 0.." + std::to_string(ny - 1) + ", z 0.." +
                             std::to_string(nz - 1) + "; z = " + std::to_string(nz - 1) + " is the top face)");
        } else if (!r.points.empty()) {
            fail(s, r.line, &r.points, pointsText(r.points),
                 "only a stream takes points; give points = [] (or omit it)");
        }
        if (r.kind == RechargeKind::kDiffuse) {
            const Area a = areaOf(s, r);
            const double cells =
                std::ceil((a.x1 - a.x0 + 1) / r.spacing - 1e-9) * std::ceil((a.y1 - a.y0 + 1) / r.spacing - 1e-9);
            if (double(total) + cells > double(kMaxSources))
                fail(s, r.line, &r.spacing, shortestText(r.spacing),
                     "gives " + shortestText(cells) +
                         " inputs; with the [[source]] entries and the recharge before it "
                         "that is more than the " +
                         std::to_string(kMaxSources) +
                         " sources allowed (stage 1 marches one zone per source): raise spacing or shrink the area");
        }
        if (r.kind == RechargeKind::kSinkholes) {
            // Each sinkhole is a (2r+1)² × (r+1) box: it must fit in its area and under the top face
            // (it was silently cut to the block before).
            const Area a = areaOf(s, r);
            const int side = 2 * r.radius + 1;
            if (side > a.x1 - a.x0 + 1 || side > a.y1 - a.y0 + 1 || r.radius + 1 > nz)
                fail(s, r.line, &r.radius, std::to_string(r.radius),
                     "a sinkhole of radius r is a (2r+1) × (2r+1) × (r+1) box, which must fit in its area [" +
                         std::to_string(a.x0) + ", " + std::to_string(a.y0) + ", " + std::to_string(a.x1) + ", " +
                         std::to_string(a.y1) + "] and in the block's " + std::to_string(nz) +
                         " layers: must be at most " +
                         std::to_string(std::max(0, std::min({(a.x1 - a.x0) / 2, (a.y1 - a.y0) / 2, nz - 1}))));
        }
        bool fits = true;
        const std::vector<SourceSpec> part = expand(s, r, e, fits);
        if (!fits) {
            const Area a = areaOf(s, r);
            fail(s, r.line, &r.count, std::to_string(r.count),
                 "the area [" + std::to_string(a.x0) + ", " + std::to_string(a.y0) + ", " + std::to_string(a.x1) +
                     ", " + std::to_string(a.y1) + "] cannot hold that many sinkholes of radius " +
                     std::to_string(r.radius) + " at least " + std::to_string(2 * r.radius + 1) +
                     " columns apart: lower count or radius, or widen the area");
        }
        total += part.size();
        if (total > kMaxSources) {
            const void* field = r.kind == RechargeKind::kSinkholes ? static_cast<const void*>(&r.count)
                                                                   : static_cast<const void*>(&r.spacing);
            fail(s, r.line, field,
                 r.kind == RechargeKind::kSinkholes ? std::to_string(r.count) : shortestText(r.spacing),
                 "gives " + std::to_string(part.size()) +
                     " inputs; with the [[source]] entries and the recharge "
                     "before it that is " +
                     std::to_string(total) + " sources, at most " + std::to_string(kMaxSources) +
                     " are allowed (stage 1 marches one zone per source)" +
                     (r.kind == RechargeKind::kSinkholes ? std::string() : ": raise spacing"));
        }
        for (const SourceSpec& src : part)
            for (std::size_t j = 0; j < s.sinks.size(); ++j) {
                if (boxesOverlap(src.box, s.sinks[j].box))
                    fail(s, r.line, &r.kind, kindValue(r.kind) + " (entry " + std::to_string(e + 1) + ")",
                         "an input at [" + std::to_string(src.box.lo[0]) + ", " + std::to_string(src.box.lo[1]) + ", " +
                             std::to_string(src.box.lo[2]) + "] overlaps [[sink]] entry " + std::to_string(j + 1) +
                             " (line " + std::to_string(s.sinks[j].line) + "): a voxel cannot be both source and sink");
            }
        if (s.siteData)
            for (const SourceSpec& src : part)
                for (std::size_t j = 0; j < s.siteData->sinks.size(); ++j)
                    if (boxesOverlap(src.box, s.siteData->sinks[j].box))
                        fail(s, r.line, &r.kind, "(entry " + std::to_string(e + 1) + ")",
                             "an input at [" + std::to_string(src.box.lo[0]) + ", " + std::to_string(src.box.lo[1]) +
                                 ", " + std::to_string(src.box.lo[2]) + "] falls on the voxel of spring '" +
                                 s.siteData->sinkNames[j] +
                                 "' ([site] springs): a voxel cannot be both source and sink");
    }
}

void validateFractureFamilies(const Scenario& s) {
    const Dims dims{s.size[0], s.size[1], s.size[2]};
    const int longest = std::max({dims.nx, dims.ny, dims.nz});
    const std::string block =
        std::to_string(dims.nx) + " × " + std::to_string(dims.ny) + " × " + std::to_string(dims.nz) + " voxels";
    for (const FractureFamily& f : s.fractureFamilies) {
        if (f.minLength > longest)
            fail(s, f.line, &f.minLength, shortestText(f.minLength),
                 "the fracture family cannot fit: its smallest fracture is longer than the block's longest side (" +
                     block + "): must be in (0, " + std::to_string(longest) + "]");
        if (f.minLength > f.maxLength)
            fail(s, f.line, &f.minLength, shortestText(f.minLength),
                 "must be at most max_length (" + shortestText(f.maxLength) + ")");
        if (f.spacing > 0 && f.density > 0)
            fail(s, f.line, &f.density, shortestText(f.density),
                 "give spacing or density, not both: set one of them to 0 (spacing = " + shortestText(f.spacing) + ")");
        if (!(f.spacing > 0) && !(f.density > 0))
            fail(s, f.line, &f.spacing, shortestText(f.spacing), "give spacing > 0 or density > 0");
        if (f.spacing > longest)
            fail(s, f.line, &f.spacing, shortestText(f.spacing),
                 "the fracture family cannot fit: its spacing is larger than the block (" + block +
                     "): must be in (0, " + std::to_string(longest) + "]");
        const double count = fractureCount(f, dims);
        const void* field = f.density > 0 ? static_cast<const void*>(&f.density) : static_cast<const void*>(&f.spacing);
        const std::string value = shortestText(f.density > 0 ? f.density : f.spacing);
        if (count < 1)
            fail(s, f.line, field, value,
                 "the fracture family cannot fit: it gives no fracture in the block (" + block +
                     ", mean disc diameter about " +
                     shortestText(
                         std::sqrt(meanDiscArea(f.lengthExponent, f.minLength, f.maxLength) * 4 / 3.14159265358979)) +
                     " voxels): lower spacing or raise density");
        if (count > 1e6)
            fail(
                s, f.line, field, value,
                "gives " + shortestText(count) + " fractures, at most 10⁶ are allowed: raise spacing or lower density");
        const std::size_t index = std::size_t(&f - s.fractureFamilies.data());
        if (!fractureFamilyReachesBlock(s.fractureFamilies, index, dims, s.seed))
            fail(s, f.line, field, value,
                 "the fracture family cannot fit: none of its " + shortestText(count) + " discs drawn with seed " +
                     std::to_string(s.seed) + " reaches the block (" + block +
                     "): lower spacing or raise density, or shorten max_length");
    }
}

}  // namespace cavesim

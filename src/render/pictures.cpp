#include "render/pictures.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>

#include "core/check.h"
#include "core/vec3.h"
#include "render/colormap.h"
#include "render/png_io.h"
#include "render/view.h"
#include "sim/cave.h"

namespace cavesim::render {
namespace {

void checkWidth(int width) {
    CAVESIM_CHECK(width >= 64 && width <= 16384, "picture width must be in [64, 16384], got " + std::to_string(width));
}

bool isSection(const Domain& d) {
    return d.dims.ny == 1;
}

// A grid that is absent or of the wrong size reads as zeros.
template <typename T>
T valueAt(const Grid3<T>& g, const Dims& dims, int i, int j, int k, T fallback = T(0)) {
    if (g.dims.count() != dims.count() || g.data.size() != dims.count()) return fallback;
    return g.at(i, j, k);
}

// Voxel (i, j, k) of cell (u, v) of an orthographic view at position `w` along the view axis
// (plan: k, side_xz: j, side_yz: i).
Index3 voxelOf(View view, int u, int v, int w) {
    switch (view) {
        case View::kPlan:
            return {u, v, w};
        case View::kSideXZ:
            return {u, w, v};
        default:
            return {w, u, v};
    }
}
int depthCount(View view, const Dims& d) {
    return view == View::kPlan ? d.nz : (view == View::kSideXZ ? d.ny : d.nx);
}

// Per cell of an orthographic view, a reduction along the view axis.
struct CellField {
    int nu = 0, nv = 0;
    std::vector<float> value;
    float at(int u, int v) const { return value[std::size_t(v) * nu + u]; }
};

CellField project(const Frame& f, const std::function<float(const Index3&)>& voxel, bool useMax, int slice = -1) {
    const CellGrid g = cellGrid(f);
    CellField out{g.nu, g.nv, std::vector<float>(std::size_t(g.nu) * g.nv, 0.f)};
    const int nw = depthCount(f.view, f.dims);
    for (int v = 0; v < g.nv; ++v)
        for (int u = 0; u < g.nu; ++u) {
            float r = 0.f;
            if (slice >= 0)
                r = voxel(voxelOf(f.view, u, v, std::min(slice, nw - 1)));
            else {
                r = useMax ? -1e30f : 0.f;
                for (int w = 0; w < nw; ++w) {
                    const float x = voxel(voxelOf(f.view, u, v, w));
                    r = useMax ? std::max(r, x) : r + x;
                }
            }
            out.value[std::size_t(v) * g.nu + u] = r;
        }
    return out;
}

// The position along the view axis holding most cave voxels (the middle when there are none).
int busiestSlice(View view, const Dims& d, const Grid3<std::uint8_t>& mask) {
    const int nw = depthCount(view, d);
    std::vector<long> count(std::size_t(nw), 0);
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i)
                if (mask.at(i, j, k)) ++count[std::size_t(view == View::kPlan ? k : (view == View::kSideXZ ? j : i))];
    const auto best = std::max_element(count.begin(), count.end());
    return *best > 0 ? int(best - count.begin()) : nw / 2;
}

std::string sliceLabel(View view, int w, double h) {
    const char* axis = view == View::kPlan ? "z" : (view == View::kSideXZ ? "y" : "x");
    return std::string(view == View::kPlan ? "horizontal" : "vertical") + " slice at " + axis + " = " +
           formatMetres((w + 0.5) * h) + " m";
}

const Rgb kRockLight = mix(colours::kRock, colours::kWhite, 0.55);
const Rgb kOutlineDark{35, 35, 45};

// Outline of the cave voxels of the view: in the slice, or anywhere along the view axis.
void outlineCave(Image& img, const Frame& f, const Grid3<std::uint8_t>& mask, int slice, Rgb c, int thickness) {
    const int nw = depthCount(f.view, f.dims);
    outlineCells(
        img, f,
        [&](int u, int v) {
            if (slice >= 0) return mask.at(voxelOf(f.view, u, v, slice)) != 0;
            for (int w = 0; w < nw; ++w)
                if (mask.at(voxelOf(f.view, u, v, w))) return true;
            return false;
        },
        c, thickness);
}

void finishPanel(Image& img, const Frame& f, const Domain& d, const std::string& title, const std::string& subtitle) {
    drawBlockOutline(img, f);
    drawAxes(img, f);
    drawSourcesAndSinks(img, f, d.dims, d.sourceVoxels, d.sinkVoxels);
    drawTitle(img, f, title, subtitle);
}

// --- Zones -------------------------------------------------------------------------------------

Image zonesImage(const Domain& d, int width) {
    checkWidth(width);
    const View view = isSection(d) ? View::kSideXZ : View::kPlan;
    const int zones = int(d.sourceVoxels.size());
    // Footer: the standard row, then the zone legend wrapped over as many rows as needed.
    const Frame probe = makeFrame(view, d.dims, d.voxelSize, width, 1);
    const int ts = probe.textScale;
    const int entryWidth = textWidth("zone S00: p = 0000, 0000000 voxels", ts) + 6 * 6 * ts;
    const int perRow = std::max(1, probe.vw / std::max(1, entryWidth));
    const int zoneRows = zones > 0 ? (zones + perRow - 1) / perRow : 0;
    const Frame f = makeFrame(view, d.dims, d.voxelSize, width, 1 + zoneRows);
    Image img = makeCanvas(f);

    const Dims& dims = d.dims;
    const int nw = depthCount(view, dims);
    const CellGrid g = cellGrid(f);
    // Majority zone per cell (ties to the lower id), and whether a protochannel is in the column.
    std::vector<int> zoneOf(std::size_t(g.nu) * g.nv, -1);
    std::vector<char> proto(std::size_t(g.nu) * g.nv, 0);
    std::vector<long> voxelsPerZone(std::size_t(std::max(zones, 0)), 0);
    for (int v = 0; v < g.nv; ++v)
        for (int u = 0; u < g.nu; ++u) {
            std::map<int, int> count;
            for (int w = 0; w < nw; ++w) {
                const Index3 p = voxelOf(view, u, v, w);
                const int z = valueAt(d.zone, dims, p.i, p.j, p.k, -1);
                if (z >= 0) ++count[z];
                if (valueAt(d.flags, dims, p.i, p.j, p.k, std::uint8_t(0)) & kProtochannel)
                    proto[std::size_t(v) * g.nu + u] = 1;
            }
            int best = -1, bestCount = 0;
            for (const auto& [z, c] : count)
                if (c > bestCount) best = z, bestCount = c;
            zoneOf[std::size_t(v) * g.nu + u] = best;
        }
    if (d.zone.data.size() == dims.count())
        for (std::int32_t z : d.zone.data)
            if (z >= 0 && z < zones) ++voxelsPerZone[std::size_t(z)];

    fillCells(img, f, [&](int u, int v) {
        const std::size_t c = std::size_t(v) * g.nu + u;
        const int z = zoneOf[c];
        const Rgb base = z >= 0 ? mix(zoneColour(z), colours::kWhite, 0.45) : kRockLight;
        return proto[c] ? mix(z >= 0 ? zoneColour(z) : colours::kGrey, colours::kBlack, 0.55) : base;
    });
    // Zone borders.
    for (int z = 0; z < zones; ++z)
        outlineCells(
            img, f, [&](int u, int v) { return zoneOf[std::size_t(v) * g.nu + u] == z; }, Rgb{70, 70, 80},
            std::max(1, ts / 2));

    long protoVoxels = 0;
    for (std::uint8_t fl : d.flags.data) protoVoxels += (fl & kProtochannel) ? 1 : 0;
    const std::string sub = view == View::kPlan ? "plan: zone of most voxels per column; protochannels of all depths"
                                                : "vertical section: zones and protochannels";
    finishPanel(img, f, d, "Stage 1: pressure zones and protochannels", sub);
    drawStandardLegend(img, f,
                       {{LegendEntry::Kind::kSwatch, Rgb{60, 60, 70}, Marker::kCircle,
                         "protochannel (" + std::to_string(protoVoxels) + " voxels)"}});
    for (int z = 0; z < zones; ++z) {
        char text[120];
        const double p = std::size_t(z) < d.sourcePressure.size() ? d.sourcePressure[std::size_t(z)] : 0.0;
        std::snprintf(text, sizeof text, "zone S%d: p = %s, %ld voxels", z + 1, formatValue(p).c_str(),
                      voxelsPerZone[std::size_t(z)]);
        const int row = 1 + z / perRow, col = z % perRow;
        drawLegend(img, f, row, f.vx + col * entryWidth,
                   {{LegendEntry::Kind::kSwatch, mix(zoneColour(z), colours::kWhite, 0.45), Marker::kCircle, text}});
    }
    if (zones == 0 || std::all_of(zoneOf.begin(), zoneOf.end(), [](int z) { return z < 0; }))
        drawNote(img, f, "no zones");
    return img;
}

// --- Fields ------------------------------------------------------------------------------------

struct FieldStyle {
    std::string name;  // "pressure", "flow"
    std::function<Rgb(double)> ramp;
    bool logScale = false;
    double decades = 4.0;  // log scale: shown range below the maximum
};

// Colour of a value: rock colour where a logarithmic field is below its range.
Rgb fieldColour(const FieldStyle& s, double v, double lo, double hi) {
    if (s.logScale) {
        if (!(v >= lo)) return kRockLight;
        return s.ramp((std::log10(v) - std::log10(lo)) / std::max(1e-12, std::log10(hi) - std::log10(lo)));
    }
    return s.ramp((v - lo) / std::max(1e-30, hi - lo));
}

// One panel of a field: `slice` >= 0 draws that slice, -1 the maximum along the view axis.
Image fieldPanel(const Domain& d, const Grid3<std::uint8_t>& mask, const Grid3<float>& field, const FieldStyle& style,
                 View view, int slice, int width, const std::string& title, const std::string& subtitle, double lo,
                 double hi, bool empty) {
    const Frame f = makeFrame(view, d.dims, d.voxelSize, width, 2);
    Image img = makeCanvas(f);
    const CellField cells = project(
        f, [&](const Index3& p) { return valueAt(field, d.dims, p.i, p.j, p.k); }, true, slice);
    if (!empty) fillCells(img, f, [&](int u, int v) { return fieldColour(style, cells.at(u, v), lo, hi); });
    outlineCave(img, f, mask, slice, style.logScale ? kOutlineDark : colours::kWhite, std::max(1, f.textScale / 2 + 1));
    finishPanel(img, f, d, title, subtitle);
    drawStandardLegend(img, f,
                       {{LegendEntry::Kind::kLine, style.logScale ? kOutlineDark : Rgb{250, 250, 250}, Marker::kCircle,
                         "cave outline"}});
    drawColourBar(img, f, 1, style.ramp, lo, hi, style.logScale, style.name);
    if (empty) drawNote(img, f, "no stage-2 data");
    return img;
}

Image fieldImage(const Domain& d, const Grid3<std::uint8_t>& mask, const Grid3<float>& field, const FieldStyle& style,
                 int width, const std::string& title) {
    checkWidth(width);
    double maxValue = 0.0;
    if (field.data.size() == d.dims.count())
        for (float v : field.data)
            if (std::isfinite(v)) maxValue = std::max(maxValue, double(v));
    const bool empty = !(maxValue > 0.0);
    const double hi = empty ? 1.0 : maxValue;
    const double lo = style.logScale ? hi * std::pow(10.0, -style.decades) : 0.0;
    if (isSection(d))
        return fieldPanel(d, mask, field, style, View::kSideXZ, 0, width, title,
                          "vertical section (y = " + formatMetres(0.5 * d.voxelSize) + " m)", lo, hi, empty);
    if (style.logScale) {
        return stackVertically({fieldPanel(d, mask, field, style, View::kPlan, -1, width, title,
                                           "plan, largest value in each column", lo, hi, empty),
                                fieldPanel(d, mask, field, style, View::kSideXZ, -1, width, title + " (side x-z)",
                                           "largest value along y", lo, hi, empty)});
    }
    const int kz = busiestSlice(View::kPlan, d.dims, mask), jy = busiestSlice(View::kSideXZ, d.dims, mask);
    return stackVertically(
        {fieldPanel(d, mask, field, style, View::kPlan, kz, width, title,
                    sliceLabel(View::kPlan, kz, d.voxelSize) + " (most cave voxels)", lo, hi, empty),
         fieldPanel(d, mask, field, style, View::kSideXZ, jy, width, title + " (side x-z)",
                    sliceLabel(View::kSideXZ, jy, d.voxelSize) + " (most cave voxels)", lo, hi, empty)});
}

FieldStyle pressureStyle() {
    return {"pressure", viridis, false, 0.0};
}
FieldStyle flowStyle() {
    return {"flow (log)", inferno, true, 4.0};
}

Rgb porosityColour(double r) {
    return mix(Rgb{238, 235, 228}, Rgb{38, 36, 46}, std::clamp(r, 0.0, 1.0));
}

}  // namespace

// --- Public ------------------------------------------------------------------------------------

Image zonesPicture(const Domain& domain, int width) {
    return zonesImage(domain, width);
}

void writeZonesPicture(const Domain& domain, const std::string& path, int width) {
    writePng(path, zonesImage(domain, width));
}

Image pressurePicture(const Domain& domain, const Grid3<std::uint8_t>& mask, int width) {
    return fieldImage(domain, mask, domain.pressure, pressureStyle(), width, "Stage 2: pressure");
}

Image flowPicture(const Domain& domain, const Grid3<std::uint8_t>& mask, int width) {
    return fieldImage(domain, mask, domain.flow, flowStyle(), width, "Stage 2: flow");
}

void writeFieldPictures(const Domain& domain, const Grid3<std::uint8_t>& mask, const std::string& imagesDir,
                        int width) {
    writePng(imagesDir + "/pressure.png", pressurePicture(domain, mask, width));
    writePng(imagesDir + "/flow.png", flowPicture(domain, mask, width));
}

Image stateFrame(const Domain& d, const Grid3<std::uint8_t>& mask, const std::string& title, int width) {
    checkWidth(width);
    long cave = 0;
    for (std::uint8_t m : mask.data) cave += m;
    if (isSection(d)) {
        // Paper Figure 8: porosity with channels dark, then pressure and flow.
        const Frame f = makeFrame(View::kSideXZ, d.dims, d.voxelSize, width, 2);
        Image top = makeCanvas(f);
        fillCells(top, f, [&](int u, int v) { return porosityColour(valueAt(d.porosity, d.dims, u, 0, v)); });
        finishPanel(top, f, d, title, "porosity R (channels dark); " + std::to_string(cave) + " cave voxels");
        drawStandardLegend(top, f);
        drawColourBar(top, f, 1, porosityColour, 0.0, 1.0, false, "porosity R");
        double pmax = 0.0, fmax = 0.0;
        for (float v : d.pressure.data) pmax = std::max(pmax, double(v));
        for (float v : d.flow.data) fmax = std::max(fmax, double(v));
        const FieldStyle ps = pressureStyle(), fs = flowStyle();
        Image p = fieldPanel(d, mask, d.pressure, ps, View::kSideXZ, 0, width, title + ": pressure", "cave outlined",
                             0.0, pmax > 0 ? pmax : 1.0, !(pmax > 0));
        const double fhi = fmax > 0 ? fmax : 1.0;
        Image fl = fieldPanel(d, mask, d.flow, fs, View::kSideXZ, 0, width, title + ": flow", "cave outlined",
                              fhi * std::pow(10.0, -fs.decades), fhi, !(fmax > 0));
        return stackVertically({top, p, fl});
    }
    const Frame f = makeFrame(View::kPlan, d.dims, d.voxelSize, width, 2);
    Image img = makeCanvas(f);
    const Dims& dims = d.dims;
    fillCells(img, f, [&](int u, int v) {
        // Top of the cave in this column, else the largest porosity.
        for (int k = dims.nz - 1; k >= 0; --k)
            if (mask.at(u, v, k)) return depthRamp(double(dims.nz - 1 - k) / std::max(1, dims.nz - 1));
        double r = 0.0;
        for (int k = 0; k < dims.nz; ++k) r = std::max(r, double(valueAt(d.porosity, dims, u, v, k)));
        return porosityColour(0.8 * r);
    });
    outlineCave(img, f, mask, -1, kOutlineDark, std::max(1, f.textScale / 2));
    finishPanel(img, f, d, title,
                "plan: cave coloured by the depth of its top; elsewhere largest porosity; " + std::to_string(cave) +
                    " cave voxels");
    drawStandardLegend(img, f);
    drawColourBar(img, f, 1, depthRamp, 0.0, f.blockMax[2], false, "depth of cave top (m)");
    return img;
}

Image stackVertically(const std::vector<Image>& images) {
    int w = 0, h = 0;
    for (const Image& i : images) w = std::max(w, i.width), h += i.height;
    Image out(std::max(w, 1), std::max(h, 1), colours::kWhite);
    int y = 0;
    for (const Image& i : images) {
        blit(out, i, (w - i.width) / 2, y);
        y += i.height;
    }
    return out;
}

Image composeStrip(const std::vector<Image>& frames, int rows) {
    CAVESIM_CHECK(!frames.empty(), "composeStrip: no frames");
    CAVESIM_CHECK(rows >= 1, "composeStrip: rows must be at least 1, got " + std::to_string(rows));
    int cw = 0, ch = 0;
    for (const Image& f : frames) {
        CAVESIM_CHECK(f.width > 0 && f.height > 0, "composeStrip: an empty frame (" + std::to_string(f.width) + "×" +
                                                       std::to_string(f.height) + ")");
        cw = std::max(cw, f.width), ch = std::max(ch, f.height);
    }
    rows = std::min<int>(rows, int(frames.size()));
    const int cols = (int(frames.size()) + rows - 1) / rows;
    const int gap = std::max(4, cw / 128);
    Image out(cols * cw + (cols - 1) * gap, rows * ch + (rows - 1) * gap, colours::kWhite);
    // Thin grey separators between cells.
    for (int c = 1; c < cols; ++c) fillRect(out, c * (cw + gap) - gap / 2 - 1, 0, 1, out.height, colours::kLightGrey);
    for (int r = 1; r < rows; ++r) fillRect(out, 0, r * (ch + gap) - gap / 2 - 1, out.width, 1, colours::kLightGrey);
    for (std::size_t n = 0; n < frames.size(); ++n) {
        const int r = int(n) / cols, c = int(n) % cols;
        blit(out, frames[n], c * (cw + gap), r * (ch + gap));
    }
    return out;
}

}  // namespace cavesim::render

namespace cavesim::render {

Image fracturesPicture(const Domain& d, const Grid3<std::uint8_t>& mask, const FractureNetwork& net, int width) {
    checkWidth(width);
    const int families = int(net.families.size());
    const Frame f = makeFrame(View::kPlan, d.dims, d.voxelSize, width, 1 + families);
    Image img = makeCanvas(f);
    const Rgb caveShadow{95, 95, 105};
    fillCells(img, f, [&](int u, int v) {
        for (int k = 0; k < d.dims.nz; ++k)
            if (mask.at(u, v, k)) return caveShadow;
        return kRockLight;
    });
    const double h = d.voxelSize;
    // Each disc's outline, projected (36 sides), and the area it covers in the picture.
    constexpr int kSides = 36;
    std::array<double, kSides> cosA{}, sinA{};  // the outline's angles, once for every disc
    for (int s = 0; s < kSides; ++s) {
        const double a = 2.0 * kPi * s / kSides;
        cosA[std::size_t(s)] = std::cos(a);
        sinA[std::size_t(s)] = std::sin(a);
    }
    const auto rimOf = [&](const FractureDisc& disc) {
        // Two unit vectors in the disc's plane.
        const Vec3d& n = disc.normal;
        Vec3d e1 = std::abs(n[2]) < 0.9 ? Vec3d{-n[1], n[0], 0.0} : Vec3d{0.0, -n[2], n[1]};
        const double l1 = norm(e1);
        for (double& c : e1) c /= l1;
        const Vec3d e2 = cross(n, e1);
        std::vector<std::pair<double, double>> rim;
        for (int s = 0; s < kSides; ++s) {
            const double c = cosA[std::size_t(s)], sn = sinA[std::size_t(s)];
            Vec3d p{};
            for (int ax = 0; ax < 3; ++ax) p[ax] = (disc.centre[ax] + 0.5 + disc.radius * (c * e1[ax] + sn * e2[ax])) * h;
            const Camera::Projected q = f.camera.project(p);
            rim.emplace_back(q.x, q.y);
        }
        return rim;
    };
    // The discs are blended at 12 % each, so a few dozen layers saturate a pixel: past a budget of
    // 64 layers over the whole view (polygon area within the view, plus outline) a family is drawn
    // as an evenly spaced subset — every stride-th of its discs, a stride per family so that a
    // sparse family beside a dense one keeps all its discs — and the picture costs about the same
    // for a million discs as for a few thousand, and says how many it shows.
    const double view = double(f.vw) * double(f.vh);
    const std::size_t nf = std::size_t(std::max(families, 1));
    std::vector<double> covered(nf, 0.0);
    const auto familyOf = [&](const FractureDisc& disc) {
        return std::min(nf - 1, std::size_t(std::max(disc.family, 0)));
    };
    for (const FractureDisc& disc : net.discs) {
        const auto rim = rimOf(disc);
        double twice = 0, outline = 0;
        for (int s = 0; s < kSides; ++s) {
            const auto& a = rim[std::size_t(s)];
            const auto& b = rim[std::size_t((s + 1) % kSides)];
            twice += a.first * b.second - b.first * a.second;
            outline += std::hypot(b.first - a.first, b.second - a.second);
        }
        covered[familyOf(disc)] += std::min(0.5 * std::abs(twice), view) + outline;
    }
    const double budget = 64.0 * view;
    std::vector<std::size_t> stride(nf, 1), index(nf, 0);
    for (std::size_t fam = 0; fam < nf; ++fam)
        if (covered[fam] > budget) stride[fam] = std::size_t(std::ceil(covered[fam] / budget));
    long drawn = 0;
    for (const FractureDisc& disc : net.discs) {
        const std::size_t fam = familyOf(disc);
        if (index[fam]++ % stride[fam] != 0) continue;
        const auto rim = rimOf(disc);
        const Rgb c = zoneColour(disc.family);
        fillPolygon(img, rim, c, 0.12);
        for (int s = 0; s < kSides; ++s) {
            const auto& a = rim[std::size_t(s)];
            const auto& b = rim[std::size_t((s + 1) % kSides)];
            drawLine(img, a.first, a.second, b.first, b.second, mix(c, colours::kBlack, 0.25));
        }
        ++drawn;
    }
    // The block's outside stays clean: repaint the margins the discs spilled into.
    const Rgb white = colours::kWhite;
    fillRect(img, 0, 0, img.width, f.vy, white);
    fillRect(img, 0, f.vy + f.vh, img.width, f.footerY - (f.vy + f.vh), white);
    fillRect(img, 0, f.vy, f.vx, f.vh, white);
    fillRect(img, f.vx + f.vw, f.vy, img.width - (f.vx + f.vw), f.vh, white);
    fillRect(img, 0, f.footerY, img.width, img.height - f.footerY, white);
    const long discs = long(net.discs.size());
    finishPanel(img, f, d,
                "Fracture network (" + std::to_string(discs) + " discs" +
                    (drawn < discs ? ", " + std::to_string(drawn) + " drawn" : "") + ")",
                "plan: disc outlines projected, coloured by family; cave shadow in grey");
    drawStandardLegend(img, f, {{LegendEntry::Kind::kSwatch, caveShadow, Marker::kCircle, "cave (plan shadow)"}});
    for (int fam = 0; fam < families; ++fam) {
        const FractureFamilyStats& st = net.families[std::size_t(fam)];
        drawLegend(img, f, 1 + fam, f.vx,
                   {{LegendEntry::Kind::kSwatch, zoneColour(fam), Marker::kCircle, fractureFamilyLabel(fam, st)}});
    }
    return img;
}

std::string fractureFamilyLabel(int family, const FractureFamilyStats& st) {
    char text[160];
    std::string orientation = "n/a";  // no mean of no disc
    if (st.count > 0) {
        std::snprintf(text, sizeof text, "%03.0f/%02.0f", st.meanDipDirection, st.meanDip);
        orientation = text;
    }
    std::string kappa = "n/a";  // no concentration estimate from fewer than 2 discs
    if (st.count > 1) {
        std::snprintf(text, sizeof text, "%.0f", st.kappaEstimate);
        kappa = text;
    }
    std::snprintf(text, sizeof text, "family %d: %ld discs, measured dip direction/dip %s, kappa %s", family + 1,
                  st.count, orientation.c_str(), kappa.c_str());
    return text;
}

void writeFracturesPicture(const Domain& d, const Grid3<std::uint8_t>& mask, const FractureNetwork& net,
                           const std::string& path, int width) {
    writePng(path, fracturesPicture(d, mask, net, width));
}

}  // namespace cavesim::render

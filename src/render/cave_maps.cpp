#include "render/cave_maps.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>

#include <cairo-svg.h>
#include <cairo.h>

#include "core/atomic_file.h"
#include "core/check.h"
#include "core/error.h"
#include "render/colormap.h"
#include "render/view.h"

namespace cavesim::render {
namespace {

constexpr const char* kFamily = "DejaVu Sans";

double horizontal(const Vec3d& a, const Vec3d& b) {
    return std::hypot(b[0] - a[0], b[1] - a[1]);
}

// ---- layout of one drawing ----------------------------------------------------------------------

/// A passage as drawn: 2D points (u right, v up, metres), elevation and radius per station.
struct DrawnPassage {
    std::vector<double> u, v, z, r;
    std::vector<int> station;
};

struct Layout {
    MapKind kind = MapKind::kPlan;
    double eu = 1, ev = 1;  ///< world extent along u and v, metres
    std::vector<DrawnPassage> passages;
    std::vector<std::pair<double, double>> sources, sinks;  ///< (u, v) metres
    std::string uName, vName, heading, subtitle;
};

/// (u, v) of a world point in a plan or section.
std::pair<double, double> project(MapKind kind, const Vec3d& p) {
    return kind == MapKind::kPlan ? std::make_pair(p[0], p[1]) : std::make_pair(p[0], p[2]);
}

int nearestStation(const CaveMapInput& in, const Vec3d& p, const std::vector<char>* allowed = nullptr) {
    int best = -1;
    double bd = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < in.stations.size(); ++i) {
        if (allowed && !(*allowed)[i]) continue;
        const Vec3d& q = in.stations[i].position;
        const double d = std::hypot(q[0] - p[0], std::hypot(q[1] - p[1], q[2] - p[2]));
        if (d < bd) bd = d, best = int(i);
    }
    return best;
}

Layout makeLayout(const CaveMapInput& in, MapKind kind) {
    Layout L;
    L.kind = kind;
    const Vec3d& m = in.blockMax;
    if (kind == MapKind::kExtendedElevation) {
        double extent = 0;
        const auto xs = extendedElevationLayout(in, &extent);
        L.eu = std::max(extent, m[2] * 0.5);
        L.ev = m[2];
        for (std::size_t p = 0; p < in.passages.size(); ++p) {
            DrawnPassage d;
            for (std::size_t s = 0; s < in.passages[p].size(); ++s) {
                const MapStation& st = in.stations[std::size_t(in.passages[p][s])];
                d.u.push_back(xs[p][s]), d.v.push_back(st.position[2]), d.z.push_back(st.position[2]);
                d.r.push_back(st.radius), d.station.push_back(in.passages[p][s]);
            }
            L.passages.push_back(std::move(d));
        }
        // Sources and sinks at the first place their nearest station is drawn.
        auto place = [&](const Vec3d& p, std::vector<std::pair<double, double>>& out) {
            const int n = nearestStation(in, p);
            for (const DrawnPassage& d : L.passages)
                for (std::size_t s = 0; s < d.station.size(); ++s)
                    if (d.station[s] == n) {
                        out.push_back({d.u[s], d.v[s]});
                        return;
                    }
        };
        for (const Vec3d& p : in.sources) place(p, L.sources);
        for (const Vec3d& p : in.sinks) place(p, L.sinks);
        L.uName = "distance along the passages (m)";
        L.vName = "elevation (m)";
        L.heading = "Extended elevation";
        L.subtitle = "passages unrolled from the entrance, laid end to end; true scale";
        return L;
    }
    L.eu = m[0];
    L.ev = kind == MapKind::kPlan ? m[1] : m[2];
    for (const auto& passage : in.passages) {
        DrawnPassage d;
        for (int id : passage) {
            const MapStation& st = in.stations[std::size_t(id)];
            const auto [u, v] = project(kind, st.position);
            d.u.push_back(u), d.v.push_back(v), d.z.push_back(st.position[2]), d.r.push_back(st.radius);
            d.station.push_back(id);
        }
        L.passages.push_back(std::move(d));
    }
    for (const Vec3d& p : in.sources) L.sources.push_back(project(kind, p));
    for (const Vec3d& p : in.sinks) L.sinks.push_back(project(kind, p));
    L.uName = "x (m), east";
    L.vName = kind == MapKind::kPlan ? "y (m), north" : "z (m), elevation";
    L.heading = kind == MapKind::kPlan ? "Plan" : "Section";
    L.subtitle = kind == MapKind::kPlan ? "seen from above, north up; true scale" : "the 2D section, x–z; true scale";
    return L;
}

// ---- drawing ------------------------------------------------------------------------------------

struct Rect {
    double x0, y0, x1, y1;
    bool overlaps(const Rect& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
};

void setColour(cairo_t* cr, Rgb c, double alpha = 1.0) {
    cairo_set_source_rgba(cr, c.r / 255.0, c.g / 255.0, c.b / 255.0, alpha);
}

void setFont(cairo_t* cr, double px, bool bold = false) {
    cairo_select_font_face(cr, kFamily, CAIRO_FONT_SLANT_NORMAL,
                           bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, px);
}

double textAdvance(cairo_t* cr, const std::string& t) {
    cairo_text_extents_t e;
    cairo_text_extents(cr, t.c_str(), &e);
    return e.x_advance;
}

/// Text with its baseline at y, anchored at x by `align` (0 left, 0.5 centre, 1 right), with an
/// optional white halo.
void text(cairo_t* cr, double x, double y, const std::string& t, Rgb c, double align = 0.0, bool halo = false) {
    x -= align * textAdvance(cr, t);
    if (halo) {
        cairo_move_to(cr, x, y);
        cairo_text_path(cr, t.c_str());
        setColour(cr, colours::kWhite);
        cairo_set_line_width(cr, 3.0);
        cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
        cairo_stroke(cr);
    }
    cairo_move_to(cr, x, y);
    setColour(cr, c);
    cairo_show_text(cr, t.c_str());
}

struct Page {
    int width = 0, height = 0;
    double fs = 12;  ///< base font size, px
    double left = 0, top = 0, vw = 0, vh = 0, scale = 1;
    double X(double u) const { return left + u * scale; }
    double Y(double v) const { return top + vh - v * scale; }
};

Page makePage(const Layout& L, int width) {
    Page p;
    p.width = width;
    p.fs = std::max(11.0, width / 80.0);
    p.left = 5.5 * p.fs;
    const double right = 3.0 * p.fs;
    p.top = 5.8 * p.fs;
    const double bottom = 9.5 * p.fs;
    const double availW = std::max(16.0, width - p.left - right);
    p.scale = availW / L.eu;
    if (L.ev * p.scale > 1.25 * width) p.scale = 1.25 * width / L.ev;
    p.vw = L.eu * p.scale;
    p.vh = L.ev * p.scale;
    p.left += (availW - p.vw) / 2;
    p.height = int(std::ceil(p.top + p.vh + bottom));
    return p;
}

void drawAxes(cairo_t* cr, const Page& pg, const Layout& L) {
    const double fs = pg.fs;
    setFont(cr, 0.9 * fs);
    cairo_set_line_width(cr, 1.0);
    auto step = [&](double extent, double pixelsPerMetre, double labelPx) {
        double s = niceNumber(std::max(extent, 1e-9) / 6.0);
        for (int g = 0; g < 60 && s * pixelsPerMetre < labelPx; ++g) s = niceNumber(s * 2.01);
        return s;
    };
    const Rgb ink = colours::kText;
    const double su = step(L.eu, pg.scale, textAdvance(cr, formatMetres(L.eu) + "000"));
    for (double t = 0; t <= L.eu * (1 + 1e-9); t += su) {
        const double x = pg.X(t), y = pg.Y(0);
        setColour(cr, ink);
        cairo_move_to(cr, x, y), cairo_line_to(cr, x, y + 0.5 * fs), cairo_stroke(cr);
        text(cr, x, y + 1.5 * fs, formatMetres(t), ink, 0.5);
    }
    text(cr, pg.X(L.eu / 2), pg.Y(0) + 2.9 * fs, L.uName, ink, 0.5);
    const double sv = step(L.ev, pg.scale, 2.0 * fs);
    for (double t = 0; t <= L.ev * (1 + 1e-9); t += sv) {
        const double x = pg.X(0), y = pg.Y(t);
        setColour(cr, ink);
        cairo_move_to(cr, x, y), cairo_line_to(cr, x - 0.5 * fs, y), cairo_stroke(cr);
        text(cr, x - 0.8 * fs, y + 0.35 * fs, formatMetres(t), ink, 1.0);
    }
    text(cr, pg.X(0) - 0.8 * fs, pg.top - 0.7 * fs, L.vName, ink, 0.0);
}

void drawPassages(cairo_t* cr, const Page& pg, const Layout& L, double zMax) {
    struct Segment {
        double x0, y0, x1, y1, width, z;
    };
    std::vector<Segment> segs;
    for (const DrawnPassage& d : L.passages)
        for (std::size_t s = 0; s + 1 < d.u.size(); ++s)
            segs.push_back({pg.X(d.u[s]), pg.Y(d.v[s]), pg.X(d.u[s + 1]), pg.Y(d.v[s + 1]),
                            std::max(2.0, (d.r[s] + d.r[s + 1]) * pg.scale), 0.5 * (d.z[s] + d.z[s + 1])});
    // Lowest first, so that upper passages cover lower ones in the plan (ties keep their order).
    std::stable_sort(segs.begin(), segs.end(), [](const Segment& a, const Segment& b) { return a.z < b.z; });
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    for (const Segment& s : segs) {  // walls: a dark rim around every passage
        setColour(cr, Rgb{45, 40, 45});
        cairo_set_line_width(cr, s.width + 2.0);
        cairo_move_to(cr, s.x0, s.y0), cairo_line_to(cr, s.x1, s.y1), cairo_stroke(cr);
    }
    for (const Segment& s : segs) {
        setColour(cr, viridis(s.z / std::max(zMax, 1e-12)));
        cairo_set_line_width(cr, s.width);
        cairo_move_to(cr, s.x0, s.y0), cairo_line_to(cr, s.x1, s.y1), cairo_stroke(cr);
    }
    // Centrelines and stations.
    cairo_set_line_width(cr, 1.0);
    for (const DrawnPassage& d : L.passages) {
        setColour(cr, Rgb{20, 20, 25}, 0.8);
        for (std::size_t s = 0; s < d.u.size(); ++s)
            s == 0 ? cairo_move_to(cr, pg.X(d.u[s]), pg.Y(d.v[s])) : cairo_line_to(cr, pg.X(d.u[s]), pg.Y(d.v[s]));
        cairo_stroke(cr);
        for (std::size_t s = 0; s < d.u.size(); ++s) {
            cairo_arc(cr, pg.X(d.u[s]), pg.Y(d.v[s]), 1.4, 0, 2 * M_PI);
            cairo_fill(cr);
        }
    }
}

void drawStationLabels(cairo_t* cr, const Page& pg, const Layout& L, const CaveMapInput& in, std::vector<Rect>& taken) {
    setFont(cr, 0.8 * pg.fs);
    std::vector<char> done(in.stations.size(), 0);
    std::vector<std::pair<int, double>> placed;  // (station, x) already named, extended elevation
    const double h = 0.8 * pg.fs;
    for (const DrawnPassage& d : L.passages) {
        for (std::size_t s : {std::size_t(0), d.u.size() - 1}) {
            const int id = d.station[s];
            const std::string& name = in.stations[std::size_t(id)].name;
            // Plans and sections name each junction once; the extended elevation names every place
            // a station is drawn (that is how its passages are tied together).
            if (name.empty() || (L.kind != MapKind::kExtendedElevation && done[std::size_t(id)])) continue;
            done[std::size_t(id)] = 1;
            const double x = pg.X(d.u[s]), y = pg.Y(d.v[s]);
            if (std::any_of(placed.begin(), placed.end(),
                            [&](const auto& q) { return q.first == id && std::abs(q.second - x) < 1.0; }))
                continue;  // a passage continuing the one before: the junction is named once
            placed.push_back({id, x});
            const double w = textAdvance(cr, name);
            const double off = 0.35 * pg.fs + 0.5 * d.r[s] * pg.scale;
            const Rect tries[4] = {{x + off, y - off - h, x + off + w, y - off},
                                   {x + off, y + off, x + off + w, y + off + h},
                                   {x - off - w, y - off - h, x - off, y - off},
                                   {x - off - w, y + off, x - off, y + off + h}};
            for (const Rect& r : tries) {
                if (r.x0 < 0 || r.x1 > pg.width || r.y0 < 0 || r.y1 > pg.height) continue;
                if (std::any_of(taken.begin(), taken.end(), [&](const Rect& t) { return t.overlaps(r); })) continue;
                taken.push_back(r);
                text(cr, r.x0, r.y1 - 0.15 * h, name, Rgb{30, 30, 36}, 0.0, true);
                break;
            }
        }
    }
}

void drawTerminals(cairo_t* cr, const Page& pg, const Layout& L, std::vector<Rect>& taken) {
    const double r = 0.45 * pg.fs;
    setFont(cr, 0.9 * pg.fs, true);
    auto label = [&](double x, double y, const std::string& t, Rgb c) {
        const double w = textAdvance(cr, t);
        const Rect rect{x + r + 2, y - r - pg.fs, x + r + 2 + w, y - r};
        taken.push_back(rect);
        text(cr, rect.x0, rect.y1, t, c, 0.0, true);
    };
    for (std::size_t i = 0; i < L.sinks.size(); ++i) {
        const double x = pg.X(L.sinks[i].first), y = pg.Y(L.sinks[i].second);
        cairo_rectangle(cr, x - r - 1, y - r - 1, 2 * r + 2, 2 * r + 2), setColour(cr, colours::kWhite), cairo_fill(cr);
        cairo_rectangle(cr, x - r, y - r, 2 * r, 2 * r), setColour(cr, colours::kSink), cairo_fill(cr);
        label(x, y, L.sinks.size() == 1 ? std::string("sink") : "sink " + std::to_string(i + 1), colours::kSink);
    }
    for (std::size_t i = 0; i < L.sources.size(); ++i) {
        const double x = pg.X(L.sources[i].first), y = pg.Y(L.sources[i].second);
        cairo_arc(cr, x, y, r + 1, 0, 2 * M_PI), setColour(cr, colours::kWhite), cairo_fill(cr);
        cairo_arc(cr, x, y, r, 0, 2 * M_PI), setColour(cr, colours::kSource), cairo_fill(cr);
        label(x, y, "S" + std::to_string(i + 1), colours::kSource);
    }
}

void drawNorthArrow(cairo_t* cr, const Page& pg) {
    const double fs = pg.fs;
    const double x = pg.left + pg.vw - 1.2 * fs, yTip = pg.top - 3.9 * fs, yBase = pg.top - 1.3 * fs;
    cairo_move_to(cr, x, yTip);
    cairo_line_to(cr, x + 0.7 * fs, yBase);
    cairo_line_to(cr, x, yBase - 0.6 * fs);
    cairo_close_path(cr);
    setColour(cr, colours::kText);
    cairo_fill(cr);
    cairo_move_to(cr, x, yTip);
    cairo_line_to(cr, x - 0.7 * fs, yBase);
    cairo_line_to(cr, x, yBase - 0.6 * fs);
    cairo_close_path(cr);
    cairo_set_line_width(cr, 1.0);
    cairo_stroke(cr);
    setFont(cr, fs, true);
    text(cr, x - 1.0 * fs, yBase - 0.4 * fs, "N", colours::kText, 1.0);
}

/// Scale bar at (x, y) (top-left); returns the x after its label.
double drawScaleBar(cairo_t* cr, const Page& pg, double extent, double x, double y) {
    double length = niceNumber(extent / 5.0);
    while (length * pg.scale > 0.3 * pg.width && length > 1e-9) length = niceNumber(length / 2.01);
    const double w = length * pg.scale, h = 0.45 * pg.fs;
    for (int s = 0; s < 4; ++s) {
        cairo_rectangle(cr, x + s * w / 4, y, w / 4, h);
        setColour(cr, s % 2 ? colours::kWhite : colours::kText);
        cairo_fill(cr);
    }
    cairo_rectangle(cr, x, y, w, h);
    setColour(cr, colours::kText);
    cairo_set_line_width(cr, 1.0);
    cairo_stroke(cr);
    setFont(cr, 0.9 * pg.fs);
    for (int s : {0, 2, 4})
        text(cr, x + s * w / 4, y + h + 1.1 * pg.fs, formatMetres(length * s / 4), colours::kText, 0.5);
    text(cr, x + w + 0.6 * pg.fs, y + h, "m", colours::kText);
    return x + w + 2.5 * pg.fs;
}

void drawColourBar(cairo_t* cr, const Page& pg, double zMax, double x0, double y) {
    const double x1 = pg.left + pg.vw;
    setFont(cr, 0.9 * pg.fs);
    const std::string label = "elevation (m)";
    text(cr, x0, y + 0.55 * pg.fs, label, colours::kText);
    x0 += textAdvance(cr, label) + 0.8 * pg.fs;
    if (x1 - x0 < 4 * pg.fs) return;
    const double h = 0.7 * pg.fs;
    const int n = 64;
    for (int i = 0; i < n; ++i) {
        cairo_rectangle(cr, x0 + (x1 - x0) * i / n, y, (x1 - x0) / n + 0.5, h);
        setColour(cr, viridis((i + 0.5) / n));
        cairo_fill(cr);
    }
    cairo_rectangle(cr, x0, y, x1 - x0, h);
    setColour(cr, Rgb{90, 90, 90});
    cairo_set_line_width(cr, 1.0);
    cairo_stroke(cr);
    const double step = niceNumber(zMax / 4.0);
    for (double v = 0; v <= zMax * (1 + 1e-9); v += step)
        text(cr, x0 + (x1 - x0) * v / zMax, y + h + 1.1 * pg.fs, formatMetres(v), colours::kText, 0.5);
}

void drawMap(cairo_t* cr, const Page& pg, const Layout& L, const CaveMapInput& in) {
    const double fs = pg.fs;
    setColour(cr, colours::kWhite);
    cairo_paint(cr);
    // The rock (plan, section) or the block's elevation band (extended elevation).
    cairo_rectangle(cr, pg.left, pg.top, pg.vw, pg.vh);
    setColour(cr, mix(colours::kRock, colours::kWhite, 0.6));
    cairo_fill(cr);
    cairo_rectangle(cr, pg.left, pg.top, pg.vw, pg.vh);
    setColour(cr, Rgb{60, 60, 66});
    cairo_set_line_width(cr, 1.5);
    cairo_stroke(cr);
    drawAxes(cr, pg, L);
    const double zMax = std::max(in.blockMax[2], 1e-9);
    drawPassages(cr, pg, L, zMax);
    std::vector<Rect> taken;
    drawTerminals(cr, pg, L, taken);
    drawStationLabels(cr, pg, L, in, taken);
    if (L.passages.empty()) {
        setFont(cr, 1.2 * fs);
        text(cr, pg.left + pg.vw / 2, pg.top + pg.vh / 2, "no passages", colours::kText, 0.5, true);
    }
    // Title.
    setFont(cr, 1.5 * fs, true);
    text(cr, pg.left, 1.8 * fs, L.heading + (in.title.empty() ? std::string() : " of " + in.title), colours::kText);
    setFont(cr, 0.95 * fs);
    text(cr, pg.left, 3.2 * fs,
         L.subtitle + "; passages as wide as the cave, coloured by elevation; stations p<passage>.<n>",
         Rgb{90, 90, 96});
    if (L.kind == MapKind::kPlan) drawNorthArrow(cr, pg);
    // Footer: scale bar, then the colour bar.
    const double yFoot = pg.top + pg.vh + 4.6 * fs;
    const double x = drawScaleBar(cr, pg, L.eu, pg.left, yFoot);
    drawColourBar(cr, pg, zMax, x, yFoot);
}

cairo_status_t appendToString(void* closure, const unsigned char* data, unsigned int length) {
    static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
    return CAIRO_STATUS_SUCCESS;
}

/// Cairo names SVG groups "surface<N>" from a process-wide counter of every surface created (the
/// text of other pictures, on any thread, included): renumbered here in order of appearance, so
/// the same map gives the same bytes whatever ran before it.
std::string renumberSurfaceIds(const std::string& svg) {
    const std::string key = "surface";
    std::vector<std::pair<std::string, std::string>> seen;
    std::string out;
    out.reserve(svg.size());
    std::size_t i = 0;
    while (i < svg.size()) {
        const std::size_t at = svg.find(key, i);
        if (at == std::string::npos) {
            out.append(svg, i, std::string::npos);
            break;
        }
        std::size_t end = at + key.size();
        while (end < svg.size() && svg[end] >= '0' && svg[end] <= '9') ++end;
        out.append(svg, i, at - i);
        if (end == at + key.size()) {
            out += key;
        } else {
            const std::string number = svg.substr(at + key.size(), end - at - key.size());
            auto it = std::find_if(seen.begin(), seen.end(), [&](const auto& p) { return p.first == number; });
            if (it == seen.end()) {
                seen.push_back({number, std::to_string(seen.size() + 1)});
                it = seen.end() - 1;
            }
            out += key + it->second;
        }
        i = end;
    }
    return out;
}

}  // namespace

std::string mapStem(MapKind kind) {
    switch (kind) {
        case MapKind::kPlan:
            return "map_plan";
        case MapKind::kExtendedElevation:
            return "map_extended_elevation";
        case MapKind::kSection:
            return "map_section";
    }
    return "map";
}

std::vector<std::vector<double>> extendedElevationLayout(const CaveMapInput& in, double* extent) {
    const std::size_t nStations = in.stations.size();
    std::vector<std::vector<std::pair<int, bool>>> atNode(nStations);  // (passage, starts here)
    double total = 0;
    for (std::size_t p = 0; p < in.passages.size(); ++p) {
        const auto& ids = in.passages[p];
        CAVESIM_CHECK(ids.size() >= 2, "a map passage needs at least 2 stations");
        for (int id : ids) CAVESIM_CHECK(id >= 0 && std::size_t(id) < nStations, "map station index out of range");
        atNode[std::size_t(ids.front())].push_back({int(p), true});
        if (ids.back() != ids.front()) atNode[std::size_t(ids.back())].push_back({int(p), false});
        for (std::size_t s = 0; s + 1 < ids.size(); ++s)
            total +=
                horizontal(in.stations[std::size_t(ids[s])].position, in.stations[std::size_t(ids[s + 1])].position);
    }
    const double gap = std::max(1e-9, 0.03 * total);
    std::vector<std::vector<double>> xs(in.passages.size());
    std::vector<char> done(in.passages.size(), 0);
    double cursor = 0;
    int lastEnd = -1;
    bool first = true;
    // Depth first from a node: each passage leaving it in turn, then what leaves its far end.
    std::function<void(int)> visit = [&](int node) {
        for (const auto& [p, forward] : atNode[std::size_t(node)]) {
            if (done[std::size_t(p)]) continue;
            done[std::size_t(p)] = 1;
            std::vector<int> ids = in.passages[std::size_t(p)];
            if (!forward) std::reverse(ids.begin(), ids.end());
            if (!first && node != lastEnd) cursor += gap;
            first = false;
            std::vector<double> x{cursor};
            for (std::size_t s = 0; s + 1 < ids.size(); ++s)
                x.push_back(x.back() + horizontal(in.stations[std::size_t(ids[s])].position,
                                                  in.stations[std::size_t(ids[s + 1])].position));
            cursor = x.back();
            lastEnd = ids.back();
            if (!forward) std::reverse(x.begin(), x.end());
            xs[std::size_t(p)] = std::move(x);
            visit(forward ? in.passages[std::size_t(p)].back() : in.passages[std::size_t(p)].front());
        }
    };
    // The entrance: the passage end nearest the first source (else the highest passage end).
    std::vector<char> isEnd(nStations, 0);
    for (const auto& ids : in.passages) isEnd[std::size_t(ids.front())] = isEnd[std::size_t(ids.back())] = 1;
    int root = -1;
    if (!in.sources.empty()) root = nearestStation(in, in.sources.front(), &isEnd);
    if (root < 0)
        for (std::size_t i = 0; i < nStations; ++i)
            if (isEnd[i] && (root < 0 || in.stations[i].position[2] > in.stations[std::size_t(root)].position[2]))
                root = int(i);
    if (root >= 0) visit(root);
    for (std::size_t p = 0; p < in.passages.size(); ++p)  // other parts of the cave, in passage order
        if (!done[p]) visit(in.passages[p].front());
    if (extent) *extent = cursor;
    return xs;
}

MapDrawing drawCaveMap(const CaveMapInput& in, MapKind kind, int width) {
    CAVESIM_CHECK(width >= 256 && width <= 16384, "map width must be in [256, 16384], got " + std::to_string(width));
    const Layout L = makeLayout(in, kind);
    const Page pg = makePage(L, width);
    MapDrawing out;
    {
        std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> s(
            cairo_image_surface_create(CAIRO_FORMAT_RGB24, pg.width, pg.height), cairo_surface_destroy);
        std::unique_ptr<cairo_t, decltype(&cairo_destroy)> cr(cairo_create(s.get()), cairo_destroy);
        drawMap(cr.get(), pg, L, in);
        cairo_surface_flush(s.get());
        if (cairo_status(cr.get()) != CAIRO_STATUS_SUCCESS ||
            cairo_surface_write_to_png_stream(s.get(), appendToString, &out.png) != CAIRO_STATUS_SUCCESS)
            throw RuntimeError("cannot draw the " + mapStem(kind) +
                               " map: " + cairo_status_to_string(cairo_status(cr.get())));
    }
    {
        std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> s(
            cairo_svg_surface_create_for_stream(appendToString, &out.svg, pg.width, pg.height), cairo_surface_destroy);
        cairo_svg_surface_set_document_unit(s.get(), CAIRO_SVG_UNIT_PX);
        std::unique_ptr<cairo_t, decltype(&cairo_destroy)> cr(cairo_create(s.get()), cairo_destroy);
        drawMap(cr.get(), pg, L, in);
        const cairo_status_t st = cairo_status(cr.get());
        cr.reset();
        cairo_surface_finish(s.get());
        if (st != CAIRO_STATUS_SUCCESS || cairo_surface_status(s.get()) != CAIRO_STATUS_SUCCESS)
            throw RuntimeError("cannot draw the " + mapStem(kind) + " map as SVG");
        out.svg = renumberSurfaceIds(out.svg);
    }
    return out;
}

std::vector<std::string> writeCaveMaps(const CaveMapInput& input, bool section, const std::string& dir, int width) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::create_directories(dir, ec);
    std::vector<std::string> written;
    for (MapKind kind : {section ? MapKind::kSection : MapKind::kPlan, MapKind::kExtendedElevation}) {
        const MapDrawing d = drawCaveMap(input, kind, width);
        for (const auto& [ext, bytes] : {std::make_pair(".png", &d.png), std::make_pair(".svg", &d.svg)}) {
            const std::string name = mapStem(kind) + ext;
            writeFileAtomic((fs::path(dir) / name).string(), *bytes);
            written.push_back(name);
        }
    }
    return written;
}

}  // namespace cavesim::render

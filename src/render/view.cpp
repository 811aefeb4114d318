#include "render/view.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/check.h"
#include "render/colormap.h"

namespace cavesim::render {
namespace {

int cellW(int ts) {
    return 6 * ts;
}
int cellH(int ts) {
    return 8 * ts;
}
int titleScale(int ts) {
    return ts + 1;
}

int textScaleFor(int width) {
    return std::clamp((width + 256) / 512, 1, 12);
}

// Vertical layout shared by every view.
int topBand(int ts) {
    return cellH(ts) / 2 + 8 * titleScale(ts) + cellH(ts) / 3 + cellH(ts) + cellH(ts) / 2 + cellH(ts) + cellH(ts) / 2;
}
int bottomBand(int ts) {
    return 6 * ts + cellH(ts) / 2 + cellH(ts) + cellH(ts) / 3 + cellH(ts) + cellH(ts) / 2;
}
int leftMargin(int ts) {
    return 6 * cellW(ts) + 6 * ts;
}
int rightMargin(int ts) {
    return 4 * cellW(ts);
}

const Rgb kOutline{60, 60, 66};
const Rgb kFaintOutline{150, 150, 158};

// The 8 corners of the block, bit a of the index = upper end on axis a.
std::array<Vec3d, 8> corners(const Vec3d& m) {
    std::array<Vec3d, 8> c{};
    for (int b = 0; b < 8; ++b) c[b] = {(b & 1) ? m[0] : 0.0, (b & 2) ? m[1] : 0.0, (b & 4) ? m[2] : 0.0};
    return c;
}

// The 12 edges as corner pairs, and for each the two faces it bounds (face = 2·axis + side).
struct Edge {
    int a, b, f0, f1;
};
std::array<Edge, 12> blockEdges() {
    std::array<Edge, 12> e{};
    int n = 0;
    for (int axis = 0; axis < 3; ++axis) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        for (int su = 0; su < 2; ++su)
            for (int sv = 0; sv < 2; ++sv) {
                const int base = (su << u) | (sv << v);
                e[n++] = {base, base | (1 << axis), 2 * u + su, 2 * v + sv};
            }
    }
    return e;
}

// Is face f (2·axis + side) of the block turned toward the camera?
bool faceVisible(const Frame& f, int face) {
    const int axis = face / 2, side = face % 2;
    Vec3d n{0, 0, 0};
    n[axis] = side ? 1.0 : -1.0;
    Vec3d p{f.blockMax[0] / 2, f.blockMax[1] / 2, f.blockMax[2] / 2};
    p[axis] = side ? f.blockMax[axis] : 0.0;
    if (f.camera.perspective) return dot(n, sub(f.camera.eye, p)) > 0.0;
    return dot(n, f.camera.forward) < 0.0;
}

std::vector<std::pair<double, double>> facePolygon(const Frame& f, int face) {
    const auto c = corners(f.blockMax);
    const int axis = face / 2, side = face % 2;
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    const int base = side << axis;
    const int order[4] = {base, base | (1 << u), base | (1 << u) | (1 << v), base | (1 << v)};
    std::vector<std::pair<double, double>> poly;
    for (int o : order) {
        const auto p = f.camera.project(c[o]);
        poly.push_back({p.x, p.y});
    }
    return poly;
}

// Tick spacing (metres) for an axis of `extent` metres drawn at `pixelsPerMetre`, so that labels
// of width `labelPx` do not collide.
double tickStep(double extent, double pixelsPerMetre, int labelPx) {
    double step = niceNumber(std::max(extent, 1e-12) / 5.0);
    for (int guard = 0; guard < 60 && step * pixelsPerMetre < labelPx; ++guard) step = niceNumber(step * 2.01);
    return step;
}

std::vector<double> ticks(double extent, double step) {
    std::vector<double> t;
    for (int n = 0;; ++n) {
        const double v = n * step;
        if (v > extent * (1 + 1e-9)) break;
        t.push_back(v);
        if (n > 1000) break;
    }
    return t;
}

}  // namespace

// --- Camera ------------------------------------------------------------------------------------

Camera::Projected Camera::project(const Vec3d& world) const {
    const Vec3d d = sub(world, eye);
    const double x = dot(d, right), y = dot(d, up), z = dot(d, forward);
    Projected p;
    p.depth = z;
    if (perspective) {
        const double inv = z > 1e-12 ? 1.0 / z : 0.0;
        p.x = cx + scale * x * inv;
        p.y = cy - scale * y * inv;
    } else {
        p.x = cx + scale * x;
        p.y = cy - scale * y;
    }
    return p;
}

void Camera::ray(double px, double py, Vec3d& origin, Vec3d& direction) const {
    const double a = (px - cx) / scale, b = -(py - cy) / scale;
    if (perspective) {
        origin = eye;
        direction = normalized(add(forward, add(cavesim::scale(right, a), cavesim::scale(up, b))));
    } else {
        origin = add(eye, add(cavesim::scale(right, a), cavesim::scale(up, b)));
        direction = forward;
    }
}

std::string viewStem(View view) {
    switch (view) {
        case View::kPlan:
            return "plan";
        case View::kSideXZ:
            return "side_xz";
        case View::kSideYZ:
            return "side_yz";
        case View::kPerspective:
            return "perspective";
    }
    return "view";
}

// --- Frame -------------------------------------------------------------------------------------

int footerRowHeight(int textScale) {
    return cellH(textScale) * 5 / 2;
}

int footerRowY(const Frame& frame, int row) {
    return frame.footerY + row * footerRowHeight(frame.textScale);
}

Frame makeFrame(View view, const Dims& dims, double voxelSize, int width, int footerRows) {
    CAVESIM_CHECK(width >= 64, "picture width must be at least 64 pixels, got " + std::to_string(width));
    CAVESIM_CHECK(voxelSize > 0.0 && std::isfinite(voxelSize),
                  "voxel size must be a positive number of metres, got " + std::to_string(voxelSize));
    CAVESIM_CHECK(dims.nx > 0 && dims.ny > 0 && dims.nz > 0, "cannot frame an empty block " + std::to_string(dims.nx) +
                                                                 "×" + std::to_string(dims.ny) + "×" +
                                                                 std::to_string(dims.nz));
    Frame f;
    f.view = view;
    f.width = width;
    f.dims = dims;
    f.voxelSize = voxelSize;
    f.footerRows = std::max(footerRows, 0);
    const int ts = textScaleFor(width);
    f.textScale = ts;
    f.blockMax = {dims.nx * voxelSize, dims.ny * voxelSize, dims.nz * voxelSize};
    const Vec3d& m = f.blockMax;
    const int left = leftMargin(ts), right = rightMargin(ts), top = topBand(ts);
    const int availW = std::max(16, width - left - right);
    const double maxVh = 1.25 * width;
    Camera& cam = f.camera;

    if (view != View::kPerspective) {
        double eu = 0, ev = 0;
        switch (view) {
            case View::kPlan:
                cam.right = {1, 0, 0}, cam.up = {0, 1, 0}, cam.forward = {0, 0, -1};
                cam.eye = {m[0] / 2, m[1] / 2, m[2]};
                eu = m[0], ev = m[1];
                f.depthMin = 0, f.depthMax = m[2];
                break;
            case View::kSideXZ:
                cam.right = {1, 0, 0}, cam.up = {0, 0, 1}, cam.forward = {0, 1, 0};
                cam.eye = {m[0] / 2, 0, m[2] / 2};
                eu = m[0], ev = m[2];
                f.depthMin = 0, f.depthMax = m[1];
                break;
            default:  // kSideYZ
                cam.right = {0, 1, 0}, cam.up = {0, 0, 1}, cam.forward = {-1, 0, 0};
                cam.eye = {m[0], m[1] / 2, m[2] / 2};
                eu = m[1], ev = m[2];
                f.depthMin = 0, f.depthMax = m[0];
                break;
        }
        double s = availW / eu;
        if (ev * s > maxVh) s = maxVh / ev;
        f.vw = std::max(1, int(std::lround(eu * s)));
        f.vh = std::max(1, int(std::lround(ev * s)));
        cam.scale = f.vw / eu;  // the viewport is exactly the block
        f.vx = left + (availW - f.vw) / 2;
        f.vy = top;
        cam.cx = f.vx + 0.5 * f.vw;
        cam.cy = f.vy + 0.5 * f.vh;
    } else {
        const Vec3d centre{m[0] / 2, m[1] / 2, m[2] / 2};
        const double azimuth = 35.0 * 3.14159265358979323846 / 180.0;
        const double elevation = 30.0 * 3.14159265358979323846 / 180.0;
        const Vec3d toEye{-std::sin(azimuth) * std::cos(elevation), -std::cos(azimuth) * std::cos(elevation),
                          std::sin(elevation)};
        const double radius = 0.5 * std::sqrt(dot(m, m));
        cam.perspective = true;
        cam.eye = add(centre, cavesim::scale(toEye, 2.8 * radius));
        cam.forward = normalized(cavesim::scale(toEye, -1.0));
        cam.right = normalized(cross(cam.forward, {0, 0, 1}));
        cam.up = cross(cam.right, cam.forward);
        cam.scale = 1.0;
        cam.cx = cam.cy = 0.0;
        double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
        f.depthMin = 1e300, f.depthMax = -1e300;
        for (const Vec3d& c : corners(m)) {
            const auto p = cam.project(c);
            x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
            f.depthMin = std::min(f.depthMin, p.depth), f.depthMax = std::max(f.depthMax, p.depth);
        }
        const int pad = 4 * cellW(ts);
        const int inner = std::max(16, availW - 2 * pad);
        double s = inner / std::max(x1 - x0, 1e-12);
        if ((y1 - y0) * s + 2 * pad > maxVh) s = (maxVh - 2 * pad) / std::max(y1 - y0, 1e-12);
        f.vw = int(std::lround((x1 - x0) * s)) + 2 * pad;
        f.vh = int(std::lround((y1 - y0) * s)) + 2 * pad;
        f.vx = left + (availW - f.vw) / 2;
        f.vy = top;
        cam.scale = s;
        cam.cx = f.vx + pad - x0 * s;
        cam.cy = f.vy + pad - y0 * s;
    }
    f.footerY = f.vy + f.vh + bottomBand(ts);
    f.height = f.footerY + f.footerRows * footerRowHeight(ts) + cellH(ts) / 2;
    return f;
}

Image makeCanvas(const Frame& f) {
    Image img(f.width, f.height, colours::kWhite);
    const Rgb rock = mix(colours::kRock, colours::kWhite, 0.55);
    if (!f.camera.perspective) {
        fillRect(img, f.vx, f.vy, f.vw, f.vh, rock);
        return img;
    }
    // Visible faces, top lighter than the sides: a solid block at a glance.
    for (int face = 0; face < 6; ++face) {
        if (!faceVisible(f, face)) continue;
        const double shade = face == 5 ? 1.04 : (face / 2 == 0 ? 0.93 : 0.97);
        fillPolygon(img, facePolygon(f, face), scale(rock, shade));
    }
    return img;
}

// --- Cells of orthographic views ---------------------------------------------------------------

CellGrid cellGrid(const Frame& f) {
    switch (f.view) {
        case View::kPlan:
            return {f.dims.nx, f.dims.ny};
        case View::kSideXZ:
            return {f.dims.nx, f.dims.nz};
        case View::kSideYZ:
            return {f.dims.ny, f.dims.nz};
        default:
            return {0, 0};
    }
}

Vec3d viewPlanePoint(const Frame& f, double u, double v) {
    const double h = f.voxelSize;
    switch (f.view) {
        case View::kPlan:
            return {u * h, v * h, f.blockMax[2]};
        case View::kSideXZ:
            return {u * h, 0.0, v * h};
        case View::kSideYZ:
            return {f.blockMax[0], u * h, v * h};
        default:
            return {0, 0, 0};
    }
}

void fillCells(Image& img, const Frame& f, const std::function<Rgb(int, int)>& colour) {
    if (f.camera.perspective) return;
    const CellGrid g = cellGrid(f);
    // Pixel column → u and row → v (the projection is axis-aligned).
    std::vector<int> us(std::size_t(f.vw)), vs(std::size_t(f.vh));
    const double h = f.voxelSize, s = f.camera.scale;
    const Vec3d origin = viewPlanePoint(f, 0, 0);
    const auto o = f.camera.project(origin);
    for (int x = 0; x < f.vw; ++x) us[x] = std::clamp(int(std::floor((f.vx + x + 0.5 - o.x) / (s * h))), 0, g.nu - 1);
    for (int y = 0; y < f.vh; ++y) vs[y] = std::clamp(int(std::floor((o.y - (f.vy + y + 0.5)) / (s * h))), 0, g.nv - 1);
    for (int y = 0; y < f.vh; ++y) {
        int lastU = -1;
        Rgb c{};
        for (int x = 0; x < f.vw; ++x) {
            if (us[x] != lastU) {
                lastU = us[x];
                c = colour(us[x], vs[y]);
            }
            img.set(f.vx + x, f.vy + y, c);
        }
    }
}

void outlineCells(Image& img, const Frame& f, const std::function<bool(int, int)>& inside, Rgb c, int thickness) {
    if (f.camera.perspective) return;
    const CellGrid g = cellGrid(f);
    auto in = [&](int u, int v) { return u >= 0 && v >= 0 && u < g.nu && v < g.nv && inside(u, v); };
    auto px = [&](double u, double v) { return f.camera.project(viewPlanePoint(f, u, v)); };
    const int t = std::max(1, thickness);
    for (int v = 0; v < g.nv; ++v)
        for (int u = 0; u < g.nu; ++u) {
            const bool a = in(u, v);
            // Vertical boundary on the right of (u, v), horizontal boundary above it; the
            // left and bottom rims are handled as the right/top of cell -1.
            for (int side = 0; side < 2; ++side) {
                const int uu = side == 0 ? u + 1 : u, vv = side == 0 ? v : v + 1;
                if (a == in(uu, vv)) continue;
                const auto p0 = side == 0 ? px(u + 1, v) : px(u, v + 1);
                const auto p1 = px(u + 1, v + 1);
                const int x0 = int(std::lround(std::min(p0.x, p1.x))), x1 = int(std::lround(std::max(p0.x, p1.x)));
                const int y0 = int(std::lround(std::min(p0.y, p1.y))), y1 = int(std::lround(std::max(p0.y, p1.y)));
                if (side == 0)
                    fillRect(img, x0 - t / 2, y0, t, y1 - y0 + (t + 1) / 2, c);
                else
                    fillRect(img, x0, y0 - t / 2, x1 - x0 + (t + 1) / 2, t, c);
            }
            if (u == 0 && a) {
                const auto p0 = px(0, v), p1 = px(0, v + 1);
                fillRect(img, int(std::lround(p0.x)) - t / 2, int(std::lround(p1.y)), t, int(std::lround(p0.y - p1.y)),
                         c);
            }
            if (v == 0 && a) {
                const auto p0 = px(u, 0), p1 = px(u + 1, 0);
                fillRect(img, int(std::lround(p0.x)), int(std::lround(p0.y)) - t / 2, int(std::lround(p1.x - p0.x)), t,
                         c);
            }
        }
}

// --- Annotations -------------------------------------------------------------------------------

double niceNumber(double x) {
    if (!(x > 0.0) || !std::isfinite(x)) return 1.0;
    const double e = std::floor(std::log10(x));
    const double p = std::pow(10.0, e);
    const double m = x / p;
    const double n = m < 1.5 ? 1.0 : (m < 3.5 ? 2.0 : (m < 7.5 ? 5.0 : 10.0));
    return n * p;
}

std::string formatMetres(double metres) {
    char buf[32];
    const double a = std::abs(metres);
    if (a == 0.0) return "0";
    if (a >= 100.0 || std::abs(metres - std::round(metres)) < 1e-9 * std::max(1.0, a))
        std::snprintf(buf, sizeof buf, "%.0f", metres);
    else if (a >= 1.0)
        std::snprintf(buf, sizeof buf, "%.1f", metres);
    else
        std::snprintf(buf, sizeof buf, "%.3g", metres);
    return buf;
}

std::string formatValue(double value) {
    char buf[32];
    const double a = std::abs(value);
    if (a == 0.0) return "0";
    if (a >= 1e5 || a < 1e-3)
        std::snprintf(buf, sizeof buf, "%.2g", value);
    else
        std::snprintf(buf, sizeof buf, "%.3g", value);
    return buf;
}

void drawTitle(Image& img, const Frame& f, const std::string& title, const std::string& subtitle) {
    const int ts = f.textScale;
    int y = cellH(ts) / 2;
    drawText(img, f.vx, y, title, colours::kText, titleScale(ts));
    y += 8 * titleScale(ts) + cellH(ts) / 3;
    if (subtitle.empty()) return;
    // A subtitle too long for the picture is drawn smaller, and shortened if still too long.
    const int room = img.width - f.vx - cellW(ts);
    int scale = ts;
    while (scale > 1 && textWidth(subtitle, scale) > room) --scale;
    std::string text = subtitle;
    if (textWidth(text, scale) > room) {
        const std::size_t keep = std::size_t(std::max(0, room / (6 * scale) - 3));
        text = text.substr(0, std::min(keep, text.size())) + "...";
    }
    drawText(img, f.vx, y + (ts - scale) * 4, text, Rgb{90, 90, 100}, scale);
}

namespace {

struct AxisNames {
    const char* u;
    const char* v;
};
AxisNames axisNames(View view) {
    switch (view) {
        case View::kPlan:
            return {"x (m)", "y (m)"};
        case View::kSideXZ:
            return {"x (m)", "z (m)"};
        default:
            return {"y (m)", "z (m)"};
    }
}

void drawPerspectiveAxes(Image& img, const Frame& f) {
    const int ts = f.textScale;
    const Vec3d& m = f.blockMax;
    const auto centre = f.camera.project({m[0] / 2, m[1] / 2, m[2] / 2});
    // Three edges through the corner (0, 0, 0), nearest the viewer: x along y = z = 0, y along
    // x = z = 0, z along x = y = 0. Labels sit outside the block, away from its centre; the
    // corner's 0 is written once (on the x axis).
    const Vec3d origin{0, 0, 0};
    const char* names[3] = {"x (m)", "y (m)", "z (m)"};
    for (int axis = 0; axis < 3; ++axis) {
        Vec3d end = origin;
        end[axis] = m[axis];
        const auto p0 = f.camera.project(origin), p1 = f.camera.project(end);
        const double ex = p1.x - p0.x, ey = p1.y - p0.y, len = std::hypot(ex, ey);
        // Too short on the picture to carry ticks (e.g. the y edge of a section): name only.
        const bool ticked = len >= 3.0 * textWidth("000", ts);
        if (len < 1.0) continue;
        double nx = -ey / len, ny = ex / len;
        const double mx = 0.5 * (p0.x + p1.x) - centre.x, my = 0.5 * (p0.y + p1.y) - centre.y;
        if (nx * mx + ny * my < 0) nx = -nx, ny = -ny;
        int widest = 0;
        if (ticked) {
            const double step = tickStep(m[axis], len / m[axis], textWidth("0000", ts) + cellW(ts));
            for (double t : ticks(m[axis], step)) {
                Vec3d w = origin;
                w[axis] = t;
                const auto p = f.camera.project(w);
                drawLine(img, p.x, p.y, p.x + nx * 6 * ts, p.y + ny * 6 * ts, kOutline, std::max(1, ts / 2));
                if (t == 0.0 && axis != 0) continue;
                const std::string label = formatMetres(t);
                widest = std::max(widest, textWidth(label, ts));
                // Centre of the label box just beyond the tick, whichever side it is on.
                const double reach = 8 * ts + 0.5 * (std::abs(nx) * textWidth(label, ts) + std::abs(ny) * cellH(ts));
                drawTextAligned(img, int(std::lround(p.x + nx * reach)),
                                int(std::lround(p.y + ny * reach - 7 * ts / 2.0)), label, colours::kText, ts,
                                Align::kCentre, true);
            }
        }
        // Axis name at the middle of the edge, beyond the tick labels.
        const std::string name = names[axis];
        const double reach = 8 * ts + std::abs(nx) * (widest + cellW(ts) + 0.5 * textWidth(name, ts)) +
                             std::abs(ny) * (1.5 * cellH(ts) + (ticked ? cellH(ts) : 0));
        const double lx = 0.5 * (p0.x + p1.x) + nx * reach, ly = 0.5 * (p0.y + p1.y) + ny * reach;
        drawTextAligned(img, int(std::lround(lx)), int(std::lround(ly - 7 * ts / 2.0)), name, colours::kText, ts,
                        Align::kCentre, true);
    }
}

}  // namespace

void drawAxes(Image& img, const Frame& f) {
    if (f.camera.perspective) {
        drawPerspectiveAxes(img, f);
        return;
    }
    const int ts = f.textScale;
    const CellGrid g = cellGrid(f);
    const double h = f.voxelSize, s = f.camera.scale;
    const double eu = g.nu * h, ev = g.nv * h;
    const int tick = 6 * ts;
    const AxisNames names = axisNames(f.view);
    // u axis along the bottom.
    const double stepU = tickStep(eu, s, textWidth(formatMetres(eu) + "00", ts));
    const int yb = f.vy + f.vh;
    for (double t : ticks(eu, stepU)) {
        const int x = int(std::lround(f.camera.project(viewPlanePoint(f, t / h, 0)).x));
        fillRect(img, x - std::max(1, ts / 2) / 2, yb, std::max(1, ts / 2), tick, kOutline);
        drawTextAligned(img, x, yb + tick + cellH(ts) / 2, formatMetres(t), colours::kText, ts, Align::kCentre);
    }
    drawTextAligned(img, f.vx + f.vw / 2, yb + tick + cellH(ts) / 2 + cellH(ts) + cellH(ts) / 3, names.u,
                    colours::kText, ts, Align::kCentre);
    // v axis along the left.
    const double stepV = tickStep(ev, s, cellH(ts) * 2);
    for (double t : ticks(ev, stepV)) {
        const int y = int(std::lround(f.camera.project(viewPlanePoint(f, 0, t / h)).y));
        fillRect(img, f.vx - tick, y - std::max(1, ts / 2) / 2, tick, std::max(1, ts / 2), kOutline);
        drawTextAligned(img, f.vx - tick - cellW(ts) / 2, y - 7 * ts / 2, formatMetres(t), colours::kText, ts,
                        Align::kRight);
    }
    drawTextAligned(img, f.vx - tick - cellW(ts) / 2, f.vy - cellH(ts) - cellH(ts) / 2, names.v, colours::kText, ts,
                    Align::kRight);
}

void drawBlockOutline(Image& img, const Frame& f, const std::vector<float>* depth) {
    const int ts = f.textScale;
    const int t = std::max(1, ts / 2 + 1);
    if (!f.camera.perspective) {
        drawRect(img, f.vx - t, f.vy - t, f.vw + 2 * t, f.vh + 2 * t, kOutline, t);
        return;
    }
    const auto c = corners(f.blockMax);
    auto hiddenByCave = [&](double x, double y, double d) {
        if (!depth) return false;
        const int px = int(std::floor(x)) - f.vx, py = int(std::floor(y)) - f.vy;
        if (px < 0 || py < 0 || px >= f.vw || py >= f.vh) return false;
        return double((*depth)[std::size_t(py) * f.vw + px]) < d;
    };
    for (const Edge& e : blockEdges()) {
        const bool front = faceVisible(f, e.f0) || faceVisible(f, e.f1);
        const auto p0 = f.camera.project(c[e.a]), p1 = f.camera.project(c[e.b]);
        if (!front) {
            // Far edges: dashed, faint where the cave is in front of them.
            const double len = std::hypot(p1.x - p0.x, p1.y - p0.y);
            const int steps = std::max(1, int(len / 2));
            const int dash = 5 * ts, gap = 4 * ts;
            for (int sIdx = 0; sIdx < steps; ++sIdx) {
                const double a = double(sIdx) / steps, b = double(sIdx + 1) / steps;
                const double along = a * len;
                if (std::fmod(along, double(dash + gap)) > dash) continue;
                const double x0 = p0.x + a * (p1.x - p0.x), y0 = p0.y + a * (p1.y - p0.y);
                const double x1 = p0.x + b * (p1.x - p0.x), y1 = p0.y + b * (p1.y - p0.y);
                const double d = p0.depth + a * (p1.depth - p0.depth);
                drawLine(img, x0, y0, x1, y1,
                         hiddenByCave(x0, y0, d) ? mix(kFaintOutline, colours::kWhite, 0.5) : kFaintOutline,
                         std::max(1, ts / 2));
            }
            continue;
        }
        drawLine(img, p0.x, p0.y, p1.x, p1.y, kOutline, t);
    }
}

int drawScaleBar(Image& img, const Frame& f, int x, int y) {
    const int ts = f.textScale;
    double pxPerMetre = f.camera.scale;
    if (f.camera.perspective) {
        const Vec3d& m = f.blockMax;
        const auto p = f.camera.project({m[0] / 2, m[1] / 2, m[2] / 2});
        pxPerMetre = f.camera.scale / std::max(p.depth, 1e-12);
    }
    const double extent = f.view == View::kSideYZ ? f.blockMax[1] : f.blockMax[0];
    double length = niceNumber(extent / 5.0);
    while (length * pxPerMetre > 0.3 * f.width && length > 1e-9) length = niceNumber(length / 2.01);
    const int w = std::max(4, int(std::lround(length * pxPerMetre)));
    const int h = std::max(4, 2 * ts + 2);
    // Four alternating segments in a frame.
    for (int s = 0; s < 4; ++s) {
        const int xa = x + s * w / 4, xb = x + (s + 1) * w / 4;
        fillRect(img, xa, y, xb - xa, h, s % 2 ? colours::kWhite : colours::kText);
    }
    drawRect(img, x, y, w, h, colours::kText, 1);
    std::string label = formatMetres(length) + " m";
    if (f.camera.perspective) label += " (at centre)";
    return drawText(img, x + w + cellW(ts), y + h / 2 - 7 * ts / 2, label, colours::kText, ts) + cellW(ts);
}

namespace {

struct VoxelBoxInfo {
    Vec3d lo, hi, centre;
};
VoxelBoxInfo voxelBox(const std::vector<std::size_t>& voxels, const Dims& dims, double h) {
    VoxelBoxInfo b{{1e300, 1e300, 1e300}, {-1e300, -1e300, -1e300}, {0, 0, 0}};
    for (std::size_t n : voxels) {
        const Index3 p = dims.coord(n);
        const double c[3] = {(p.i + 0.5) * h, (p.j + 0.5) * h, (p.k + 0.5) * h};
        for (int a = 0; a < 3; ++a) {
            b.lo[a] = std::min(b.lo[a], c[a] - 0.5 * h);
            b.hi[a] = std::max(b.hi[a], c[a] + 0.5 * h);
            b.centre[a] += c[a] / double(voxels.size());
        }
    }
    return b;
}

void drawVoxelBox(Image& img, const Frame& f, const VoxelBoxInfo& b, Rgb c, double minPx) {
    if (!f.camera.perspective) {
        // The box's projection is a rectangle.
        double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
        for (int k = 0; k < 8; ++k) {
            const auto p = f.camera.project(
                {(k & 1) ? b.hi[0] : b.lo[0], (k & 2) ? b.hi[1] : b.lo[1], (k & 4) ? b.hi[2] : b.lo[2]});
            x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
        }
        if (x1 - x0 < minPx && y1 - y0 < minPx) return;
        const int xa = int(std::lround(x0)), ya = int(std::lround(y0));
        const int w = int(std::lround(x1)) - xa, h = int(std::lround(y1)) - ya;
        for (int y = std::max(ya, 0); y < std::min(ya + h, img.height); ++y)
            for (int x = std::max(xa, 0); x < std::min(xa + w, img.width); ++x) img.blend(x, y, c, 0.25);
        drawRect(img, xa, ya, w, h, c, std::max(1, f.textScale / 2 + 1));
        return;
    }
    // Edges of the box (corner bits as for the block).
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    std::array<Camera::Projected, 8> p;
    for (int k = 0; k < 8; ++k) {
        p[k] =
            f.camera.project({(k & 1) ? b.hi[0] : b.lo[0], (k & 2) ? b.hi[1] : b.lo[1], (k & 4) ? b.hi[2] : b.lo[2]});
        x0 = std::min(x0, p[k].x), x1 = std::max(x1, p[k].x), y0 = std::min(y0, p[k].y), y1 = std::max(y1, p[k].y);
    }
    if (x1 - x0 < minPx && y1 - y0 < minPx) return;
    for (const Edge& e : blockEdges())
        drawLine(img, p[e.a].x, p[e.a].y, p[e.b].x, p[e.b].y, c, std::max(1, f.textScale / 2 + 1));
}

}  // namespace

void drawSourcesAndSinks(Image& img, const Frame& f, const Dims& dims,
                         const std::vector<std::vector<std::size_t>>& sourceVoxels,
                         const std::vector<std::vector<std::size_t>>& sinkVoxels) {
    const int ts = f.textScale;
    const double r = 3.0 * ts + 2.0;
    const double h = f.voxelSize;
    // A box shared by several terminals (sources given at the same voxels) is shaded once.
    std::vector<std::pair<std::array<double, 6>, Rgb>> drawn;
    auto place = [&](const std::vector<std::size_t>& voxels, Rgb c, Marker marker, const std::string& label) {
        if (voxels.empty()) return;
        const VoxelBoxInfo b = voxelBox(voxels, dims, h);
        const std::array<double, 6> key{b.lo[0], b.lo[1], b.lo[2], b.hi[0], b.hi[1], b.hi[2]};
        bool seen = false;
        for (const auto& [k, col] : drawn) seen = seen || (k == key && col == c);
        if (!seen) {
            drawVoxelBox(img, f, b, c, 2.5 * r);
            drawn.push_back({key, c});
        }
        const auto p = f.camera.project(b.centre);
        drawMarker(img, p.x, p.y, r, marker, c, colours::kWhite);
        // Label up and to the right, or to the left where it would leave the picture.
        const int right = int(std::lround(p.x + r + 2 * ts));
        const bool flip = right + textWidth(label, ts) + 2 > img.width;
        drawTextAligned(img, flip ? int(std::lround(p.x - r - 2 * ts)) : right, int(std::lround(p.y - r - cellH(ts))),
                        label, c, ts, flip ? Align::kRight : Align::kLeft, true);
    };
    for (std::size_t s = 0; s < sinkVoxels.size(); ++s)
        place(sinkVoxels[s], colours::kSink, Marker::kSquare,
              sinkVoxels.size() == 1 ? std::string("sink") : "sink " + std::to_string(s + 1));
    for (std::size_t s = 0; s < sourceVoxels.size(); ++s)
        place(sourceVoxels[s], colours::kSource, Marker::kCircle, "S" + std::to_string(s + 1));
}

int drawLegend(Image& img, const Frame& f, int row, int x, const std::vector<LegendEntry>& entries) {
    const int ts = f.textScale;
    const int yc = footerRowY(f, row) + cellH(ts);
    for (const LegendEntry& e : entries) {
        switch (e.kind) {
            case LegendEntry::Kind::kMarker: {
                const double r = 3.0 * ts + 2.0;
                drawMarker(img, x + r + 1, yc, r, e.marker, e.colour, colours::kWhite);
                x += int(2 * r + 2) + cellW(ts) / 2;
                break;
            }
            case LegendEntry::Kind::kSwatch:
                fillRect(img, x, yc - cellH(ts) / 2, 3 * cellW(ts), cellH(ts), e.colour);
                drawRect(img, x, yc - cellH(ts) / 2, 3 * cellW(ts), cellH(ts), Rgb{90, 90, 90}, 1);
                x += 3 * cellW(ts) + cellW(ts) / 2;
                break;
            case LegendEntry::Kind::kLine:
                // On a mid-grey box, so that white and black lines both show.
                fillRect(img, x, yc - cellH(ts) / 2, 3 * cellW(ts), cellH(ts), Rgb{150, 150, 156});
                fillRect(img, x, yc - std::max(1, ts / 2), 3 * cellW(ts), std::max(2, ts), e.colour);
                x += 3 * cellW(ts) + cellW(ts) / 2;
                break;
        }
        x = drawText(img, x, yc - 7 * ts / 2, e.text, colours::kText, ts) + 2 * cellW(ts);
    }
    return x;
}

void drawStandardLegend(Image& img, const Frame& f, const std::vector<LegendEntry>& extra) {
    if (f.footerRows < 1) return;
    const int ts = f.textScale;
    int x = drawScaleBar(img, f, f.vx, footerRowY(f, 0) + cellH(ts) - (2 * ts + 2) / 2) + cellW(ts);
    std::vector<LegendEntry> entries{{LegendEntry::Kind::kMarker, colours::kSource, Marker::kCircle, "source"},
                                     {LegendEntry::Kind::kMarker, colours::kSink, Marker::kSquare, "sink"}};
    entries.insert(entries.end(), extra.begin(), extra.end());
    drawLegend(img, f, 0, x, entries);
}

void drawColourBar(Image& img, const Frame& f, int row, const std::function<Rgb(double)>& colour, double lo, double hi,
                   bool logScale, const std::string& label) {
    const int ts = f.textScale;
    const int y = footerRowY(f, row);
    const int x0 =
        drawText(img, f.vx, y + cellH(ts) / 2 - 7 * ts / 2 + cellH(ts) / 4, label, colours::kText, ts) + cellW(ts);
    const int x1 = std::max(x0 + 16, f.vx + f.vw - cellW(ts) * 2);
    const int barH = cellH(ts);
    const int w = x1 - x0;
    if (!std::isfinite(lo) || !std::isfinite(hi)) lo = 0, hi = 1;
    if (logScale && !(lo > 0)) logScale = false;
    if (!(hi > lo)) hi = lo + (lo == 0 ? 1.0 : std::abs(lo) * 1e-3);
    for (int x = 0; x < w; ++x) {
        const Rgb c = colour((x + 0.5) / w);
        fillRect(img, x0 + x, y, 1, barH, c);
    }
    drawRect(img, x0, y, w, barH, Rgb{90, 90, 90}, 1);
    auto xOf = [&](double v) {
        const double t =
            logScale ? (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo)) : (v - lo) / (hi - lo);
        return x0 + t * w;
    };
    std::vector<double> values;
    if (logScale) {
        for (double e = std::ceil(std::log10(lo) - 1e-9); e <= std::log10(hi) + 1e-9; e += 1.0)
            values.push_back(std::pow(10.0, e));
        if (values.size() < 2) values = {lo, hi};
    } else {
        const double step = niceNumber((hi - lo) / 5.0);
        for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + 1e-9 * std::abs(hi) + 1e-300; v += step)
            values.push_back(std::abs(v) < 1e-12 * step ? 0.0 : v);
    }
    int lastRight = std::numeric_limits<int>::min() / 2;
    for (double v : values) {
        const double x = xOf(v);
        const std::string text = formatValue(v);
        const int tw = textWidth(text, ts);
        const int left = int(std::lround(x)) - tw / 2;
        fillRect(img, int(std::lround(x)), y + barH, std::max(1, ts / 2), 3 * ts, colours::kText);
        if (left <= lastRight + cellW(ts)) continue;
        drawTextAligned(img, int(std::lround(x)), y + barH + 4 * ts, text, colours::kText, ts, Align::kCentre);
        lastRight = left + tw;
    }
}

void drawNote(Image& img, const Frame& f, const std::string& text) {
    const int ts = f.textScale;
    const int w = textWidth(text, ts + 1) + 2 * cellW(ts), h = 8 * (ts + 1) + cellH(ts);
    const int x = f.vx + f.vw / 2 - w / 2, y = f.vy + f.vh / 2 - h / 2;
    fillRect(img, x, y, w, h, colours::kWhite);
    drawRect(img, x, y, w, h, kOutline, 1);
    drawTextAligned(img, x + w / 2, y + cellH(ts) / 2, text, colours::kText, ts + 1, Align::kCentre);
}

}  // namespace cavesim::render

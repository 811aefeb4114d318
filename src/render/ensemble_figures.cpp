#include "render/ensemble_figures.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/check.h"
#include "render/colormap.h"

namespace cavesim::render {
namespace {

std::string number(double v, int digits = 3) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    return buf;
}

/// Linear interpolation between order statistics of sorted values (q in [0, 1]).
double quantile(const std::vector<double>& sorted, double q) {
    if (sorted.empty()) return 0;
    const double at = q * double(sorted.size() - 1);
    const std::size_t lo = std::size_t(std::floor(at));
    const std::size_t hi = std::min(sorted.size() - 1, lo + 1);
    return sorted[lo] + (at - double(lo)) * (sorted[hi] - sorted[lo]);
}

}  // namespace

Image histogramFigure(const std::vector<double>& values, const std::string& title, const std::string& unit, int bins,
                      int width) {
    CAVESIM_CHECK(width >= 256 && width <= 4096, "histogram width out of range");
    CAVESIM_CHECK(bins >= 1 && bins <= 1000, "histogram bins out of range");
    const int height = width * 5 / 8;
    const int scale = std::max(1, width / 400);
    Image img(width, height, colours::kWhite);
    std::vector<double> v = values;
    std::sort(v.begin(), v.end());
    drawTextAligned(img, width / 2, 6 * scale, title + "  (n = " + std::to_string(v.size()) + ")", colours::kText,
                    scale, Align::kCentre);
    const int left = 14 * scale * 3, right = width - 10 * scale, top = 20 * scale, boxH = 14 * scale;
    const int plotTop = top + boxH + 6 * scale, bottom = height - 22 * scale;
    drawRect(img, left, plotTop, right - left, bottom - plotTop, colours::kGrey);
    if (v.empty()) {
        drawTextAligned(img, (left + right) / 2, (plotTop + bottom) / 2, "no values", colours::kGrey, scale,
                        Align::kCentre);
        return img;
    }
    const double lo = v.front(), hi = v.back();
    const double span = hi > lo ? hi - lo : 1.0;
    const double x0 = hi > lo ? lo : lo - 0.5, x1 = hi > lo ? hi : lo + 0.5;
    auto xOf = [&](double x) { return left + (x - x0) / (x1 - x0) * double(right - left); };
    std::vector<int> counts(std::size_t(bins), 0);
    for (double x : v) {
        const int b = hi > lo ? std::min(bins - 1, int((x - lo) / span * bins)) : bins / 2;
        ++counts[std::size_t(b)];
    }
    const int most = *std::max_element(counts.begin(), counts.end());
    for (int b = 0; b < bins; ++b) {
        const double a = hi > lo ? lo + span * b / bins : x0 + (x1 - x0) * b / bins;
        const double e = hi > lo ? lo + span * (b + 1) / bins : x0 + (x1 - x0) * (b + 1) / bins;
        const int h = int(std::lround(double(counts[std::size_t(b)]) / most * (bottom - plotTop - 4 * scale)));
        const int xa = int(std::lround(xOf(a))), xe = int(std::lround(xOf(e)));
        fillRect(img, xa + 1, bottom - h, std::max(1, xe - xa - 1), h, viridis(0.35));
    }
    // Box plot: whiskers at the extremes, box at the quartiles, bar at the median.
    const double q1 = quantile(v, 0.25), med = quantile(v, 0.5), q3 = quantile(v, 0.75);
    const double yMid = top + boxH / 2.0;
    drawLine(img, xOf(lo), yMid, xOf(hi), yMid, colours::kText);
    drawLine(img, xOf(lo), top + 2.0, xOf(lo), top + boxH - 2.0, colours::kText);
    drawLine(img, xOf(hi), top + 2.0, xOf(hi), top + boxH - 2.0, colours::kText);
    const int bx = int(std::lround(xOf(q1)));
    fillRect(img, bx, top, std::max(1, int(std::lround(xOf(q3))) - bx), boxH, viridis(0.75));
    drawRect(img, bx, top, std::max(1, int(std::lround(xOf(q3))) - bx), boxH, colours::kText);
    drawLine(img, xOf(med), top, xOf(med), bottom, colours::kSource, 2);
    drawDashedLine(img, xOf(q1), plotTop, xOf(q1), bottom, colours::kText);
    drawDashedLine(img, xOf(q3), plotTop, xOf(q3), bottom, colours::kText);
    // Axis labels: the ends, the median, the largest count.
    const int ty = bottom + 4 * scale;
    drawTextAligned(img, left, ty, number(lo), colours::kText, scale, Align::kLeft);
    drawTextAligned(img, right, ty, number(hi), colours::kText, scale, Align::kRight);
    drawTextAligned(img, int(xOf(med)), ty + 9 * scale, "median " + number(med) + (unit.empty() ? "" : " " + unit),
                    colours::kSource, scale, Align::kCentre);
    drawTextAligned(img, left - 3 * scale, plotTop, std::to_string(most), colours::kText, scale, Align::kRight);
    drawTextAligned(img, left - 3 * scale, bottom - 8 * scale, "0", colours::kText, scale, Align::kRight);
    return img;
}

Image probabilityPlanFigure(const Grid3<float>& p, double voxelSize, double originX, double originY,
                            const std::string& title, int width, const std::vector<std::array<double, 2>>& sources,
                            const std::vector<std::array<double, 2>>& sinks) {
    CAVESIM_CHECK(width >= 256 && width <= 4096, "probability map width out of range");
    CAVESIM_CHECK(p.dims.count() > 0, "probability map of an empty grid");
    const Dims& d = p.dims;
    const int scale = std::max(1, width / 400);
    const int left = 36 * scale, right = 60 * scale, top = 20 * scale, bottom = 40 * scale;  // room for 3 text lines
    const double px = double(width - left - right) / d.nx;
    const int mapW = width - left - right, mapH = int(std::lround(px * d.ny));
    Image img(width, top + mapH + bottom, colours::kWhite);
    drawTextAligned(img, width / 2, 6 * scale, title, colours::kText, scale, Align::kCentre);
    // Largest probability along each column; pixel rows run from north (top) to south.
    std::vector<float> columnMax(std::size_t(d.nx) * std::size_t(d.ny), 0.f);
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                float& m = columnMax[std::size_t(j) * std::size_t(d.nx) + std::size_t(i)];
                m = std::max(m, p.at(i, j, k));
            }
    for (int y = 0; y < mapH; ++y) {
        const int j = std::min(d.ny - 1, int((mapH - 1 - y) / px));
        for (int x = 0; x < mapW; ++x) {
            const int i = std::min(d.nx - 1, int(x / px));
            const float m = columnMax[std::size_t(j) * std::size_t(d.nx) + std::size_t(i)];
            img.set(left + x, top + y, m > 0 ? viridis(m) : colours::kLightGrey);
        }
    }
    drawRect(img, left - 1, top - 1, mapW + 2, mapH + 2, colours::kText);
    const double r = std::max(3.0, 0.6 * px);
    for (const auto& c : sinks)
        drawMarker(img, left + (c[0] + 0.5) * px, top + mapH - (c[1] + 0.5) * px, r, Marker::kSquare, colours::kSink,
                   colours::kWhite);
    for (const auto& c : sources)
        drawMarker(img, left + (c[0] + 0.5) * px, top + mapH - (c[1] + 0.5) * px, r, Marker::kCircle, colours::kSource,
                   colours::kWhite);
    // Colour bar 0–1.
    const int cbX = left + mapW + 12 * scale, cbW = 10 * scale;
    for (int y = 0; y < mapH; ++y)
        fillRect(img, cbX, top + y, cbW, 1, viridis(1.0 - double(y) / std::max(1, mapH - 1)));
    drawRect(img, cbX, top, cbW, mapH, colours::kText);
    drawText(img, cbX + cbW + 2 * scale, top, "1", colours::kText, scale);
    drawText(img, cbX + cbW + 2 * scale, top + mapH - 8 * scale, "0", colours::kText, scale);
    // Axes in metres: the block's extent, and where its corner lies in the world.
    const double wx = d.nx * voxelSize, wy = d.ny * voxelSize;
    drawTextAligned(img, left, top + mapH + 4 * scale, "0", colours::kText, scale, Align::kLeft);
    drawTextAligned(img, left + mapW, top + mapH + 4 * scale, number(wx) + " m", colours::kText, scale, Align::kRight);
    drawTextAligned(img, left - 3 * scale, top, number(wy) + " m", colours::kText, scale, Align::kRight);
    drawTextAligned(
        img, left, top + mapH + 16 * scale,
        "x east, y north; corner at (" + number(originX, 12) + ", " + number(originY, 12) + ") m; grey: never cave",
        colours::kText, scale, Align::kLeft);
    drawTextAligned(img, left, top + mapH + 27 * scale, "red circles: sources, blue squares: sinks", colours::kText,
                    scale, Align::kLeft);
    return img;
}

}  // namespace cavesim::render

#include "render/image.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

#include "core/check.h"

namespace cavesim::render {

Image::Image(int w, int h, Rgb fill) : width(std::max(w, 0)), height(std::max(h, 0)) {
    pixels.resize(std::size_t(width) * std::size_t(height) * 3);
    for (std::size_t n = 0; n < pixels.size(); n += 3) {
        pixels[n] = fill.r;
        pixels[n + 1] = fill.g;
        pixels[n + 2] = fill.b;
    }
}

Rgb Image::get(int x, int y) const {
    if (!contains(x, y)) return {};
    const std::size_t n = (std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3;
    return {pixels[n], pixels[n + 1], pixels[n + 2]};
}

void Image::set(int x, int y, Rgb c) {
    if (!contains(x, y)) return;
    const std::size_t n = (std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3;
    pixels[n] = c.r;
    pixels[n + 1] = c.g;
    pixels[n + 2] = c.b;
}

void Image::blend(int x, int y, Rgb c, double alpha) {
    if (!contains(x, y)) return;
    set(x, y, mix(get(x, y), c, std::clamp(alpha, 0.0, 1.0)));
}

Rgb mix(Rgb a, Rgb b, double t) {
    auto m = [t](std::uint8_t u, std::uint8_t v) {
        return std::uint8_t(std::lround(std::clamp(u + (double(v) - double(u)) * t, 0.0, 255.0)));
    };
    return {m(a.r, b.r), m(a.g, b.g), m(a.b, b.b)};
}

Rgb scale(Rgb c, double s) {
    auto f = [s](std::uint8_t u) { return std::uint8_t(std::lround(std::clamp(u * s, 0.0, 255.0))); };
    return {f(c.r), f(c.g), f(c.b)};
}

void fillRect(Image& img, int x0, int y0, int w, int h, Rgb c) {
    const int xa = std::max(x0, 0), ya = std::max(y0, 0);
    const int xb = std::min(x0 + w, img.width), yb = std::min(y0 + h, img.height);
    for (int y = ya; y < yb; ++y)
        for (int x = xa; x < xb; ++x) img.set(x, y, c);
}

void drawRect(Image& img, int x0, int y0, int w, int h, Rgb c, int thickness) {
    for (int t = 0; t < thickness; ++t) {
        const int xa = x0 + t, ya = y0 + t, ww = w - 2 * t, hh = h - 2 * t;
        if (ww <= 0 || hh <= 0) break;
        fillRect(img, xa, ya, ww, 1, c);
        fillRect(img, xa, ya + hh - 1, ww, 1, c);
        fillRect(img, xa, ya, 1, hh, c);
        fillRect(img, xa + ww - 1, ya, 1, hh, c);
    }
}

namespace {

// Anti-aliased 1-px line after Xiaolin Wu: two pixels per step weighted by coverage.
void wuLine(Image& img, double x0, double y0, double x1, double y1, Rgb c) {
    // Continuous coordinates: pixel x is centred at x + 0.5.
    x0 -= 0.5;
    y0 -= 0.5;
    x1 -= 0.5;
    y1 -= 0.5;
    const bool steep = std::abs(y1 - y0) > std::abs(x1 - x0);
    if (steep) {
        std::swap(x0, y0);
        std::swap(x1, y1);
    }
    if (x0 > x1) {
        std::swap(x0, x1);
        std::swap(y0, y1);
    }
    const double dx = x1 - x0, dy = y1 - y0;
    const double grad = dx == 0.0 ? 1.0 : dy / dx;
    auto plot = [&](int x, int y, double a) {
        if (steep)
            img.blend(y, x, c, a);
        else
            img.blend(x, y, c, a);
    };
    const int xs = int(std::lround(x0)), xe = int(std::lround(x1));
    for (int x = xs; x <= xe; ++x) {
        const double y = y0 + grad * (x - x0);
        const int yi = int(std::floor(y));
        const double f = y - yi;
        plot(x, yi, 1.0 - f);
        plot(x, yi + 1, f);
    }
}

}  // namespace

void drawLine(Image& img, double x0, double y0, double x1, double y1, Rgb c, int thickness) {
    if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1)) return;
    if (thickness <= 1) {
        wuLine(img, x0, y0, x1, y1, c);
        return;
    }
    // Thick line: stamp discs along the segment.
    const double len = std::hypot(x1 - x0, y1 - y0);
    const int steps = std::max(1, int(std::ceil(len)));
    const double r = 0.5 * thickness;
    for (int s = 0; s <= steps; ++s) {
        const double t = double(s) / steps;
        fillCircle(img, x0 + t * (x1 - x0), y0 + t * (y1 - y0), r, c);
    }
}

void drawDashedLine(Image& img, double x0, double y0, double x1, double y1, Rgb c, int dash, int gap, int thickness) {
    const double len = std::hypot(x1 - x0, y1 - y0);
    if (len <= 0.0 || !std::isfinite(len)) return;
    const double period = std::max(1, dash + gap);
    for (double s = 0.0; s < len; s += period) {
        const double e = std::min(len, s + dash);
        drawLine(img, x0 + (x1 - x0) * s / len, y0 + (y1 - y0) * s / len, x0 + (x1 - x0) * e / len,
                 y0 + (y1 - y0) * e / len, c, thickness);
    }
}

void fillCircle(Image& img, double cx, double cy, double radius, Rgb c) {
    const int xa = int(std::floor(cx - radius - 1)), xb = int(std::ceil(cx + radius + 1));
    const int ya = int(std::floor(cy - radius - 1)), yb = int(std::ceil(cy + radius + 1));
    for (int y = ya; y <= yb; ++y)
        for (int x = xa; x <= xb; ++x) {
            const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
            const double cover = std::clamp(radius + 0.5 - d, 0.0, 1.0);
            if (cover > 0.0) img.blend(x, y, c, cover);
        }
}

void fillPolygon(Image& img, const std::vector<std::pair<double, double>>& p, Rgb c, double alpha) {
    if (p.size() < 3) return;
    double ylo = p[0].second, yhi = p[0].second;
    for (const auto& q : p) {
        if (!std::isfinite(q.first) || !std::isfinite(q.second)) return;
        ylo = std::min(ylo, q.second);
        yhi = std::max(yhi, q.second);
    }
    const int ya = std::max(0, int(std::floor(ylo))), yb = std::min(img.height - 1, int(std::ceil(yhi)));
    std::vector<double> xs;
    for (int y = ya; y <= yb; ++y) {
        const double yc = y + 0.5;
        xs.clear();
        for (std::size_t i = 0; i < p.size(); ++i) {
            const auto& a = p[i];
            const auto& b = p[(i + 1) % p.size()];
            if ((a.second <= yc) != (b.second <= yc))
                xs.push_back(a.first + (yc - a.second) * (b.first - a.first) / (b.second - a.second));
        }
        std::sort(xs.begin(), xs.end());
        for (std::size_t i = 0; i + 1 < xs.size(); i += 2) {
            // Pixels whose centre lies in [xs[i], xs[i+1]).
            const int xa = std::max(0, int(std::ceil(xs[i] - 0.5)));
            const int xb = std::min(img.width - 1, int(std::ceil(xs[i + 1] - 0.5)) - 1);
            for (int x = xa; x <= xb; ++x) {
                if (alpha >= 1.0)
                    img.set(x, y, c);
                else
                    img.blend(x, y, c, alpha);
            }
        }
    }
}

void drawCircle(Image& img, double cx, double cy, double radius, Rgb c, int thickness) {
    const int xa = int(std::floor(cx - radius - thickness)), xb = int(std::ceil(cx + radius + thickness));
    const int ya = int(std::floor(cy - radius - thickness)), yb = int(std::ceil(cy + radius + thickness));
    const double half = 0.5 * thickness;
    for (int y = ya; y <= yb; ++y)
        for (int x = xa; x <= xb; ++x) {
            const double d = std::abs(std::hypot(x + 0.5 - cx, y + 0.5 - cy) - radius);
            const double cover = std::clamp(half + 0.5 - d, 0.0, 1.0);
            if (cover > 0.0) img.blend(x, y, c, cover);
        }
}

void drawMarker(Image& img, double cx, double cy, double r, Marker m, Rgb fill, Rgb outline) {
    switch (m) {
        case Marker::kCircle:
            fillCircle(img, cx, cy, r + 1.0, outline);
            fillCircle(img, cx, cy, r, fill);
            break;
        case Marker::kSquare: {
            const int x0 = int(std::lround(cx - r)), y0 = int(std::lround(cy - r)), s = int(std::lround(2 * r));
            fillRect(img, x0 - 1, y0 - 1, s + 2, s + 2, outline);
            fillRect(img, x0, y0, s, s, fill);
            break;
        }
        case Marker::kTriangle:
        case Marker::kDiamond: {
            // Scan-convert a convex polygon by testing pixel centres against its edges.
            std::vector<std::pair<double, double>> p;
            if (m == Marker::kTriangle)
                p = {{cx, cy - 1.2 * r}, {cx + 1.1 * r, cy + 0.8 * r}, {cx - 1.1 * r, cy + 0.8 * r}};
            else
                p = {{cx, cy - 1.3 * r}, {cx + 1.3 * r, cy}, {cx, cy + 1.3 * r}, {cx - 1.3 * r, cy}};
            auto inside = [&](double x, double y, double grow) {
                for (std::size_t i = 0; i < p.size(); ++i) {
                    const auto& a = p[i];
                    const auto& b = p[(i + 1) % p.size()];
                    const double ex = b.first - a.first, ey = b.second - a.second;
                    const double len = std::hypot(ex, ey);
                    if ((ex * (y - a.second) - ey * (x - a.first)) / len < -grow) return false;
                }
                return true;
            };
            const int xa = int(cx - 2 * r - 2), xb = int(cx + 2 * r + 2);
            const int ya = int(cy - 2 * r - 2), yb = int(cy + 2 * r + 2);
            for (int y = ya; y <= yb; ++y)
                for (int x = xa; x <= xb; ++x) {
                    if (inside(x + 0.5, y + 0.5, 0.0))
                        img.set(x, y, fill);
                    else if (inside(x + 0.5, y + 0.5, 1.2))
                        img.set(x, y, outline);
                }
            break;
        }
    }
}

void blit(Image& dst, const Image& src, int x, int y) {
    for (int v = 0; v < src.height; ++v)
        for (int u = 0; u < src.width; ++u) dst.set(x + u, y + v, src.get(u, v));
}

Image downsample(const Image& src, int factor) {
    CAVESIM_CHECK(factor >= 1, "downsample: factor must be at least 1, got " + std::to_string(factor));
    if (factor == 1) return src;
    Image out((src.width + factor - 1) / factor, (src.height + factor - 1) / factor);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            int sum[3] = {0, 0, 0}, n = 0;
            for (int v = y * factor; v < std::min(src.height, (y + 1) * factor); ++v)
                for (int u = x * factor; u < std::min(src.width, (x + 1) * factor); ++u) {
                    const Rgb c = src.get(u, v);
                    sum[0] += c.r, sum[1] += c.g, sum[2] += c.b, ++n;
                }
            out.set(x, y,
                    {std::uint8_t((sum[0] + n / 2) / n), std::uint8_t((sum[1] + n / 2) / n),
                     std::uint8_t((sum[2] + n / 2) / n)});
        }
    return out;
}

double pixelVariance(const Image& img) {
    if (img.pixels.empty()) return 0.0;
    double sum = 0.0, sum2 = 0.0;
    for (std::uint8_t p : img.pixels) {
        sum += p;
        sum2 += double(p) * p;
    }
    const double n = double(img.pixels.size());
    const double mean = sum / n;
    return std::max(0.0, sum2 / n - mean * mean);
}

std::size_t distinctColours(const Image& img) {
    std::unordered_set<std::uint32_t> seen;
    for (std::size_t n = 0; n + 2 < img.pixels.size(); n += 3)
        seen.insert(std::uint32_t(img.pixels[n]) << 16 | std::uint32_t(img.pixels[n + 1]) << 8 | img.pixels[n + 2]);
    return seen.size();
}

}  // namespace cavesim::render

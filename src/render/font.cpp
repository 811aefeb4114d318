// Text in DejaVu Sans (fonts-dejavu-core, found through fontconfig) drawn with Cairo: each string is
// rendered as an 8-bit coverage mask and blended into the RGB image, so the pictures keep their
// own raster code and get real, anti-aliased type. The layout keeps the metrics of a 6×8-pixel
// cell per scale step: a line is 8·scale pixels high with the baseline 7·scale below its top.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <cairo.h>

#include "core/check.h"
#include "render/image.h"

namespace cavesim::render {
namespace {

constexpr int kCellH = 8;
constexpr const char* kFamily = "DejaVu Sans";

double fontPixels(int scale) {
    return 9.0 * std::max(scale, 1);
}
double baseline(int scale) {
    return 7.0 * std::max(scale, 1);
}

using SurfacePtr = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using ContextPtr = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

/// The same font, size and rasterisation options for measuring and drawing (deterministic output).
void setFont(cairo_t* cr, int scale) {
    cairo_select_font_face(cr, kFamily, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, fontPixels(scale));
    cairo_font_options_t* o = cairo_font_options_create();
    cairo_font_options_set_antialias(o, CAIRO_ANTIALIAS_GRAY);
    cairo_font_options_set_hint_style(o, CAIRO_HINT_STYLE_SLIGHT);
    cairo_font_options_set_hint_metrics(o, CAIRO_HINT_METRICS_ON);
    cairo_set_font_options(cr, o);
    cairo_font_options_destroy(o);
}

/// Valid UTF-8 for Cairo: bytes of broken sequences become '?'.
std::string sanitise(const std::string& text) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size();) {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        int len = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
        bool ok = len > 0 && i + std::size_t(len) <= text.size();
        for (int k = 1; ok && k < len; ++k) ok = (static_cast<unsigned char>(text[i + k]) >> 6) == 2;
        if (ok && len == 1 && (c < 32 || c == 127)) ok = false;
        if (!ok) {
            out += '?';
            ++i;
            continue;
        }
        out.append(text, i, std::size_t(len));
        i += std::size_t(len);
    }
    return out;
}

double advance(const std::string& text, int scale) {
    static thread_local SurfacePtr surface(cairo_image_surface_create(CAIRO_FORMAT_A8, 1, 1), cairo_surface_destroy);
    static thread_local ContextPtr cr(cairo_create(surface.get()), cairo_destroy);
    setFont(cr.get(), scale);
    cairo_text_extents_t e;
    cairo_text_extents(cr.get(), text.c_str(), &e);
    return e.x_advance;
}

/// Coverage mask (0–255) of `text` with its top-left at the mask's (pad, pad).
struct Mask {
    int width = 0, height = 0, pad = 0;
    std::vector<std::uint8_t> alpha;
};
Mask renderMask(const std::string& text, int scale, int pad) {
    Mask m;
    m.pad = pad;
    m.width = int(std::ceil(advance(text, scale))) + 2 * pad + 2 * std::max(scale, 1);
    m.height = kCellH * std::max(scale, 1) + 3 * std::max(scale, 1) + 2 * pad;
    SurfacePtr surface(cairo_image_surface_create(CAIRO_FORMAT_A8, m.width, m.height), cairo_surface_destroy);
    CAVESIM_CHECK(cairo_surface_status(surface.get()) == CAIRO_STATUS_SUCCESS, "cannot create a text surface");
    ContextPtr cr(cairo_create(surface.get()), cairo_destroy);
    setFont(cr.get(), scale);
    cairo_move_to(cr.get(), pad, pad + baseline(scale));
    cairo_show_text(cr.get(), text.c_str());
    cairo_surface_flush(surface.get());
    const unsigned char* data = cairo_image_surface_get_data(surface.get());
    const int stride = cairo_image_surface_get_stride(surface.get());
    m.alpha.resize(std::size_t(m.width) * m.height);
    for (int y = 0; y < m.height; ++y)
        std::copy(data + std::size_t(y) * stride, data + std::size_t(y) * stride + m.width,
                  m.alpha.begin() + std::size_t(y) * m.width);
    return m;
}

void blendMask(Image& img, int x, int y, const Mask& m, Rgb c) {
    for (int v = 0; v < m.height; ++v)
        for (int u = 0; u < m.width; ++u) {
            const std::uint8_t a = m.alpha[std::size_t(v) * m.width + u];
            if (a == 0) continue;
            const int px = x - m.pad + u, py = y - m.pad + v;
            if (a == 255)
                img.set(px, py, c);
            else
                img.blend(px, py, c, a / 255.0);
        }
}

}  // namespace

int textWidth(const std::string& text, int scale) {
    return int(std::ceil(advance(sanitise(text), scale)));
}

int textHeight(int scale) {
    return kCellH * std::max(scale, 1);
}

int drawText(Image& img, int x, int y, const std::string& text, Rgb c, int scale) {
    const std::string t = sanitise(text);
    if (t.empty()) return x;
    blendMask(img, x, y, renderMask(t, scale, 0), c);
    return x + int(std::ceil(advance(t, scale)));
}

void drawTextAligned(Image& img, int x, int y, const std::string& text, Rgb c, int scale, Align align, bool halo,
                     Rgb haloColour) {
    const std::string t = sanitise(text);
    if (t.empty()) return;
    const int w = textWidth(t, scale);
    if (align == Align::kCentre)
        x -= w / 2;
    else if (align == Align::kRight)
        x -= w;
    const int r = halo ? std::max(1, scale / 2 + 1) : 0;
    const Mask m = renderMask(t, scale, r);
    if (halo) {
        // The glyphs' coverage grown by r pixels (square neighbourhood) under the text.
        Mask grown = m;
        for (int v = 0; v < m.height; ++v)
            for (int u = 0; u < m.width; ++u) {
                std::uint8_t best = 0;
                for (int dv = -r; dv <= r; ++dv)
                    for (int du = -r; du <= r; ++du) {
                        const int uu = u + du, vv = v + dv;
                        if (uu >= 0 && vv >= 0 && uu < m.width && vv < m.height)
                            best = std::max(best, m.alpha[std::size_t(vv) * m.width + uu]);
                    }
                grown.alpha[std::size_t(v) * m.width + u] = best;
            }
        blendMask(img, x, y, grown, haloColour);
    }
    blendMask(img, x, y, m, c);
}

}  // namespace cavesim::render

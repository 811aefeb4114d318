/// @file image.h
/// @brief RGB8 raster images and the drawing primitives used by every cavesim picture.
///
/// Pixel coordinates: x to the right, y downward, (0, 0) the top-left pixel. Integer arguments
/// (rectangles, text) address pixels; real arguments (lines, circles, markers) are continuous:
/// pixel (x, y) covers [x, x+1) × [y, y+1) and is centred at (x + 0.5, y + 0.5). Drawing outside
/// the image is clipped silently. Text is DejaVu Sans drawn with Cairo (UTF-8), anti-aliased, at a
/// size set by an integer scale: a line is 8·scale pixels high, the baseline 7·scale below its top.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace cavesim::render {

/// One 8-bit RGB colour.
struct Rgb {
    std::uint8_t r = 0, g = 0, b = 0;
    friend bool operator==(const Rgb& a, const Rgb& b) { return a.r == b.r && a.g == b.g && a.b == b.b; }
    friend bool operator!=(const Rgb& a, const Rgb& b) { return !(a == b); }
};

/// A width × height RGB image, rows top to bottom, 3 bytes per pixel.
struct Image {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> pixels;

    Image() = default;
    Image(int w, int h, Rgb fill = {255, 255, 255});

    bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
    Rgb get(int x, int y) const;
    /// Sets a pixel; ignored outside the image.
    void set(int x, int y, Rgb c);
    /// Mixes `c` over the pixel with opacity `alpha` in [0, 1].
    void blend(int x, int y, Rgb c, double alpha);
};

/// Linear mix of two colours, t in [0, 1].
Rgb mix(Rgb a, Rgb b, double t);
/// Multiplies a colour by `s` (clamped to [0, 255]).
Rgb scale(Rgb c, double s);

void fillRect(Image& img, int x0, int y0, int w, int h, Rgb c);
/// Outline of a rectangle, `thickness` pixels drawn inward.
void drawRect(Image& img, int x0, int y0, int w, int h, Rgb c, int thickness = 1);
/// Straight line (anti-aliased when thickness is 1).
void drawLine(Image& img, double x0, double y0, double x1, double y1, Rgb c, int thickness = 1);
/// Dashed line: `dash` pixels drawn, `gap` pixels skipped.
void drawDashedLine(Image& img, double x0, double y0, double x1, double y1, Rgb c, int dash = 6, int gap = 4,
                    int thickness = 1);
void fillCircle(Image& img, double cx, double cy, double radius, Rgb c);
/// Fills a simple polygon (pixel centres inside by the even-odd rule) with `c` at opacity `alpha`.
void fillPolygon(Image& img, const std::vector<std::pair<double, double>>& points, Rgb c, double alpha = 1.0);
void drawCircle(Image& img, double cx, double cy, double radius, Rgb c, int thickness = 1);

/// Marker shapes for sources, sinks and legends.
enum class Marker { kCircle, kSquare, kTriangle, kDiamond };
/// A filled marker of half-size `radius` px with a 1-px outline of colour `outline`.
void drawMarker(Image& img, double cx, double cy, double radius, Marker m, Rgb fill, Rgb outline);

/// Width in pixels of `text` (UTF-8) at integer `scale` (its advance, rounded up).
int textWidth(const std::string& text, int scale = 1);
/// Height in pixels of one line of text at `scale`.
int textHeight(int scale = 1);
/// Draws `text` with its top-left corner at (x, y); returns the x just after the text.
/// Bytes that are not valid UTF-8, and control characters, are drawn as '?'.
int drawText(Image& img, int x, int y, const std::string& text, Rgb c, int scale = 1);
/// Horizontal alignment for drawTextAligned.
enum class Align { kLeft, kCentre, kRight };
/// Draws text anchored at x by `align`, top at y; with `halo` a 1-px outline of `haloColour` keeps
/// it readable over busy pictures.
void drawTextAligned(Image& img, int x, int y, const std::string& text, Rgb c, int scale, Align align,
                     bool halo = false, Rgb haloColour = {255, 255, 255});

/// Copies `src` into `dst` with its top-left corner at (x, y), clipped.
void blit(Image& dst, const Image& src, int x, int y);

/// The image reduced by an integer `factor` ≥ 1: each output pixel is the mean of a factor × factor
/// block (partial blocks at the right and bottom edges average what they cover).
Image downsample(const Image& src, int factor);

/// Mean over pixels and channels of the squared deviation from the mean (0 for a blank image).
double pixelVariance(const Image& img);
/// Number of distinct colours (tests, sanity checks).
std::size_t distinctColours(const Image& img);

}  // namespace cavesim::render

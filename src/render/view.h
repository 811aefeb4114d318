/// @file view.h
/// @brief The one camera code of every cavesim picture: views of the rock block, their framing in
/// a picture of a given width, and the annotations every picture shares.
///
/// Views: the plan (from above: x right, y up), two sides (x–z seen from the y = 0 face, y–z seen
/// from the x = max face; z up) and a perspective from the front-left, above. A `Frame` places
/// the block's projection in a viewport with room for a title above, axes in metres to the left
/// and below, and legend rows (the footer) under it. The frame depends only on the view, the
/// block and the width, so the 2D figures of the voxel state and the ray-traced views of the cave
/// (src/mesh/cave_pictures.h) line up pixel for pixel when drawn at the same width.
///
/// Space: world coordinates are metres, the block spans [0, n·voxelSize] on each axis and voxel
/// (i, j, k) is centred at ((i, j, k) + 0.5)·voxelSize. Pixel coordinates follow image.h.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "core/grid.h"
#include "core/vec3.h"
#include "render/image.h"
#include "sim/domain.h"

namespace cavesim::render {

/// Projection of world space (metres) onto pixels: orthographic or perspective.
struct Camera {
    bool perspective = false;
    Vec3d eye{0, 0, 0};  ///< perspective: centre of projection; orthographic: a point on the central ray
    Vec3d right{1, 0, 0}, up{0, 1, 0}, forward{0, 0, -1};  ///< orthonormal; forward = viewing direction
    double scale = 1.0;         ///< orthographic: pixels per metre; perspective: focal length in pixels
    double cx = 0.0, cy = 0.0;  ///< pixel position of the central ray

    /// A world point on the picture: pixel position and depth (metres along `forward` from `eye`;
    /// perspective points with depth <= 0 are behind the eye and their x, y are meaningless).
    struct Projected {
        double x = 0, y = 0, depth = 0;
    };
    Projected project(const Vec3d& world) const;
    /// The ray through continuous pixel position (px, py): origin and unit direction. Orthographic
    /// rays start on the plane through `eye` normal to `forward`.
    void ray(double px, double py, Vec3d& origin, Vec3d& direction) const;
};

enum class View { kPlan, kSideXZ, kSideYZ, kPerspective };

/// "plan", "side_xz", "side_yz", "perspective" (file stems of the pictures).
std::string viewStem(View view);

/// Layout of one picture of the block.
struct Frame {
    View view = View::kPlan;
    int width = 0, height = 0;           ///< the whole picture, footer included
    int vx = 0, vy = 0, vw = 0, vh = 0;  ///< viewport holding the block's projection
    int footerY = 0;                     ///< top row of the footer (legend rows)
    int footerRows = 0;
    int textScale = 1;  ///< font scale (glyph cell 6×8 px times this)
    Camera camera;
    Vec3d blockMax{0, 0, 0};            ///< the block spans [0, blockMax] metres
    double depthMin = 0, depthMax = 1;  ///< depth range of the block along the view, metres
    double voxelSize = 1.0;
    Dims dims;
};

/// Frames the block of `dims` voxels of edge `voxelSize` metres for `view` in a picture
/// `width` pixels wide with `footerRows` legend rows. The picture's height follows from the
/// block's proportions (the viewport is at most 1.25 × width tall).
/// @throw InternalError if width < 64, voxelSize <= 0 or dims has a zero extent
Frame makeFrame(View view, const Dims& dims, double voxelSize, int width, int footerRows = 2);

/// Height in pixels of one footer row.
int footerRowHeight(int textScale);
/// Top pixel row of footer row `row`.
int footerRowY(const Frame& frame, int row);
/// A white picture of the frame's size with the block's faces in the viewport tinted as rock.
Image makeCanvas(const Frame& frame);

/// Orthographic views: the (u, v) cell grid of the view plane (plan: i, j; side_xz: i, k;
/// side_yz: j, k), u to the right and v up.
struct CellGrid {
    int nu = 0, nv = 0;
};
CellGrid cellGrid(const Frame& frame);
/// Fills the viewport with a colour per (u, v) cell (orthographic views only), nearest cell per
/// pixel centre.
void fillCells(Image& img, const Frame& frame, const std::function<Rgb(int u, int v)>& colour);
/// Draws the boundary between cells where `inside(u, v)` changes (and around inside cells on the
/// block's rim), `thickness` px (orthographic views only).
void outlineCells(Image& img, const Frame& frame, const std::function<bool(int u, int v)>& inside, Rgb c,
                  int thickness = 1);
/// World position (metres) of continuous cell coordinate (u, v) on the block's face nearest the
/// viewer (orthographic views; cell (u, v) spans [u, u+1) × [v, v+1)).
Vec3d viewPlanePoint(const Frame& frame, double u, double v);

// --- Annotations -------------------------------------------------------------------------------

/// Title (large) and subtitle above the viewport.
void drawTitle(Image& img, const Frame& frame, const std::string& title, const std::string& subtitle = {});
/// Axes in metres: tick marks and labels along the bottom and left of the viewport with the axis
/// names (orthographic); ticks and labels along three edges of the block (perspective).
void drawAxes(Image& img, const Frame& frame);
/// The block's outline. Orthographic: the viewport rectangle. Perspective: the 12 edges; with
/// `depth` (the viewport's depth buffer, vw × vh, +inf where empty) parts hidden behind the cave
/// are drawn faint, and edges on the far side of the block dashed.
void drawBlockOutline(Image& img, const Frame& frame, const std::vector<float>* depth = nullptr);
/// Scale bar (a round length near a fifth of the block) with its length in metres, its left end
/// at (x, y); returns the x just right of its label. In the perspective view the bar is measured
/// at the depth of the block's centre.
int drawScaleBar(Image& img, const Frame& frame, int x, int y);
/// Sources (red circles, labelled S1, S2, ... in scenario order) and sinks (blue squares) at the
/// centre of their voxels, with the outline of their voxel box when it is larger than a marker.
void drawSourcesAndSinks(Image& img, const Frame& frame, const Dims& dims,
                         const std::vector<std::vector<std::size_t>>& sourceVoxels,
                         const std::vector<std::vector<std::size_t>>& sinkVoxels);

/// One legend entry: a marker, a colour swatch or a line sample, then text.
struct LegendEntry {
    enum class Kind { kMarker, kSwatch, kLine } kind = Kind::kSwatch;
    Rgb colour{0, 0, 0};
    Marker marker = Marker::kCircle;
    std::string text;
};
/// Draws entries left to right in footer row `row`, starting at x; returns the x after the last.
int drawLegend(Image& img, const Frame& frame, int row, int x, const std::vector<LegendEntry>& entries);
/// The standard first footer row: scale bar, source and sink markers, then `extra` entries.
void drawStandardLegend(Image& img, const Frame& frame, const std::vector<LegendEntry>& extra = {});
/// A horizontal colour bar in footer row `row`: `label` on the left, the ramp `colour(t)`,
/// t in [0, 1], mapping [lo, hi] (log10 spacing when `logScale`, lo > 0), with tick values.
void drawColourBar(Image& img, const Frame& frame, int row, const std::function<Rgb(double)>& colour, double lo,
                   double hi, bool logScale, const std::string& label);
/// A short text in the middle of the viewport on a white box (e.g. "no cave").
void drawNote(Image& img, const Frame& frame, const std::string& text);

/// A round number (1, 2 or 5 × 10^k) near `x` > 0.
double niceNumber(double x);
/// Formats a length in metres compactly ("12", "2.5", "0.25").
std::string formatMetres(double metres);
/// Formats a value compactly with about 3 significant digits ("0.0012", "1.5e+06").
std::string formatValue(double value);

}  // namespace cavesim::render

// Ray-traced pictures of the cave: OpenVDB LevelSetRayIntersector through render/view.h cameras.
#include "mesh/cave_pictures.h"

#include <openvdb/math/Ray.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/RayIntersector.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "core/check.h"
#include "core/timer.h"
#include "mesh/cave_level_set.h"
#include "render/colormap.h"
#include "render/png_io.h"
#include "sim/cave.h"

namespace cavesim::mesh {
namespace {

using render::Frame;
using render::Image;
using render::Rgb;

constexpr float kMiss = std::numeric_limits<float>::infinity();

// What each ray found: depth along the view (metres, kMiss where it found nothing) and the
// surface normal there.
struct GBuffer {
    int w = 0, h = 0;
    std::vector<float> depth;
    std::vector<std::array<float, 3>> normal;
};

// Where a ray can meet the surface: the depth range (metres along the view) of the boxes of the
// cave's boundary voxels grown by `margin` metres that cover each viewport pixel; near = kMiss
// where no box covers it. The surface lies within `margin` of a boundary voxel's cube, so rays
// start just before it and stop just after, and pixels no box covers are not traced at all.
struct DepthRange {
    std::vector<float> near, far;
};

DepthRange depthRanges(const Frame& f, const Grid3<std::uint8_t>& mask, double margin) {
    DepthRange range;
    range.near.assign(std::size_t(f.vw) * f.vh, kMiss);
    range.far.assign(std::size_t(f.vw) * f.vh, -kMiss);
    const Dims& d = mask.dims;
    const double h = f.voxelSize;
    struct Rect {
        int x0, y0, x1, y1;  // inclusive pixel range in the viewport
        float near, far;
    };
    std::vector<Rect> rects;
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                if (!mask.at(i, j, k)) continue;
                bool boundary = false;
                for (const NeighbourOffset& o : faceNeighbours()) {
                    const int a = i + o.di, b = j + o.dj, c = k + o.dk;
                    if (!d.contains(a, b, c) || !mask.at(a, b, c)) boundary = true;
                }
                if (!boundary) continue;
                double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300, near = 1e300, far = -1e300;
                for (int corner = 0; corner < 8; ++corner) {
                    const Vec3d w{(corner & 1) ? (i + 1) * h + margin : i * h - margin,
                                  (corner & 2) ? (j + 1) * h + margin : j * h - margin,
                                  (corner & 4) ? (k + 1) * h + margin : k * h - margin};
                    const auto p = f.camera.project(w);
                    x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
                    near = std::min(near, p.depth), far = std::max(far, p.depth);
                }
                Rect r{std::max(0, int(std::floor(x0)) - f.vx),
                       std::max(0, int(std::floor(y0)) - f.vy),
                       std::min(f.vw - 1, int(std::ceil(x1)) - f.vx),
                       std::min(f.vh - 1, int(std::ceil(y1)) - f.vy),
                       float(near),
                       float(far)};
                if (r.x0 <= r.x1 && r.y0 <= r.y1) rects.push_back(r);
            }
    // Rows in parallel bands, each band reducing over all rectangles (min and max: any order).
    tbb::parallel_for(tbb::blocked_range<int>(0, f.vh, 16), [&](const tbb::blocked_range<int>& rows) {
        for (const Rect& r : rects) {
            const int ya = std::max(r.y0, rows.begin()), yb = std::min(r.y1, rows.end() - 1);
            for (int y = ya; y <= yb; ++y) {
                float* n = range.near.data() + std::size_t(y) * f.vw;
                float* fa = range.far.data() + std::size_t(y) * f.vw;
                for (int x = r.x0; x <= r.x1; ++x) {
                    n[x] = std::min(n[x], r.near);
                    fa[x] = std::max(fa[x], r.far);
                }
            }
        }
    });
    return range;
}

using Intersector = openvdb::tools::LevelSetRayIntersector<openvdb::FloatGrid>;
using Sampler = openvdb::tools::GridSampler<openvdb::FloatGrid::ConstAccessor, openvdb::tools::BoxSampler>;

// Per-thread tracing state: the intersector and a trilinear sampler of the level set (the
// intersector's own normal is the gradient at the nearest voxel: faceted).
struct Tracer {
    Intersector inter;
    openvdb::FloatGrid::ConstAccessor acc;
    Sampler sampler;
    double step;  // central-difference step, metres
    Tracer(const Intersector& proto, const openvdb::FloatGrid& grid)
        : inter(proto), acc(grid.getConstAccessor()), sampler(acc, grid.transform()), step(0.5 * grid.voxelSize()[0]) {}
    openvdb::Vec3d normal(const openvdb::Vec3d& p) const {
        openvdb::Vec3d n;
        for (int a = 0; a < 3; ++a) {
            openvdb::Vec3d lo = p, hi = p;
            lo[a] -= step;
            hi[a] += step;
            n[a] = double(sampler.wsSample(hi)) - double(sampler.wsSample(lo));
        }
        const double len = n.length();
        return len > 0 ? n / len : openvdb::Vec3d(0, 0, 1);
    }
};

// Traces the ray of viewport pixel (x, y) between the depths of `range`; fills g on a hit.
void tracePixel(const Frame& f, const DepthRange& range, Tracer& tracer, GBuffer& g, int x, int y) {
    const std::size_t id = std::size_t(y) * g.w + x;
    g.depth[id] = kMiss;
    if (range.near[id] == kMiss) return;
    const render::Camera& cam = f.camera;
    const double slack = 0.5 * f.voxelSize;
    Vec3d o, d;
    cam.ray(f.vx + x + 0.5, f.vy + y + 0.5, o, d);
    double t0 = 0.0, t1 = 0.0;
    if (cam.perspective) {
        const double cosine = std::max(1e-6, d[0] * cam.forward[0] + d[1] * cam.forward[1] + d[2] * cam.forward[2]);
        t0 = std::max(0.0, double(range.near[id]) / cosine - slack);
        t1 = double(range.far[id]) / cosine + slack;
    } else {
        t0 = double(range.near[id]) - slack;  // the origin lies on the plane of depth 0
        t1 = double(range.far[id]) + slack;
    }
    openvdb::math::Ray<double> ray(openvdb::Vec3d(o[0], o[1], o[2]), openvdb::Vec3d(d[0], d[1], d[2]), t0, t1);
    openvdb::Vec3d hit;
    if (!tracer.inter.intersectsWS(ray, hit)) return;
    g.depth[id] = float((hit[0] - cam.eye[0]) * cam.forward[0] + (hit[1] - cam.eye[1]) * cam.forward[1] +
                        (hit[2] - cam.eye[2]) * cam.forward[2]);
    const openvdb::Vec3d n = tracer.normal(hit);
    g.normal[id] = {float(n[0]), float(n[1]), float(n[2])};
}

// Ray-traces the viewport, coarse to fine. Rays first go through every fourth pixel of every
// fourth row; then, at spacing 2 and 1, a pixel between traced ones is interpolated when they
// all hit at nearly the same depth with nearly the same normal (a smooth surface), left empty
// when they all missed and they are too close together for any channel to fit between them,
// and traced otherwise (silhouettes, creases, thin tubes).
GBuffer traceViewport(const Frame& f, const detail::CaveLevelSet& ls, const Grid3<std::uint8_t>& mask) {
    GBuffer g;
    g.w = f.vw;
    g.h = f.vh;
    g.depth.assign(std::size_t(g.w) * g.h, kMiss);
    g.normal.assign(std::size_t(g.w) * g.h, {0.f, 0.f, 0.f});
    if (!ls.grid) return g;
    // The surface keeps within the iso offset plus three quarters of a voxel of the cave voxels'
    // cubes (the net lies inside them, the curvature flow fills concave corners by less).
    const double margin = std::min(1.5 * f.voxelSize, ls.isoValue + 0.85 * f.voxelSize);
    const DepthRange range = depthRanges(f, mask, margin);
    const Intersector prototype(*ls.grid, float(ls.isoValue));
    // Pixel size in metres at the surface (orthographic: exact; perspective: at the block's near
    // side, the largest magnification).
    const double pixelMetres = f.camera.perspective ? f.depthMin / f.camera.scale : 1.0 / f.camera.scale;
    // The thinnest channel is a tube of the net's radius: about 0.9 voxel across.
    const double thinnest = 0.9 * f.voxelSize;
    auto onGrid = [&](int x, int y, int step) {
        return (x % step == 0 || x == g.w - 1) && (y % step == 0 || y == g.h - 1);
    };
    tbb::parallel_for(tbb::blocked_range<int>(0, g.h, 16), [&](const tbb::blocked_range<int>& rows) {
        Tracer tracer(prototype, *ls.grid);  // one per task: accessors are not thread-safe
        for (int y = rows.begin(); y < rows.end(); ++y)
            for (int x = 0; x < g.w; ++x)
                if (onGrid(x, y, 4)) tracePixel(f, range, tracer, g, x, y);
    });
    for (int step : {2, 1}) {
        const bool skipEmpty = 2.0 * step * pixelMetres * 2.0 <= thinnest;
        const float depthTolerance = float(std::max(2.0 * step * pixelMetres, 0.1 * f.voxelSize));
        tbb::parallel_for(tbb::blocked_range<int>(0, g.h, 16), [&](const tbb::blocked_range<int>& rows) {
            Tracer tracer(prototype, *ls.grid);
            for (int y = rows.begin(); y < rows.end(); ++y)
                for (int x = 0; x < g.w; ++x) {
                    if (!onGrid(x, y, step) || onGrid(x, y, 2 * step)) continue;
                    // The traced pixels around (x, y): left/right, above/below, or four corners.
                    const bool offX = !(x % (2 * step) == 0 || x == g.w - 1);
                    const bool offY = !(y % (2 * step) == 0 || y == g.h - 1);
                    int nx[4], ny[4], count = 0;
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dx = -1; dx <= 1; ++dx) {
                            if ((dx != 0) != offX || (dy != 0) != offY) continue;
                            nx[count] = std::min(x + dx * step, g.w - 1), ny[count] = std::min(y + dy * step, g.h - 1);
                            ++count;
                        }
                    bool inside = true;
                    for (int c = 0; c < count; ++c) inside = inside && nx[c] >= 0 && ny[c] >= 0;
                    const std::size_t id = std::size_t(y) * g.w + x;
                    if (!inside || range.near[id] == kMiss) {
                        tracePixel(f, range, tracer, g, x, y);
                        continue;
                    }
                    int hits = 0;
                    float dmin = kMiss, dmax = -kMiss;
                    std::array<float, 3> nsum{0.f, 0.f, 0.f};
                    double dsum = 0.0;
                    float minDot = 1.f;
                    std::array<float, 3> first{0.f, 0.f, 0.f};
                    for (int c = 0; c < count; ++c) {
                        const std::size_t n = std::size_t(ny[c]) * g.w + nx[c];
                        if (g.depth[n] == kMiss) continue;
                        const auto& nn = g.normal[n];
                        if (hits == 0) first = nn;
                        ++hits;
                        dmin = std::min(dmin, g.depth[n]), dmax = std::max(dmax, g.depth[n]);
                        dsum += g.depth[n];
                        for (int a = 0; a < 3; ++a) nsum[a] += nn[a];
                        minDot = std::min(minDot, nn[0] * first[0] + nn[1] * first[1] + nn[2] * first[2]);
                    }
                    if (hits == 0 && skipEmpty) continue;  // stays empty
                    if (hits == count && dmax - dmin <= depthTolerance && minDot > 0.97f) {
                        g.depth[id] = float(dsum / hits);
                        const float len = std::sqrt(nsum[0] * nsum[0] + nsum[1] * nsum[1] + nsum[2] * nsum[2]);
                        g.normal[id] = {nsum[0] / len, nsum[1] / len, nsum[2] / len};
                        continue;
                    }
                    tracePixel(f, range, tracer, g, x, y);
                }
        });
    }
    return g;
}

std::string depthLabel(render::View view) {
    switch (view) {
        case render::View::kPlan:
            return "depth below top (m)";
        case render::View::kSideXZ:
            return "distance from y = 0 face (m)";
        case render::View::kSideYZ:
            return "distance from x = max face (m)";
        default:
            return "elevation above block base (m)";
    }
}

std::string viewTitle(render::View view) {
    switch (view) {
        case render::View::kPlan:
            return "Cave, plan view (from above)";
        case render::View::kSideXZ:
            return "Cave, side view x-z (looking north, +y)";
        case render::View::kSideYZ:
            return "Cave, side view y-z (looking west, -x)";
        default:
            return "Cave, perspective from the front left";
    }
}

// Shades the hits into the canvas: depth colour, diffuse key light and head light, a little
// specular, dark outlines where the depth jumps (silhouettes, one tube in front of another).
void shade(Image& img, const Frame& f, const GBuffer& g) {
    const render::Camera& cam = f.camera;
    const double range = std::max(f.depthMax - f.depthMin, 1e-12);
    auto comb = [](const Vec3d& a, double sa, const Vec3d& b, double sb, const Vec3d& c, double sc) {
        Vec3d r{a[0] * sa + b[0] * sb + c[0] * sc, a[1] * sa + b[1] * sb + c[1] * sc,
                a[2] * sa + b[2] * sb + c[2] * sc};
        const double n = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
        return Vec3d{r[0] / n, r[1] / n, r[2] / n};
    };
    // Key light from the upper left, toward the viewer.
    const Vec3d light = comb(cam.right, -0.45, cam.up, 0.6, cam.forward, -0.66);
    const double jump = 1.5 * f.voxelSize;
    tbb::parallel_for(tbb::blocked_range<int>(0, g.h, 16), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y)
            for (int x = 0; x < g.w; ++x) {
                const std::size_t id = std::size_t(y) * g.w + x;
                const float d = g.depth[id];
                if (d == kMiss) {
                    // Outline the cave from outside too (a 1-px dark rim on the rock).
                    bool rim = false;
                    for (int k = 0; k < 4 && !rim; ++k) {
                        const int nx = x + (k == 0) - (k == 1), ny = y + (k == 2) - (k == 3);
                        if (nx >= 0 && ny >= 0 && nx < g.w && ny < g.h && g.depth[std::size_t(ny) * g.w + nx] != kMiss)
                            rim = true;
                    }
                    if (rim) img.blend(f.vx + x, f.vy + y, Rgb{40, 36, 40}, 0.45);
                    continue;
                }
                Vec3d dir;
                Vec3d o;
                cam.ray(f.vx + x + 0.5, f.vy + y + 0.5, o, dir);
                const auto& nf = g.normal[id];
                const Vec3d n{nf[0], nf[1], nf[2]};
                const double ndl = std::max(0.0, n[0] * light[0] + n[1] * light[1] + n[2] * light[2]);
                const double head = std::max(0.0, -(n[0] * dir[0] + n[1] * dir[1] + n[2] * dir[2]));
                const Vec3d half = comb(light, 1.0, dir, -1.0, dir, 0.0);
                const double spec = std::pow(std::max(0.0, n[0] * half[0] + n[1] * half[1] + n[2] * half[2]), 40.0);
                // Perspective: colour by elevation (viridis, block base to top), what a geologist
                // reads as depth; orthographic views: by distance along the view.
                Rgb base;
                if (cam.perspective) {
                    const double along = double(d) / std::max(1e-12, dot(dir, cam.forward));
                    base = render::viridis((o[2] + along * dir[2]) / std::max(f.blockMax[2], 1e-12));
                } else {
                    base = render::depthRamp(std::clamp((double(d) - f.depthMin) / range, 0.0, 1.0));
                }
                Rgb c = render::scale(base, 0.28 + 0.55 * ndl + 0.32 * head);
                c = render::mix(c, render::colours::kWhite, 0.22 * spec);
                // Outline where a neighbour is empty or much farther away.
                bool edge = false;
                for (int k = 0; k < 4 && !edge; ++k) {
                    const int nx = x + (k == 0) - (k == 1), ny = y + (k == 2) - (k == 3);
                    if (nx < 0 || ny < 0 || nx >= g.w || ny >= g.h) continue;
                    const float dn = g.depth[std::size_t(ny) * g.w + nx];
                    if (dn == kMiss || dn - d > jump) edge = true;
                }
                if (edge) c = render::mix(c, Rgb{30, 26, 30}, 0.7);
                img.set(f.vx + x, f.vy + y, c);
            }
    });
}

Image renderView(const Cave& cave, render::View view, int width, const detail::CaveLevelSet& ls,
                 const Grid3<std::uint8_t>& mask, long caveVoxels) {
    const Frame f = render::makeFrame(view, cave.dims(), cave.voxelSize, width, 2);
    Image img = render::makeCanvas(f);
    const GBuffer g = traceViewport(f, ls, mask);
    shade(img, f, g);
    render::drawBlockOutline(img, f, &g.depth);
    render::drawAxes(img, f);
    render::drawSourcesAndSinks(img, f, cave.dims(), cave.sourceVoxels, cave.sinkVoxels);
    char sub[200];
    std::snprintf(sub, sizeof sub, "%d x %d x %d voxels of %s m; %ld cave voxels, smooth surface", cave.dims().nx,
                  cave.dims().ny, cave.dims().nz, render::formatMetres(cave.voxelSize).c_str(), caveVoxels);
    render::drawTitle(
        img, f, cave.dims().ny == 1 && view == render::View::kSideXZ ? "Cave, the 2D section x-z" : viewTitle(view),
        sub);
    render::drawStandardLegend(img, f);
    if (f.camera.perspective)
        render::drawColourBar(img, f, 1, render::viridis, 0.0, f.blockMax[2], false, "elevation above block base (m)");
    else
        render::drawColourBar(img, f, 1, render::depthRamp, f.depthMin, f.depthMax, false, depthLabel(view));
    if (!ls.grid) render::drawNote(img, f, "no cave");
    return img;
}

}  // namespace

namespace {

std::array<render::Image, 4> renderViews(const Cave& cave, int width, const detail::CaveLevelSet& ls) {
    const Grid3<std::uint8_t>& mask = cave.mask;
    long caveVoxels = 0;
    for (std::uint8_t v : mask.data) caveVoxels += v ? 1 : 0;
    std::array<render::Image, 4> out;
    for (std::size_t v = 0; v < kCaveViews.size(); ++v)
        out[v] = renderView(cave, kCaveViews[v], width, ls, mask, caveVoxels);
    return out;
}

void checkWidth(int width) {
    CAVESIM_CHECK(width >= 64 && width <= 16384, "picture width must be in [64, 16384], got " + std::to_string(width));
}

// A 2D section (one voxel thick in y) is shown only as itself: the x–z view. Its plan is a line,
// and the y–z and perspective views show the slab's edge.
bool viewApplies(const Cave& cave, render::View view) {
    return cave.dims().ny != 1 || view == render::View::kSideXZ;
}

void writeViews(const Cave& cave, const std::array<render::Image, 4>& images, const std::string& imagesDir) {
    std::error_code ec;
    std::filesystem::create_directories(imagesDir, ec);
    if (ec) throw RuntimeError("cannot create " + imagesDir + ": " + ec.message());
    // PNG compression is the costly part of writing: the four files in parallel.
    tbb::parallel_for(std::size_t(0), kCaveViews.size(), [&](std::size_t v) {
        if (!viewApplies(cave, kCaveViews[v])) return;
        render::writePng((std::filesystem::path(imagesDir) / (render::viewStem(kCaveViews[v]) + ".png")).string(),
                         images[v]);
    });
}

}  // namespace

std::array<render::Image, 4> renderCaveViews(const Cave& cave, int width, const MeshOptions& options) {
    checkWidth(width);
    // The level set at the mesh's iso value, so the pictures show the surface of cave.obj.
    return renderViews(cave, width, detail::buildCaveSurface(cave.mask, cave.voxelSize, options, false).levelSet);
}

void writeCavePictures(const Cave& cave, const std::string& imagesDir, int width) {
    writeViews(cave, renderCaveViews(cave, width), imagesDir);
}

MeshStats writeCaveMeshAndPictures(const Cave& cave, const std::string& dir, const std::string& imagesDir, int width,
                                   const MeshOptions& options, SurfaceMesh* built) {
    const Stopwatch watch;
    checkWidth(width);
    detail::validateMeshOptions(options, cave.voxelSize);
    const detail::CaveSurface surface = detail::buildCaveSurface(cave.mask, cave.voxelSize, options, true);
    MeshStats stats = detail::writeMeshOutputs(surface.mesh, cave.mask, cave.voxelSize, dir, options);
    if (built) *built = toSurfaceMesh(surface.mesh);
    writeViews(cave, renderViews(cave, width, surface.levelSet), imagesDir);
    stats.seconds = watch.seconds();
    return stats;
}

}  // namespace cavesim::mesh

#include "speleo/decorate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "core/timer.h"
#include "formats/mesh_formats.h"
#include "render/png_io.h"

namespace cavesim::speleo {
namespace {

Vec3d unit3(const Vec3d& a) {
    const double l = std::sqrt(dot(a, a));
    return l > 0 ? Vec3d{a[0] / l, a[1] / l, a[2] / l} : Vec3d{0, 0, 1};
}

std::string frameName(const char* stem, int frame) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "images/speleo_%s_%02d.png", stem, frame);
    return buf;
}

/// A camera inside the cave looking at the stalactite from the side, a little below its tip.
render::Camera closeUpCamera(const DecorationField& f, const Stalactite& st, int width, int height, double& reach) {
    const double size = std::max({st.length, 2 * st.radius, 0.1});
    const Vec3d target{st.tip[0], st.tip[1], st.tip[2] + 0.3 * st.length};
    render::Camera cam;
    cam.perspective = true;
    // Back away along the direction with the most air, trying eight azimuths.
    double bestD = 0;
    Vec3d bestDir{1, 0, 0};
    for (int k = 0; k < 8; ++k) {
        const double a = k * 3.14159265358979323846 / 4;
        const Vec3d dir = unit3({std::cos(a), std::sin(a), -0.35});
        double d = 0;
        // From just outside the stalactite (the target is on its axis, inside it) into the air.
        const double t0 = st.radius + 2 * f.voxelSize();
        for (double t = t0; t <= t0 + 4 * size + 0.5; t += 0.5 * f.voxelSize()) {
            const Vec3d p{target[0] + t * dir[0], target[1] + t * dir[1], target[2] + t * dir[2]};
            if (f.distance(p) >= -f.voxelSize()) break;
            d = t;
        }
        if (d > bestD + 1e-9) bestD = d, bestDir = dir;
    }
    const double back = std::max(st.radius + 2 * f.voxelSize(), 0.9 * bestD);
    reach = back + 2 * size;
    cam.eye = {target[0] + back * bestDir[0], target[1] + back * bestDir[1], target[2] + back * bestDir[2]};
    cam.forward = unit3(sub(target, cam.eye));
    cam.right = unit3(cross(cam.forward, {0, 0, 1}));
    cam.up = cross(cam.right, cam.forward);
    cam.scale = 0.9 * width;  // ~58° field of view
    cam.cx = 0.5 * width;
    cam.cy = 0.5 * height;
    return cam;
}

/// The close-up's subject: the longest grown speleothem (`st` is ordered by grown length) when
/// it grew at least two voxels; otherwise the most slender stalactite (length over radius) at
/// least two voxels long, so a metre-wide convex bulge of the cave's own ceiling is not chosen.
const Stalactite& closeUpSubject(const std::vector<Stalactite>& st, double voxel) {
    if (st[0].grownLength >= 2 * voxel) return st[0];
    std::size_t best = 0;
    double bestRatio = -1;
    for (std::size_t i = 0; i < st.size(); ++i) {
        if (st[i].length < 2 * voxel) continue;
        const double ratio = st[i].length / std::max(st[i].radius, voxel);
        if (ratio > bestRatio) bestRatio = ratio, best = i;
    }
    return st[best];
}

}  // namespace

render::Image renderMesh(const mesh::TriangleMesh& m, const render::Camera& cam, int width, int height, double zLow,
                         double zHigh) {
    render::Image img(width, height, {250, 250, 248});
    std::vector<float> depth(std::size_t(width) * height, std::numeric_limits<float>::infinity());
    std::vector<render::Camera::Projected> p(m.vertices.size());
    for (std::size_t i = 0; i < m.vertices.size(); ++i) p[i] = cam.project(m.vertices[i]);
    const Vec3d light = unit3({-0.3, -0.5, 0.8});
    for (const auto& t : m.triangles) {
        const auto &a = p[t[0]], &b = p[t[1]], &c = p[t[2]];
        if (a.depth <= 1e-3 || b.depth <= 1e-3 || c.depth <= 1e-3) continue;
        const Vec3d n = unit3(cross(sub(m.vertices[t[1]], m.vertices[t[0]]), sub(m.vertices[t[2]], m.vertices[t[0]])));
        const double head = std::abs(dot(n, cam.forward)), diffuse = std::abs(dot(n, light));
        const double zMid = (m.vertices[t[0]][2] + m.vertices[t[1]][2] + m.vertices[t[2]][2]) / 3;
        const double h = std::clamp((zMid - zLow) / std::max(zHigh - zLow, 1e-9), 0.0, 1.0);
        const render::Rgb base = render::mix({196, 160, 112}, {232, 222, 200}, h);  // ochre low, pale high
        const render::Rgb col = render::scale(base, 0.25 + 0.45 * diffuse + 0.35 * head);
        const int x0 = std::max(0, int(std::floor(std::min({a.x, b.x, c.x})))),
                  x1 = std::min(width - 1, int(std::ceil(std::max({a.x, b.x, c.x}))));
        const int y0 = std::max(0, int(std::floor(std::min({a.y, b.y, c.y})))),
                  y1 = std::min(height - 1, int(std::ceil(std::max({a.y, b.y, c.y}))));
        const double area = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
        if (std::abs(area) < 1e-12) continue;
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const double px = x + 0.5, py = y + 0.5;
                const double w0 = ((b.x - px) * (c.y - py) - (c.x - px) * (b.y - py)) / area;
                const double w1 = ((c.x - px) * (a.y - py) - (a.x - px) * (c.y - py)) / area;
                const double w2 = 1 - w0 - w1;
                if (w0 < 0 || w1 < 0 || w2 < 0) continue;
                const float d = float(w0 * a.depth + w1 * b.depth + w2 * c.depth);
                float& z = depth[std::size_t(y) * width + x];
                if (d < z) {
                    z = d;
                    img.set(x, y, col);
                }
            }
    }
    return img;
}

DecorationSummary decorateCave(const Cave& cave, const SpeleothemOptions& o, const std::string& dir, int imageWidth,
                               bool images, bool meshes, const ProgressFn& progress) {
    Stopwatch watch;
    DecorationSummary sum;
    sum.voxelSize = o.voxelSize;
    namespace fs = std::filesystem;
    const mesh::TriangleMesh caveMesh = mesh::buildCaveMesh(cave.mask, cave.voxelSize);
    if (caveMesh.triangles.empty()) {
        sum.emptyCave = true;
        sum.note = "the cave is empty: no surface to decorate";
        return sum;
    }
    DecorationField field = fieldFromMesh(caveMesh, o.voxelSize);
    addCeilingRoughness(field, o.roughness, o.roughnessScale, o.seed);
    const DecorationField original = field;  // the ceiling before growth, to measure what grew

    const int frames = images ? o.frames : 0;
    std::vector<double> frameYears;
    for (int k = 1; k < frames; ++k) frameYears.push_back(o.years * k / (frames - 1));
    // Frames are rendered after growth from stored meshes (close-up on the final longest stalactite).
    std::vector<DecorationField> frameFields;
    std::vector<double> frameTimes;
    const GrowthResult g =
        grow(field, o, frameYears, [&](double years, const DecorationField& f, const std::vector<Stalactite>&) {
            if (int(frameFields.size()) >= frames) return;
            frameFields.push_back(f);
            frameTimes.push_back(years);
        }, progress);
    sum.stalactites = g.stalactites;
    measureGrowth(original, sum.stalactites);
    sum.steps = g.steps;
    sum.years = g.years;
    if (g.years < o.years - 1e-9) {
        // Growth stops only when nothing moves; such a surface stays as it is for the rest of the time.
        sum.note = (g.steps == 0 ? std::string("nothing grows")
                                 : "nothing grows after year " + std::to_string(long(std::lround(g.years)))) +
                   ": no ceiling drip point moves (a cave not drained, a ceiling without a convex patch, or a "
                   "growth rate of 0)";
        sum.years = o.years;
    }
    sum.maxSpeed = g.maxSpeed;
    sum.levelSetVoxels = field.activeVoxels();
    sum.secondsGrowth = watch.lap();

    const mesh::TriangleMesh decorated = meshField(field);
    sum.mesh = mesh::measureMesh(decorated);
    fs::create_directories(dir);
    if (meshes) {
        mesh::writeMeshFile(decorated, (fs::path(dir) / "cave_decorated.obj").string());
        mesh::writeMeshFile(decorated, (fs::path(dir) / "cave_decorated.ply").string());
        formats::GlbOptions go;
        go.name = "cave_decorated";
        formats::writeGlb(mesh::toSurfaceMesh(decorated), (fs::path(dir) / "cave_decorated.glb").string(), go);
        sum.meshFiles = {"cave_decorated.obj", "cave_decorated.ply", "cave_decorated.glb"};
    }

    if (frames > 0) {
        fs::create_directories(fs::path(dir) / "images");
        const render::Frame pf = render::makeFrame(render::View::kPerspective, cave.dims(), cave.voxelSize, imageWidth);
        const double zTop = cave.dims().nz * cave.voxelSize;
        const int cw = imageWidth, ch = imageWidth * 3 / 4;
        // The close-up: the same subject, camera and box in every frame, chosen on the final surface.
        const Stalactite* st = sum.stalactites.empty() ? nullptr : &closeUpSubject(sum.stalactites, o.voxelSize);
        render::Camera cam;
        Vec3d lo{0, 0, 0}, hi{0, 0, 0};
        if (st) {
            double reach = 1;
            cam = closeUpCamera(field, *st, cw, ch, reach);
            lo = {std::min(cam.eye[0], st->tip[0]) - reach, std::min(cam.eye[1], st->tip[1]) - reach,
                  std::min(cam.eye[2], st->tip[2]) - reach};
            hi = {std::max(cam.eye[0], st->tip[0]) + reach, std::max(cam.eye[1], st->tip[1]) + reach,
                  std::max(cam.eye[2], st->tip[2]) + reach};
        }
        for (std::size_t k = 0; k < frameFields.size(); ++k) {
            const int year = int(std::lround(frameTimes[k]));
            const mesh::TriangleMesh whole = meshField(frameFields[k]);
            render::Image img = renderMesh(whole, pf.camera, pf.width, pf.height, 0.0, zTop);
            render::drawText(img, 10, 10, "speleothems: year " + std::to_string(year), {40, 40, 40}, pf.textScale);
            const std::string pn = frameName("perspective", int(k));
            render::writePng((fs::path(dir) / pn).string(), img);
            sum.pictures.push_back(pn);
            if (st) {
                const mesh::TriangleMesh part = meshField(frameFields[k], lo, hi);
                render::Image cimg = renderMesh(part, cam, cw, ch, st->tip[2], st->tip[2] + st->length + st->radius);
                render::drawText(cimg, 10, 10,
                                 "stalactite, year " + std::to_string(year) + " (final length " +
                                     std::to_string(int(std::lround(st->length * 100))) + " cm)",
                                 {40, 40, 40}, pf.textScale);
                const std::string cn = frameName("closeup", int(k));
                render::writePng((fs::path(dir) / cn).string(), cimg);
                sum.pictures.push_back(cn);
            }
        }
    }
    sum.secondsOutput = watch.seconds();
    return sum;
}

}  // namespace cavesim::speleo

#include "site/site.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>

#include "core/error.h"
#include "core/text.h"
#include "sim/parameters.h"
#include "sim/recharge.h"
#include "sim/scenario_io.h"

#ifdef CAVESIM_HAVE_GDAL
#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#endif

namespace fs = std::filesystem;

namespace cavesim::site {
namespace {

std::string num(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

/// The block's extent in world metres: lo and hi per axis.
struct Block {
    double lo[3], hi[3], h;
    int n[3];
};

Block blockOf(const Scenario& s) {
    Block b;
    b.h = s.voxelSize;
    for (int c = 0; c < 3; ++c) {
        b.n[c] = s.size[c];
        b.lo[c] = s.site.origin[c];
        b.hi[c] = s.site.origin[c] + s.size[c] * s.voxelSize;
    }
    return b;
}

std::string trim(const std::string& t) {
    const auto a = t.find_first_not_of(" \t\r\n");
    if (a == std::string::npos) return "";
    return t.substr(a, t.find_last_not_of(" \t\r\n") - a + 1);
}

/// Drops the UTF-8 byte order mark that spreadsheet programs put before a file's first line
/// (read as part of the first field, it made an XYZ file's first point look like a header).
void stripByteOrderMark(std::string& line, int lineNo) {
    if (lineNo == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
}

bool parseNumber(const std::string& t, double& out) {
    const std::string x = trim(t);
    if (x.empty()) return false;
    try {
        std::size_t used = 0;
        out = std::stod(x, &used);
        return used == x.size() && std::isfinite(out);
    } catch (const std::exception&) {
        return false;
    }
}

bool isTiff(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".tif" || ext == ".tiff";
}

/// How messages name a site file: the scenario, the key and its value as typed, then the file
/// itself (absolute), which the rest of the message continues ("…/dem.tif: not a GeoTIFF").
std::string label(const Scenario& s, const void* field, const std::string& typed, const std::string& path) {
    const std::string key = s.path + ": key '" + scenarioKey(s, field) + "' = ";
    return typed == path ? key + path : key + "\"" + typed + "\": " + path;
}

void checkReadable(const std::string& what, const std::string& path) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) throw InputError(what + ": no such file");
}

/// XYZ points, "x y z" or "x,y,z" per line; '#' comments, blank lines and one header line skipped.
std::vector<std::array<double, 3>> readXyz(const std::string& what, const std::string& path) {
    std::ifstream in(path);
    if (!in) throw InputError(what + ": cannot be read");
    std::vector<std::array<double, 3>> pts;
    std::string line;
    int lineNo = 0;
    while (std::getline(in, line)) {
        ++lineNo;
        stripByteOrderMark(line, lineNo);
        std::string t = trim(line);
        if (t.empty() || t[0] == '#') continue;
        std::replace(t.begin(), t.end(), ',', ' ');
        std::replace(t.begin(), t.end(), ';', ' ');
        std::istringstream fields(t);
        std::vector<std::string> f;
        for (std::string x; fields >> x;) f.push_back(x);
        std::array<double, 3> p{};
        const bool ok = f.size() == 3 && parseNumber(f[0], p[0]) && parseNumber(f[1], p[1]) && parseNumber(f[2], p[2]);
        if (!ok) {
            if (pts.empty() && lineNo == 1) continue;  // a header
            throw InputError(what + ":" + std::to_string(lineNo) + ": '" + t +
                             "' is not a point; an XYZ file has three numbers x y z per line (metres)");
        }
        pts.push_back(p);
    }
    if (pts.size() < 3)
        throw InputError(what + ": " + std::to_string(pts.size()) + " point(s); a surface needs at least 3");
    return pts;
}

/// Inverse-distance weighting (power 2) of the 8 nearest points at (x, y).
double idw(const std::vector<std::array<double, 3>>& pts, double x, double y) {
    std::vector<std::pair<double, std::size_t>> d(pts.size());
    for (std::size_t n = 0; n < pts.size(); ++n) {
        const double dx = pts[n][0] - x, dy = pts[n][1] - y;
        d[n] = {dx * dx + dy * dy, n};
    }
    const std::size_t k = std::min<std::size_t>(8, d.size());
    std::partial_sort(d.begin(), d.begin() + std::ptrdiff_t(k), d.end());
    if (d[0].first < 1e-18) return pts[d[0].second][2];
    double wsum = 0, zsum = 0;
    for (std::size_t n = 0; n < k; ++n) {
        const double w = 1.0 / d[n].first;
        wsum += w;
        zsum += w * pts[d[n].second][2];
    }
    return zsum / wsum;
}

/// A CSV row of sinkholes or springs.
struct SitePoint {
    double x = 0, y = 0, z = 0;
    bool hasZ = false;
    std::string name;
    double pressure = 0;
    bool hasPressure = false;
    int line = 0;
};

std::vector<SitePoint> readPoints(const std::string& what, const std::string& path) {
    std::ifstream in(path);
    if (!in) throw InputError(what + ": cannot be read");
    std::string line;
    int lineNo = 0;
    std::vector<std::string> cols;
    std::vector<SitePoint> out;
    auto split = [](const std::string& t) {
        std::vector<std::string> f;
        std::stringstream ss(t);
        for (std::string x; std::getline(ss, x, ',');) f.push_back(trim(x));
        if (!t.empty() && t.back() == ',') f.push_back("");
        return f;
    };
    while (std::getline(in, line)) {
        ++lineNo;
        stripByteOrderMark(line, lineNo);
        const std::string t = trim(line);
        if (t.empty() || t[0] == '#') continue;
        if (cols.empty()) {
            cols = split(t);
            for (auto& c : cols)
                std::transform(c.begin(), c.end(), c.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
            const auto has = [&](const char* c) { return std::count(cols.begin(), cols.end(), c); };
            for (const auto& c : cols)
                if (c != "x" && c != "y" && c != "z" && c != "name" && c != "pressure")
                    throw InputError(
                        what + ":" + std::to_string(lineNo) + ": column '" + escaped(c) +
                        "' is not one of x, y, z, name, pressure (the header must name x,y[,z],name[,pressure])");
            if (has("x") != 1 || has("y") != 1 || has("name") != 1 || has("z") > 1 || has("pressure") > 1)
                throw InputError(what + ":" + std::to_string(lineNo) + ": header '" + escaped(t) +
                                 "' must name x, y and name once each, and z and pressure at most once");
            continue;
        }
        const std::vector<std::string> f = split(t);
        if (f.size() != cols.size())
            throw InputError(what + ":" + std::to_string(lineNo) + ": " + std::to_string(f.size()) +
                             " field(s), the header has " + std::to_string(cols.size()));
        SitePoint p;
        p.line = lineNo;
        for (std::size_t c = 0; c < cols.size(); ++c) {
            if (cols[c] == "name") {
                p.name = f[c];
                continue;
            }
            if (f[c].empty() && (cols[c] == "z" || cols[c] == "pressure")) continue;  // optional per row
            double v = 0;
            if (!parseNumber(f[c], v))
                throw InputError(what + ":" + std::to_string(lineNo) + ": " + cols[c] + " = '" + escaped(f[c]) +
                                 "' is not a number");
            if (cols[c] == "x") p.x = v;
            if (cols[c] == "y") p.y = v;
            if (cols[c] == "z") p.z = v, p.hasZ = true;
            if (cols[c] == "pressure") {
                if (!(v > 0 && v <= 1e6))
                    throw InputError(what + ":" + std::to_string(lineNo) + ": pressure = " + f[c] +
                                     " must be in (0, 10⁶]");
                p.pressure = v, p.hasPressure = true;
            }
        }
        if (p.name.empty()) throw InputError(what + ":" + std::to_string(lineNo) + ": an empty name");
        out.push_back(p);
    }
    if (cols.empty())
        throw InputError(what + ": empty; expected a header x,y[,z],name[,pressure] and one row per point");
    return out;
}

#ifdef CAVESIM_HAVE_GDAL

/// GDAL's messages stay quiet while site files are read (library code never prints): failures
/// come back as return values, turned into InputErrors here.
struct QuietGdal {
    QuietGdal() { CPLPushErrorHandler(CPLQuietErrorHandler); }
    ~QuietGdal() { CPLPopErrorHandler(); }
    QuietGdal(const QuietGdal&) = delete;
    QuietGdal& operator=(const QuietGdal&) = delete;
};

struct DatasetCloser {
    void operator()(GDALDataset* d) const { GDALClose(GDALDataset::ToHandle(d)); }
};

/// A single-band GeoTIFF in a projected CRS in metres.
struct Raster {
    std::string what;
    std::unique_ptr<GDALDataset, DatasetCloser> ds;
    OGRSpatialReference srs;
    std::string crsName;
    double gt[6]{}, inv[6]{};
    int w = 0, h = 0;
    std::vector<double> values;
    bool hasNoData = false;
    double noData = 0;
};

Raster openRaster(const std::string& what, const std::string& path) {
    static std::once_flag once;
    std::call_once(once, [] { GDALAllRegister(); });
    checkReadable(what, path);
    Raster r;
    r.what = what;
    r.ds.reset(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    if (!r.ds) throw InputError(what + ": not a GeoTIFF (GDAL cannot read it as a raster)");
    const std::string driver = r.ds->GetDriver() ? r.ds->GetDriver()->GetDescription() : "?";
    if (driver != "GTiff") throw InputError(what + ": not a GeoTIFF (GDAL reads it as " + driver + ")");
    const OGRSpatialReference* srs = r.ds->GetSpatialRef();
    if (!srs || srs->IsEmpty())
        throw InputError(what +
                         ": has no coordinate reference system; site files must be in a projected CRS in metres");
    r.srs = *srs;
    r.crsName = srs->GetName() ? srs->GetName() : "?";
    if (srs->IsGeographic())
        throw InputError(what + ": geographic CRS '" + r.crsName +
                         "' (degrees); reproject it to a projected CRS in metres, e.g. gdalwarp -t_srs EPSG:32633");
    if (!srs->IsProjected()) throw InputError(what + ": CRS '" + r.crsName + "' is not a projected CRS in metres");
    const char* unit = nullptr;
    const double toMetre = srs->GetLinearUnits(&unit);
    if (std::abs(toMetre - 1.0) > 1e-12)
        throw InputError(what + ": CRS '" + r.crsName + "' is in " + (unit ? unit : "?") + " (" + num(toMetre) +
                         " m); site files must be in metres");
    if (r.ds->GetGeoTransform(r.gt) != CE_None || !GDALInvGeoTransform(r.gt, r.inv))
        throw InputError(what + ": has no usable geotransform (pixel → CRS coordinates)");
    if (r.ds->GetRasterCount() < 1) throw InputError(what + ": has no raster band");
    r.w = r.ds->GetRasterXSize();
    r.h = r.ds->GetRasterYSize();
    GDALRasterBand* band = r.ds->GetRasterBand(1);
    int has = 0;
    r.noData = band->GetNoDataValue(&has);
    r.hasNoData = has != 0;
    r.values.resize(std::size_t(r.w) * std::size_t(r.h));
    if (band->RasterIO(GF_Read, 0, 0, r.w, r.h, r.values.data(), r.w, r.h, GDT_Float64, 0, 0) != CE_None)
        throw InputError(what + ": its pixels cannot be read");
    return r;
}

/// Bilinear value between pixel centres at world (x, y); false outside the raster or on no-data.
bool sample(const Raster& r, double x, double y, double& out) {
    const double px = r.inv[0] + r.inv[1] * x + r.inv[2] * y;
    const double py = r.inv[3] + r.inv[4] * x + r.inv[5] * y;
    if (!(px >= 0 && py >= 0 && px <= r.w && py <= r.h)) return false;
    const double fx = std::clamp(px - 0.5, 0.0, double(r.w - 1)), fy = std::clamp(py - 0.5, 0.0, double(r.h - 1));
    const int c0 = std::min(int(fx), r.w - 1), r0 = std::min(int(fy), r.h - 1);
    const int c1 = std::min(c0 + 1, r.w - 1), r1 = std::min(r0 + 1, r.h - 1);
    const double tx = fx - c0, ty = fy - r0;
    auto at = [&](int c, int rr) { return r.values[std::size_t(rr) * std::size_t(r.w) + std::size_t(c)]; };
    double v[4] = {at(c0, r0), at(c1, r0), at(c0, r1), at(c1, r1)};
    const double wts[4] = {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty};
    double sum = 0;
    for (int n = 0; n < 4; ++n) {
        if (wts[n] == 0) continue;
        if (!std::isfinite(v[n]) || (r.hasNoData && v[n] == r.noData)) return false;
        sum += wts[n] * v[n];
    }
    out = sum;
    return true;
}

#endif

}  // namespace

bool gdalAvailable() {
#ifdef CAVESIM_HAVE_GDAL
    return true;
#else
    return false;
#endif
}

bool hasSiteFiles(const Scenario& s) {
    return !s.site.dem.empty() || !s.site.sinkholes.empty() || !s.site.springs.empty() ||
           !s.site.baseOfLimestone.empty() || !s.site.waterTable.empty() || !s.siteHorizons.empty();
}

void loadSite(Scenario& s) {
    if (!hasSiteFiles(s)) return;
    // Paths relative to the scenario file's folder, made absolute for the effective scenario.
    const fs::path folder =
        s.path.empty() || s.path.front() == '<' ? fs::current_path() : fs::absolute(s.path).parent_path();
    // The values as typed, kept for messages.
    std::map<const void*, std::string> typed;
    auto resolve = [&](std::string& p) {
        typed[&p] = p;
        if (!p.empty() && fs::path(p).is_relative()) p = (folder / p).lexically_normal().string();
    };
    for (std::string* p :
         {&s.site.dem, &s.site.sinkholes, &s.site.springs, &s.site.baseOfLimestone, &s.site.waterTable})
        resolve(*p);
    for (SiteHorizon& hz : s.siteHorizons) resolve(hz.file);
    const auto label = [&](const void* field, const std::string& path) {
        return site::label(s, field, typed[field], path);
    };

#ifndef CAVESIM_HAVE_GDAL
    throw InputError(s.path +
                     ": [site] files need GDAL, and this cavesim was built without it (install libgdal-dev "
                     "and rebuild: bash scripts/setup.sh)");
#else
    const QuietGdal quiet;
    const Block b = blockOf(s);
    const int nx = b.n[0], ny = b.n[1], nz = b.n[2];
    auto data = std::make_shared<SiteData>();
    data->nx = nx;
    data->ny = ny;
    auto colX = [&](int i) { return b.lo[0] + (i + 0.5) * b.h; };
    auto colY = [&](int j) { return b.lo[1] + (j + 0.5) * b.h; };

    // The CRS every raster must share: the first one read (the DEM when there is one).
    std::unique_ptr<OGRSpatialReference> crs;
    std::string crsWhat;
    auto checkCrs = [&](const Raster& r) {
        if (!crs) {
            crs = std::make_unique<OGRSpatialReference>(r.srs);
            crsWhat = r.what;
            data->crs = r.crsName;
            return;
        }
        if (!r.srs.IsSame(crs.get()))
            throw InputError(r.what + ": CRS '" + r.crsName + "' differs from the CRS '" + data->crs + "' of " +
                             crsWhat + "; every site file must be in one CRS");
    };
    // A surface on the block's columns, checked to lie within the block's elevations.
    auto surface = [&](const std::string& what, const std::string& path, bool mustBeTiff) {
        std::vector<double> z(std::size_t(nx) * std::size_t(ny));
        if (mustBeTiff || isTiff(path)) {
            const Raster r = openRaster(what, path);
            checkCrs(r);
            for (int j = 0; j < ny; ++j)
                for (int i = 0; i < nx; ++i)
                    if (!sample(r, colX(i), colY(j), z[std::size_t(i) + std::size_t(nx) * std::size_t(j)]))
                        throw InputError(what + ": does not cover the block: no data at column (" + std::to_string(i) +
                                         ", " + std::to_string(j) + "), world x = " + num(colX(i)) +
                                         ", y = " + num(colY(j)) + " m");
        } else {
            checkReadable(what, path);
            const auto pts = readXyz(what, path);
            for (int j = 0; j < ny; ++j)
                for (int i = 0; i < nx; ++i)
                    z[std::size_t(i) + std::size_t(nx) * std::size_t(j)] = idw(pts, colX(i), colY(j));
        }
        // Interpolation rounds: a surface given exactly on the block's top or bottom may come out a
        // little beyond it (a few ulps), and within 10⁻⁹ of the elevations (micrometres) reads as on it.
        const double slack = 1e-9 * std::max({1.0, std::abs(b.lo[2]), std::abs(b.hi[2])});
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                double& v = z[std::size_t(i) + std::size_t(nx) * std::size_t(j)];
                if (v > b.hi[2] && v <= b.hi[2] + slack) v = b.hi[2];
                if (v < b.lo[2] && v >= b.lo[2] - slack) v = b.lo[2];
                if (!(v >= b.lo[2] && v <= b.hi[2]))
                    throw InputError(what + ": the surface leaves the block: elevation " + num(v) + " m at column (" +
                                     std::to_string(i) + ", " + std::to_string(j) + "), world x = " + num(colX(i)) +
                                     ", y = " + num(colY(j)) + " m, is outside the block's elevations [" +
                                     num(b.lo[2]) + ", " + num(b.hi[2]) + "] m (key '" +
                                     scenarioKey(s, &s.site.origin) + "' and the grid place the block)");
            }
        return z;
    };
    if (!s.site.dem.empty()) data->landSurface = surface(label(&s.site.dem, s.site.dem), s.site.dem, true);
    if (!s.site.baseOfLimestone.empty())
        data->baseOfLimestone =
            surface(label(&s.site.baseOfLimestone, s.site.baseOfLimestone), s.site.baseOfLimestone, false);
    if (!s.site.waterTable.empty())
        data->waterTable = surface(label(&s.site.waterTable, s.site.waterTable), s.site.waterTable, false);
    for (std::size_t n = 0; n < s.siteHorizons.size(); ++n)
        data->horizons.push_back(surface(label(&s.siteHorizons[n].file, s.siteHorizons[n].file) +
                                             " ([[site.horizon]] " + std::to_string(n + 1) + ")",
                                         s.siteHorizons[n].file, false));

    // Sinkholes and springs: one voxel each.
    auto place = [&](const std::string& what, const SitePoint& p, const char* kind) {
        const std::string at = what + ":" + std::to_string(p.line) + ": " + kind + " '" + escaped(p.name) +
                               "' at x = " + num(p.x) + ", y = " + num(p.y) +
                               (p.hasZ ? ", z = " + num(p.z) : std::string()) + " m";
        const int i = int(std::floor((p.x - b.lo[0]) / b.h)), j = int(std::floor((p.y - b.lo[1]) / b.h));
        if (p.x < b.lo[0] || p.y < b.lo[1] || i < 0 || j < 0 || i >= nx || j >= ny)
            throw InputError(at + " lies outside the block (x " + num(b.lo[0]) + "–" + num(b.hi[0]) + " m, y " +
                             num(b.lo[1]) + "–" + num(b.hi[1]) + " m)");
        const std::size_t col = std::size_t(i) + std::size_t(nx) * std::size_t(j);
        const double land = data->landSurface.empty() ? b.hi[2] : data->landSurface[col];
        int k;
        if (p.hasZ) {
            k = int(std::floor((p.z - b.lo[2]) / b.h));
            if (p.z < b.lo[2] || k < 0 || k >= nz)
                throw InputError(at + " lies outside the block (z " + num(b.lo[2]) + "–" + num(b.hi[2]) + " m)");
            if (b.lo[2] + (k + 0.5) * b.h > land)
                throw InputError(at + " lies above the land surface (" + num(land) + " m there): its voxel is air");
        } else {
            k = landSurfaceLayer(s, land);
            if (k < 0)
                throw InputError(at + ": the land surface (" + num(land) +
                                 " m) is below every voxel centre of its column");
        }
        // A voxel below the base of the limestone is inert (holds no water, never eroded): no place
        // for a source or sink.
        if (!data->baseOfLimestone.empty() && b.lo[2] + (k + 0.5) * b.h < data->baseOfLimestone[col])
            throw InputError(at + (p.hasZ ? "" : " (on the land surface)") + " lies below the base of the limestone (" +
                             num(data->baseOfLimestone[col]) + " m there): its voxel is insoluble rock");
        return VoxelBox{{i, j, k}, {i, j, k}};
    };
    if (!s.site.sinkholes.empty()) {
        const std::string what = label(&s.site.sinkholes, s.site.sinkholes);
        checkReadable(what, s.site.sinkholes);
        for (const SitePoint& p : readPoints(what, s.site.sinkholes)) {
            SourceSpec src;
            src.box = place(what, p, "sinkhole");
            src.pressure = p.hasPressure ? p.pressure : s.site.sinkholePressure;
            data->sources.push_back(src);
            data->sourceNames.push_back(p.name);
        }
    }
    if (!s.site.springs.empty()) {
        const std::string what = label(&s.site.springs, s.site.springs);
        checkReadable(what, s.site.springs);
        for (const SitePoint& p : readPoints(what, s.site.springs)) {
            SinkSpec snk;
            snk.box = place(what, p, "spring");
            for (std::size_t n = 0; n < data->sources.size(); ++n)
                if (data->sources[n].box.lo == snk.box.lo)
                    throw InputError(what + ":" + std::to_string(p.line) + ": spring '" + escaped(p.name) +
                                     "' falls on the voxel of sinkhole '" + escaped(data->sourceNames[n]) +
                                     "': a voxel cannot be both source and sink");
            for (const SourceSpec& src : s.sources)
                if (snk.box.lo[0] >= src.box.lo[0] && snk.box.lo[0] <= src.box.hi[0] &&
                    snk.box.lo[1] >= src.box.lo[1] && snk.box.lo[1] <= src.box.hi[1] &&
                    snk.box.lo[2] >= src.box.lo[2] && snk.box.lo[2] <= src.box.hi[2])
                    throw InputError(what + ":" + std::to_string(p.line) + ": spring '" + escaped(p.name) +
                                     "' falls inside a [[source]] (line " + std::to_string(src.line) + ")");
            data->sinks.push_back(snk);
            data->sinkNames.push_back(p.name);
        }
    }
    // Stage 1 marches one zone per source: at most 256 in all, as with [[source]] and [[recharge]]
    // (which validateRecharge counts with these).
    if (s.sources.size() + data->sources.size() > kMaxSources)
        throw InputError(label(&s.site.sinkholes, s.site.sinkholes) + ": " + std::to_string(data->sources.size()) +
                         " sinkholes with the " + std::to_string(s.sources.size()) + " [[source]] entries make " +
                         std::to_string(s.sources.size() + data->sources.size()) + " sources; at most " +
                         std::to_string(kMaxSources) +
                         " are allowed (stage 1 marches one zone per source): merge or drop sinkholes");
    if (s.stage2.enabled && s.sinks.empty() && data->sinks.empty())
        throw InputError(s.path + ": stage 2 needs at least one sink, and the springs file has no rows");
    if ((s.stage1.enabled || s.stage2.enabled) && s.sources.empty() && s.recharge.empty() && data->sources.empty())
        throw InputError(s.path + ": a stage needs at least one source, and the sinkholes file has no rows");
    // A [[source]] or [[sink]] wholly in air or insoluble rock (inert: porosity 0, no water) takes in
    // or drains nothing: refused, as a sinkhole or spring there is.
    const auto checkKarst = [&](const VoxelBox& box, int line, const char* header, std::size_t n) {
        for (int k = box.lo[2]; k <= box.hi[2]; ++k)
            for (int j = box.lo[1]; j <= box.hi[1]; ++j)
                for (int i = box.lo[0]; i <= box.hi[0]; ++i) {
                    const std::size_t col = std::size_t(i) + std::size_t(nx) * std::size_t(j);
                    const double z = b.lo[2] + (k + 0.5) * b.h;
                    const bool air = !data->landSurface.empty() && z > data->landSurface[col];
                    const bool insoluble = !data->baseOfLimestone.empty() && z < data->baseOfLimestone[col];
                    if (!air && !insoluble) return;
                }
        const auto corner = [](const std::array<int, 3>& c) {
            return "[" + std::to_string(c[0]) + ", " + std::to_string(c[1]) + ", " + std::to_string(c[2]) + "]";
        };
        throw InputError(s.path + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + header + " " +
                         std::to_string(n + 1) + " (voxels " + corner(box.lo) + " to " + corner(box.hi) +
                         ") lies wholly in air above the [site] dem or in insoluble rock below its base_of_limestone: "
                         "no water can flow there; at least one of its voxels must be karst rock");
    };
    for (std::size_t n = 0; n < s.sources.size(); ++n) checkKarst(s.sources[n].box, s.sources[n].line, "[[source]]", n);
    for (std::size_t n = 0; n < s.sinks.size(); ++n) checkKarst(s.sinks[n].box, s.sinks[n].line, "[[sink]]", n);
    s.siteData = std::move(data);
    // [[recharge]] sits on the land surface: checked again now that the DEM places it.
    if (!s.recharge.empty()) validateRecharge(s);
    validatePhaseTerminals(s);  // phases may name the site's sinkholes and springs
#endif
}

}  // namespace cavesim::site

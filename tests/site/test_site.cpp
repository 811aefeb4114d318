// Site inputs (src/site): GeoTIFF, CSV and XYZ files placed on the block at known coordinates,
// and each class of bad input refused with a message naming the file and the value.
//
// The block: 8 × 6 × 10 voxels of 10 m, low corner at (500000, 4000000, 100) in UTM zone 33N:
// column (i, j) is centred at (500005 + 10 i, 4000005 + 10 j), voxel k at elevation 105 + 10 k.
// The test DEM has one pixel per column, pixel-centre aligned, elevation 150 + i: bilinear
// sampling at the column centres gives it exactly.
#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include "core/error.h"
#include "sim/domain.h"
#include "sim/recharge.h"
#include "site/site.h"

using namespace cavesim;
namespace fs = std::filesystem;

namespace {

constexpr double kX0 = 500000, kY0 = 4000000, kZ0 = 100, kH = 10;

struct SiteTest : ::testing::Test {
    fs::path dir;
    void SetUp() override {
        GDALAllRegister();
        dir = fs::temp_directory_path() / ("cavesim_site_" + std::to_string(::getpid()) + "_" +
                                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }

    /// A north-up single-band Float64 GeoTIFF: pixel (c, r) covers x0 + [c, c+1]·px, yTop − [r, r+1]·px.
    std::string tiff(const std::string& name, int epsg, double x0, double yTop, double px, int w, int h,
                     const std::function<double(int, int)>& value, const char* driver = "GTiff") {
        const std::string path = (dir / name).string();
        GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
        GDALDataset* ds = mem->Create("", w, h, 1, GDT_Float64, nullptr);
        double gt[6] = {x0, px, 0, yTop, 0, -px};
        ds->SetGeoTransform(gt);
        OGRSpatialReference srs;
        srs.importFromEPSG(epsg);
        ds->SetSpatialRef(&srs);
        std::vector<double> v(std::size_t(w) * std::size_t(h));
        for (int r = 0; r < h; ++r)
            for (int c = 0; c < w; ++c) v[std::size_t(r) * std::size_t(w) + std::size_t(c)] = value(c, r);
        EXPECT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, w, h, v.data(), w, h, GDT_Float64, 0, 0), CE_None);
        GDALDataset* out = GetGDALDriverManager()->GetDriverByName(driver)->CreateCopy(path.c_str(), ds, FALSE, nullptr,
                                                                                       nullptr, nullptr);
        GDALClose(out);
        GDALClose(ds);
        return path;
    }
    /// The test DEM: one pixel per column, elevation 150 + i (column i), in `epsg`.
    std::string dem(const std::string& name = "dem.tif", int epsg = 32633) {
        return tiff(name, epsg, kX0, kY0 + 6 * kH, kH, 8, 6, [](int c, int) { return 150.0 + c; });
    }
    std::string text(const std::string& name, const std::string& body) {
        std::ofstream((dir / name).string()) << body;
        return (dir / name).string();
    }
    Scenario scenario() {
        Scenario s;
        s.name = "site";
        s.size = {8, 6, 10};
        s.voxelSize = kH;
        s.site.origin = {kX0, kY0, kZ0};
        s.stage1.enabled = false;
        s.stage2.enabled = false;
        s.path = (dir / "s.toml").string();
        return s;
    }
    /// loadSite's error message, or "" when it accepts.
    std::string error(Scenario s) {
        try {
            site::loadSite(s);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    }
};

}  // namespace

TEST_F(SiteTest, DemSinkholesSpringsAndSurfacesLandOnKnownVoxels) {
    Scenario s = scenario();
    s.site.dem = dem();
    // Relative paths are taken from the scenario file's folder.
    text("sinkholes.csv", "x,y,name,pressure\n500035,4000025,A,2.0\n500005,4000055,B,\n");
    s.site.sinkholes = "sinkholes.csv";
    text("springs.csv", "name,x,y,z\nS1,500075,4000005,125\n");
    s.site.springs = "springs.csv";
    s.site.sinkholePressure = 0.5;
    s.site.baseOfLimestone = text("base.xyz", "x y z\n500000 4000000 121\n500100 4000000 121\n500000 4000100 121\n");
    s.siteHorizons.push_back({text("h.xyz", "500000,4000000,135\n500100,4000000,135\n500050,4000100,135\n"), 1.0, 0.3});
    site::loadSite(s);
    ASSERT_TRUE(s.siteData);
    const SiteData& d = *s.siteData;
    EXPECT_EQ(d.crs, "WGS 84 / UTM zone 33N");
    EXPECT_EQ(s.site.sinkholes, (dir / "sinkholes.csv").string());  // made absolute
    ASSERT_EQ(d.landSurface.size(), 48u);
    for (int j = 0; j < 6; ++j)
        for (int i = 0; i < 8; ++i) EXPECT_DOUBLE_EQ(d.landSurface[std::size_t(i + 8 * j)], 150.0 + i);
    for (double z : d.baseOfLimestone) EXPECT_DOUBLE_EQ(z, 121.0);
    // Sinkhole A: x 500035 → i 3, y 4000025 → j 2, no z: land 153 m, highest centre below it 145 m → k 4.
    ASSERT_EQ(d.sources.size(), 2u);
    EXPECT_EQ(d.sources[0].box.lo, (std::array<int, 3>{3, 2, 4}));
    EXPECT_EQ(d.sources[0].pressure, 2.0);
    // Sinkhole B: (0, 5), land 150 m → k 4 (centre 145 m); no pressure in its row → sinkhole_pressure.
    EXPECT_EQ(d.sources[1].box.lo, (std::array<int, 3>{0, 5, 4}));
    EXPECT_EQ(d.sources[1].pressure, 0.5);
    EXPECT_EQ(d.sourceNames[1], "B");
    // Spring S1 with z 125 m: (7, 0, 2).
    ASSERT_EQ(d.sinks.size(), 1u);
    EXPECT_EQ(d.sinks[0].box.lo, (std::array<int, 3>{7, 0, 2}));

    Rng rng(1);
    const Domain dom = buildDomain(s, rng);
    EXPECT_EQ(dom.origin, (std::array<double, 3>{kX0, kY0, kZ0}));
    for (int j = 0; j < 6; ++j)
        for (int i = 0; i < 8; ++i)
            for (int k = 0; k < 10; ++k) {
                const double z = kZ0 + (k + 0.5) * kH;
                const bool inert = z > 150.0 + i || z < 121.0;  // air, or below the base of the limestone
                EXPECT_EQ(bool(dom.flags.at(i, j, k) & kInert), inert) << i << " " << j << " " << k;
                if (inert) {
                    EXPECT_EQ(dom.porosity.at(i, j, k), 0.f);
                }
                EXPECT_EQ(bool(dom.flags.at(i, j, k) & kFracture), k == 3);  // the horizon at 135 m
            }
    EXPECT_TRUE(dom.flags.at(3, 2, 4) & kSource);
    EXPECT_TRUE(dom.flags.at(7, 0, 2) & kSink);
    EXPECT_FLOAT_EQ(dom.porosity.at(1, 1, 3), 0.3f);
}

TEST_F(SiteTest, NotAGeoTiff) {
    Scenario s = scenario();
    s.site.dem = text("dem.tif", "this is not a raster\n");
    const std::string e = error(s);
    EXPECT_NE(e.find("dem.tif"), std::string::npos) << e;
    EXPECT_NE(e.find("not a GeoTIFF"), std::string::npos) << e;
    // A raster of another format is named by its driver.
    s.site.dem = tiff(
        "dem.asc", 32633, kX0, kY0 + 60, kH, 8, 6, [](int, int) { return 150.0; }, "AAIGrid");
    const std::string e2 = error(s);
    EXPECT_NE(e2.find("not a GeoTIFF (GDAL reads it as AAIGrid)"), std::string::npos) << e2;
}

TEST_F(SiteTest, GeographicCrsIsRefused) {
    Scenario s = scenario();
    s.site.dem = tiff("deg.tif", 4326, 15.0, 45.0, 0.001, 8, 6, [](int, int) { return 150.0; });
    const std::string e = error(s);
    EXPECT_NE(e.find("deg.tif"), std::string::npos) << e;
    EXPECT_NE(e.find("geographic CRS 'WGS 84' (degrees)"), std::string::npos) << e;
}

TEST_F(SiteTest, CrssThatDisagreeAreRefused) {
    Scenario s = scenario();
    s.site.dem = dem();
    s.site.baseOfLimestone = tiff("base.tif", 32634, kX0, kY0 + 60, kH, 8, 6, [](int, int) { return 120.0; });
    const std::string e = error(s);
    EXPECT_NE(e.find("base.tif: CRS 'WGS 84 / UTM zone 34N' differs from the CRS 'WGS 84 / UTM zone 33N'"),
              std::string::npos)
        << e;
}

TEST_F(SiteTest, PointsOutsideTheBlockAreRefused) {
    Scenario s = scenario();
    s.site.dem = dem();
    s.site.sinkholes = text("sinkholes.csv", "x,y,name\n500035,4000025,A\n499990,4000025,Far\n");
    std::string e = error(s);
    EXPECT_NE(e.find("sinkholes.csv:3: sinkhole 'Far' at x = 499990, y = 4000025 m lies outside the block"),
              std::string::npos)
        << e;
    s.site.sinkholes.clear();
    s.site.springs = text("springs.csv", "x,y,z,name\n500035,4000025,99,Deep\n");
    e = error(s);
    EXPECT_NE(e.find("spring 'Deep' at x = 500035, y = 4000025, z = 99 m lies outside the block (z 100–200 m)"),
              std::string::npos)
        << e;
    s.site.springs = text("springs2.csv", "x,y,z,name\n500035,4000025,190,High\n");
    e = error(s);
    EXPECT_NE(e.find("lies above the land surface (153 m there)"), std::string::npos) << e;
}

// Stage 1 marches one zone per source: a sinkholes file may not take the run past 256 sources (it
// was accepted, and 300 ran for 22 s against an estimate of 1 s).
TEST_F(SiteTest, MoreThan256SourcesAreRefused) {
    Scenario s = scenario();
    s.site.dem = dem();
    const auto rows = [](int n) {
        std::string csv = "x,y,name\n";
        for (int r = 0; r < n; ++r)
            csv += std::to_string(500005 + 10 * (r % 8)) + "," + std::to_string(4000005 + 10 * ((r / 8) % 6)) + ",S" +
                   std::to_string(r) + "\n";
        return csv;
    };
    s.site.sinkholes = text("many.csv", rows(257));
    const std::string e = error(s);
    EXPECT_NE(e.find("257 sinkholes with the 0 [[source]] entries make 257 sources; at most 256 are allowed"),
              std::string::npos)
        << e;
    s.site.sinkholes = text("enough.csv", rows(256));
    EXPECT_EQ(error(s), "");
}

TEST_F(SiteTest, SurfacesThatLeaveOrMissTheBlockAreRefused) {
    Scenario s = scenario();
    s.site.dem =
        tiff("high.tif", 32633, kX0, kY0 + 60, kH, 8, 6, [](int c, int r) { return c == 6 && r == 0 ? 250.0 : 150.0; });
    std::string e = error(s);
    // Pixel (6, 0) is column (6, 5).
    EXPECT_NE(e.find("high.tif: the surface leaves the block: elevation 250 m at column (6, 5)"), std::string::npos)
        << e;
    EXPECT_NE(e.find("[100, 200] m"), std::string::npos) << e;
    s.site.dem = tiff("small.tif", 32633, kX0, kY0 + 60, kH, 4, 6, [](int, int) { return 150.0; });
    e = error(s);
    EXPECT_NE(e.find("small.tif: does not cover the block: no data at column (4, 0)"), std::string::npos) << e;
    s.site.dem.clear();
    s.site.waterTable = text("wt.xyz", "500000 4000000 90\n500100 4000000 90\n500000 4000100 90\n");
    e = error(s);
    EXPECT_NE(e.find("wt.xyz: the surface leaves the block: elevation 90 m"), std::string::npos) << e;
    // A surface exactly on the block's top or bottom is inside (interpolation once put it a few
    // ulps beyond, refused as "elevation 200 m … outside the block's elevations [100, 200] m").
    for (const char* z : {"200", "100", "200.00000000000003", "99.999999999999986"}) {
        const std::string zs(z);
        s.site.waterTable = text("edge.xyz", "500000 4000000 " + zs + "\n500100 4000000 " + zs + "\n500000 4000100 " +
                                                 zs + "\n500033 4000077 " + zs + "\n");
        EXPECT_EQ(error(s), "") << z;
    }
}

TEST_F(SiteTest, MissingFilesAndMalformedCsvAreRefused) {
    Scenario s = scenario();
    s.site.dem = (dir / "nope.tif").string();
    EXPECT_NE(error(s).find("nope.tif: no such file"), std::string::npos);
    s.site.dem.clear();
    s.site.sinkholes = text("bad.csv", "x,y,label\n1,2,A\n");
    EXPECT_NE(error(s).find("bad.csv:1: column 'label' is not one of x, y, z, name, pressure"), std::string::npos);
    s.site.sinkholes = text("bad2.csv", "x,y,name\n500035,north,A\n");
    EXPECT_NE(error(s).find("bad2.csv:2: y = 'north' is not a number"), std::string::npos);
    // A control byte in the header is shown, not left to cut the message short.
    const char nul[] = "x,y\0,name\n1,2,A\n";
    s.site.sinkholes = text("nul.csv", std::string(nul, sizeof nul - 1));
    EXPECT_NE(error(s).find("nul.csv:1: column 'y\\u0000' is not one of x, y, z, name, pressure"), std::string::npos)
        << error(s);
}

// A sinkhole or spring in the insoluble rock below the base of the limestone (an inert voxel that
// holds no water) is refused; a UTF-8 byte order mark before a CSV header or an XYZ file's first
// point is read as nothing.
TEST_F(SiteTest, PointsInInsolubleRockAndByteOrderMarks) {
    Scenario s = scenario();
    s.site.baseOfLimestone = text("base.xyz",
                                  "\xEF\xBB\xBF"
                                  "500000 4000000 125\n500100 4000000 125\n500000 4000100 125\n");
    s.site.sinkholes = text("sinkholes.csv", "\xEF\xBB\xBFx,y,z,name\n500035,4000025,111,Low\n");
    std::string e = error(s);
    EXPECT_NE(e.find("sinkholes.csv:2: sinkhole 'Low' at x = 500035, y = 4000025, z = 111 m lies below the base of the "
                     "limestone (125 m there): its voxel is insoluble rock"),
              std::string::npos)
        << e;
    s.site.sinkholes = text("sinkholes2.csv", "\xEF\xBB\xBFx,y,z,name\n500035,4000025,131,Ok\n");
    EXPECT_EQ(error(s), "");
    site::loadSite(s);
    ASSERT_TRUE(s.siteData);
    ASSERT_EQ(s.siteData->sources.size(), 1u);
    EXPECT_EQ(s.siteData->sources[0].box.lo, (std::array<int, 3>{3, 2, 3}));
    // The first point counts: the base is 125 m everywhere (the BOM once dropped it, leaving 2 points).
    for (double z : s.siteData->baseOfLimestone) EXPECT_NEAR(z, 125.0, 1e-9);
}

// A phase names the site's sinkholes and springs after the [[source]] and [[sink]] entries; a number
// past them is refused once the site is read (it once ran the phase with no source and no sink).
TEST_F(SiteTest, PhaseTerminalsCountTheSitesSinkholesAndSprings) {
    Scenario s = scenario();
    s.site.sinkholes = text("sinkholes.csv", "x,y,name\n500035,4000025,A\n500055,4000025,B\n");
    s.site.springs = text("springs.csv", "x,y,z,name\n500075,4000045,105,S\n");
    Stage2Phase ph;
    ph.iterations = 5;
    ph.line = 7;
    ph.sources = {2};
    ph.sinks = {1};
    s.stage2.phases = {ph};
    EXPECT_EQ(error(s), "");
    s.stage2.phases[0].sinks = {2};
    std::string e = error(s);
    EXPECT_NE(e.find(":7: key 'phase.sinks' (entry 1) names sink 2: the run has 1 sinks, numbered 1 to 1 (0 [[sink]] "
                     "entries in file order, then 1 [site] springs)"),
              std::string::npos)
        << e;
    s.stage2.phases[0].sinks = {};
    s.stage2.phases[0].sources = {3};
    e = error(s);
    EXPECT_NE(e.find("names source 3: the run has 2 sources, numbered 1 to 2 (0 [[source]] entries in file order, then "
                     "0 [[recharge]] inputs, then 2 [site] sinkholes)"),
              std::string::npos)
        << e;
}

TEST_F(SiteTest, NoSiteFilesChangeNothing) {
    Scenario s = scenario();
    site::loadSite(s);
    EXPECT_FALSE(s.siteData);
    EXPECT_TRUE(site::gdalAvailable());
}

// A site's water table reaches the domain in voxel index units: elevation 160 m is
// (160 − 100) / 10 − 0.5 = 5.5, between the centres of voxels 5 (155 m) and 6 (165 m).
TEST_F(SiteTest, WaterTableReachesTheDomainInIndexUnits) {
    Scenario s = scenario();
    s.site.waterTable = text("wt_level.xyz",
                             "499990 3999990 160\n500100 3999990 160\n499990 4000080 160\n"
                             "500100 4000080 160\n");
    site::loadSite(s);
    ASSERT_TRUE(s.siteData);
    Rng rng(1);
    const Domain d = buildDomain(s, rng);
    ASSERT_EQ(d.siteWaterTable.size(), 48u);
    for (double z : d.siteWaterTable) EXPECT_NEAR(z, 5.5, 1e-9);
}

// [[recharge]] under a DEM sits on the land surface of each column. The DEM rises 6 m a column,
// 120 + 6 i m: the highest voxel centre (105 + 10 k m) not above it is k = 1, 2, 2, 3, 3, 4, 5, 5
// for i = 0 … 7.
TEST_F(SiteTest, RechargeSitsOnTheDemsLandSurface) {
    const int top[8] = {1, 2, 2, 3, 3, 4, 5, 5};
    Scenario s = scenario();
    s.site.dem = tiff("slope.tif", 32633, kX0, kY0 + 6 * kH, kH, 8, 6, [](int c, int) { return 120.0 + 6 * c; });
    s.stage1.enabled = true;  // a stage: recharge is its only source
    RechargeSpec diffuse;     // spacing 1: one input on every column, at its land-surface voxel
    diffuse.kind = RechargeKind::kDiffuse;
    diffuse.spacing = 1.0;
    diffuse.line = 20;
    RechargeSpec sinkhole;  // one of radius 1 filling its area, centred on column (3, 2): surfaces 2, 3, 3
    sinkhole.kind = RechargeKind::kSinkholes;
    sinkhole.area = {2, 1, 4, 3};
    sinkhole.count = 1;
    sinkhole.radius = 1;
    sinkhole.line = 30;
    RechargeSpec stream;  // along y = 5 at z = 9 (above the land everywhere): lowered onto it
    stream.kind = RechargeKind::kStream;
    stream.points = {{0, 5, 9}, {7, 5, 9}};
    stream.spacing = 1.0;
    stream.line = 40;
    s.recharge = {diffuse};
    site::loadSite(s);
    std::vector<SourceSpec> got = rechargeSources(s);
    ASSERT_EQ(got.size(), 48u);
    for (const SourceSpec& src : got) {
        EXPECT_EQ(src.box.lo, src.box.hi);
        EXPECT_EQ(src.box.lo[2], top[src.box.lo[0]]) << src.box.lo[0] << " " << src.box.lo[1];
    }
    s.recharge = {sinkhole, stream};
    got = rechargeSources(s);
    ASSERT_EQ(got.size(), 9u);
    // The sinkhole hangs from the lowest surface voxel of its columns (2, at i = 2), r + 1 = 2 layers.
    EXPECT_EQ(got[0].box.lo, (std::array<int, 3>{2, 1, 1}));
    EXPECT_EQ(got[0].box.hi, (std::array<int, 3>{4, 3, 2}));
    for (int i = 0; i < 8; ++i) EXPECT_EQ(got[std::size_t(1 + i)].box.lo, (std::array<int, 3>{i, 5, top[i]}));
    // In the domain every input is rock under the land (not air), and a source.
    Rng rng(1);
    const Domain dom = buildDomain(s, rng);
    for (const SourceSpec& src : got) {
        EXPECT_TRUE(dom.flags.at(src.box.hi[0], src.box.hi[1], src.box.hi[2]) & kSource);
        EXPECT_LE(kZ0 + (src.box.hi[2] + 0.5) * kH, 120.0 + 6 * src.box.hi[0]);
    }
}

TEST_F(SiteTest, RechargeOnAirOrOnASpringIsRefused) {
    Scenario s = scenario();
    // Column 0's land (102 m) lies below its lowest voxel centre (105 m): the column is air.
    s.site.dem = tiff("low.tif", 32633, kX0, kY0 + 6 * kH, kH, 8, 6, [](int c, int) { return c == 0 ? 102.0 : 150.0; });
    RechargeSpec diffuse;
    diffuse.kind = RechargeKind::kDiffuse;
    diffuse.spacing = 1.0;
    diffuse.line = 12;
    s.recharge = {diffuse};
    const std::string air = error(s);
    EXPECT_NE(air.find("s.toml:12: key '"), std::string::npos) << air;
    EXPECT_NE(air.find("column x 0, y 0"), std::string::npos) << air;
    EXPECT_NE(air.find("the column is air"), std::string::npos) << air;
    // A spring on the land-surface voxel of a column that takes a diffuse input.
    s.site.dem = dem();  // 150 + i: column 1's surface voxel is k 4
    s.site.springs = text("springs.csv", "name,x,y\nS1,500015,4000005\n");
    const std::string spring = error(s);
    EXPECT_NE(spring.find("s.toml:12:"), std::string::npos) << spring;
    EXPECT_NE(spring.find("an input at [1, 0, 4] falls on the voxel of spring 'S1'"), std::string::npos) << spring;
}

// An input is karst rock all through: a sinkhole's box that the DEM would push below the block's
// bottom, or any input below the base of the limestone (insoluble, inert), is refused like a site
// sinkhole there. Both were accepted before: the box was cut to the block, the input made inert.
TEST_F(SiteTest, RechargeBelowTheBlockOrOnInsolubleRockIsRefused) {
    Scenario s = scenario();
    s.stage1.enabled = true;
    // 121 m: only layer 0 (centre 105 m) and layer 1 (115 m) are rock under the land.
    s.site.dem = tiff("low.tif", 32633, kX0, kY0 + 6 * kH, kH, 8, 6, [](int, int) { return 121.0; });
    RechargeSpec sinkhole;  // radius 2 needs 3 layers under the land surface, the DEM leaves 2
    sinkhole.kind = RechargeKind::kSinkholes;
    sinkhole.area = {0, 0, 7, 5};
    sinkhole.count = 1;
    sinkhole.radius = 2;
    sinkhole.line = 14;
    s.recharge = {sinkhole};
    const std::string deep = error(s);
    EXPECT_NE(deep.find("s.toml:14: key 'recharge.radius' = 2:"), std::string::npos) << deep;
    EXPECT_NE(deep.find("leaves 2 layer(s) of rock, so it would reach below the block's bottom: must be at most 1"),
              std::string::npos)
        << deep;
    s.recharge[0].radius = 1;
    EXPECT_EQ(error(s), "");
    // The base of the limestone at 110 m: layer 0 (centre 105 m) is insoluble. The radius-1
    // sinkhole reaches it, a diffuse input on the land surface (layer 1) does not.
    s.site.baseOfLimestone = text("base.xyz", "x y z\n500000 4000000 110\n500100 4000000 110\n500000 4000100 110\n");
    const std::string insoluble = error(s);
    EXPECT_NE(insoluble.find("s.toml:14: key 'recharge.kind' = \"sinkholes\": an input reaches voxel ["),
              std::string::npos)
        << insoluble;
    EXPECT_NE(insoluble.find(", 0] (centre 105 m), below the base of the limestone there ([site] base_of_limestone, "
                             "110 m): its voxel is insoluble rock"),
              std::string::npos)
        << insoluble;
    RechargeSpec diffuse;
    diffuse.kind = RechargeKind::kDiffuse;
    diffuse.line = 20;
    s.recharge = {diffuse};
    EXPECT_EQ(error(s), "");
    // Base at 118 m: the land-surface layer (centre 115 m) is insoluble too.
    s.site.baseOfLimestone = text("base.xyz", "x y z\n500000 4000000 118\n500100 4000000 118\n500000 4000100 118\n");
    const std::string diffuseInsoluble = error(s);
    EXPECT_NE(diffuseInsoluble.find("s.toml:20: key 'recharge.kind' = \"diffuse\": an input reaches voxel ["),
              std::string::npos)
        << diffuseInsoluble;
    EXPECT_NE(diffuseInsoluble.find(", 1] (centre 115 m), below the base of the limestone"), std::string::npos)
        << diffuseInsoluble;
}

// A [[source]] or [[sink]] wholly in air above the DEM or in insoluble rock is refused (it once
// ran, taking in or draining nothing); one that reaches a voxel of karst rock is kept.
TEST_F(SiteTest, TerminalsWhollyInAirOrInsolubleRockAreRefused) {
    Scenario s = scenario();
    s.site.dem = dem();  // 150 + i m: layers 0–4 (centres 105–145 m) are rock, 5–9 air
    SourceSpec source;
    source.box.lo = source.box.hi = {2, 2, 7};
    source.line = 9;
    s.sources = {source};
    const std::string air = error(s);
    EXPECT_NE(air.find("s.toml:9: [[source]] 1 (voxels [2, 2, 7] to [2, 2, 7]) lies wholly in air above the [site] "
                       "dem or in insoluble rock below its base_of_limestone"),
              std::string::npos)
        << air;
    s.sources[0].box.lo = {2, 2, 4};  // the box reaches the land-surface voxel
    EXPECT_EQ(error(s), "");
    SinkSpec sink;
    sink.box = {{7, 0, 0}, {7, 1, 1}};
    sink.line = 12;
    s.sinks = {sink};
    EXPECT_EQ(error(s), "");
    s.site.baseOfLimestone = text("base.xyz", "x y z\n500000 4000000 121\n500100 4000000 121\n500000 4000100 121\n");
    const std::string insoluble = error(s);  // layers 0 and 1 (105, 115 m) lie below 121 m
    EXPECT_NE(insoluble.find("s.toml:12: [[sink]] 1 (voxels [7, 0, 0] to [7, 1, 1]) lies wholly in air"),
              std::string::npos)
        << insoluble;
}

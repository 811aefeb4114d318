/// @file scenario.h
/// @brief The scenario: everything a run needs, as a plain validated struct.
///
/// Parsed from TOML by `parseScenarioFile` (scenario_io.h); every field is one key of the parameter
/// registry (parameters.h), which holds its default, unit and allowed range (docs/scenario-format.md
/// is made from it; the comments here give meaning and unit only). Positions and sizes are in voxel
/// (index) units unless a field says metres.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sim/options.h"

namespace cavesim {

/// An axis-aligned box of voxels, inclusive on both ends, in index units.
struct VoxelBox {
    std::array<int, 3> lo{0, 0, 0};
    std::array<int, 3> hi{0, 0, 0};
};

struct NoiseSettings {
    double amplitude = 0.0;  ///< porosity added at most (±)
    double scale = 8.0;      ///< feature size in voxels
    int octaves = 3;         ///< fractal octaves
};

/// A spherical obstacle: porosity falls from the rock value at the rim to `corePorosity` at the centre.
struct SphereObstacle {
    Vec3d center{0, 0, 0};        ///< voxel units
    double radius = 1.0;          ///< voxel units
    double corePorosity = 0.005;  ///< porosity at the centre
};

/// What a plane feature stands for.
enum class PlaneKind : std::uint8_t { kBedding, kFracture };

/// A bedding plane or fracture: a slab of raised porosity around a plane of any orientation.
struct PlaneFeature {
    Vec3d point{0, 0, 0};    ///< a point on the plane, voxel units
    Vec3d normal{0, 0, 1};   ///< need not be unit; must be non-zero
    double thickness = 1.0;  ///< slab thickness in voxels
    double porosity = 0.3;   ///< porosity inside the slab
    /// Optional in-plane extent: voxels farther than this from `point` (within the plane) are
    /// untouched; 0 means unbounded.
    double extent = 0.0;
    PlaneKind kind = PlaneKind::kBedding;  ///< what the slab is (flags and pictures only)
};

/// A known conduit or synthetic protochannel: a polyline of raised porosity.
struct ChannelFeature {
    std::vector<Vec3d> points;  ///< at least two, voxel units
    double radius = 0.5;        ///< voxels
    double porosity = 0.4;      ///< porosity inside
    /// Treat the voxels as protochannel for the stage-2 pressure rule (stage-2-only runs).
    bool protochannel = true;
};

/// A fracture family (`[[rock.fracture_family]]`): a discrete fracture network of discs drawn from
/// the scenario's seed (sim/fractures.h). Orientations are of the fracture planes: the dip direction
/// is an azimuth clockwise from north (+y, with +x east and +z up); the poles scatter about the mean
/// pole by a Fisher distribution. Disc diameters follow a truncated power law.
struct FractureFamily {
    double dipDirection = 0.0;    ///< degrees clockwise from +y of the mean plane's dip
    double dip = 90.0;            ///< degrees below the horizontal of the mean plane
    double kappa = 20.0;          ///< Fisher concentration of the poles about the mean pole
    double spacing = 10.0;        ///< voxels: mean spacing along the mean pole (P32 = 1/spacing); 0 = `density`
    double density = 0.0;         ///< fractures per voxel³ (P30); 0 = `spacing`
    double lengthExponent = 2.5;  ///< a of the diameter density p(l) ∝ l^−a on [minLength, maxLength]
    double minLength = 4.0;       ///< voxels: least disc diameter
    double maxLength = 40.0;      ///< voxels: largest disc diameter
    double aperture = 1.0;        ///< voxels: slab thickness across the disc
    double porosity = 0.3;        ///< porosity inside the slab (the larger of this and the rock's)
    int line = 0;                 ///< line in the scenario file (for messages)
};

/// How a `[[recharge]]` entry feeds the block (sim/recharge.h).
enum class RechargeKind : std::uint8_t {
    kSinkholes,  ///< `count` point inputs drawn from the seed within `area`, each of `pressure`
    kDiffuse,    ///< one input per `spacing` × `spacing` cell of `area`, sharing `pressure`
    kStream,     ///< inputs every `spacing` voxels along the polyline `points`, sharing `pressure`
};

/// Recharge (`[[recharge]]`): expands into ordinary sources in the block's top layer (the land
/// surface), after the `[[source]]` entries (sim/recharge.h).
struct RechargeSpec {
    RechargeKind kind = RechargeKind::kSinkholes;
    std::vector<int> area;      ///< [x0, y0, x1, y1] inclusive voxel columns; empty = the whole top face
    int count = 5;              ///< sinkholes: how many
    int radius = 0;             ///< sinkholes: half-width of each (a (2r+1)² × (r+1) box under the top), voxels
    double spacing = 4.0;       ///< diffuse: cell size; stream: distance between inputs; voxels
    double pressure = 1.0;      ///< sinkholes: each one's; diffuse and stream: the total, shared equally
    std::vector<Vec3d> points;  ///< stream: the polyline, voxels (at least two points)
    int line = 0;               ///< line in the scenario file (for messages)
};

struct SourceSpec {
    VoxelBox box;           ///< `at = [x,y,z]` gives a one-voxel box
    double pressure = 1.0;  ///< relative pressure
    int line = 0;           ///< line in the scenario file (for messages)
};

struct SinkSpec {
    VoxelBox box;
    int line = 0;
};

/// An inception horizon of a site: a slab of raised porosity along a surface read from a file.
struct SiteHorizon {
    std::string file;        ///< GeoTIFF or XYZ points, as written (relative to the scenario file)
    double thickness = 1.0;  ///< slab thickness in voxels, measured vertically
    double porosity = 0.3;   ///< porosity inside the slab
};

/// A real site (`[site]`): files in one projected CRS (metres) and where the block sits in it.
/// Empty file names mean "none". The files are read by the site module (src/site), which fills
/// `Scenario::siteData`; the simulation only sees that.
struct SiteSettings {
    Vec3d origin{0, 0, 0};          ///< world position (metres, the CRS's x, y and elevation) of the block's low corner
    std::string dem;                ///< land surface, GeoTIFF: voxels whose centre is above it are air
    std::string sinkholes;          ///< CSV x,y[,z],name[,pressure]: sources
    std::string springs;            ///< CSV x,y[,z],name[,pressure]: sinks
    std::string baseOfLimestone;    ///< GeoTIFF or XYZ: voxels whose centre is below it are insoluble
    std::string waterTable;         ///< GeoTIFF or XYZ: stage 2's water table with `[hydrology] from_site`
    double sinkholePressure = 1.0;  ///< pressure of a sinkhole whose CSV row has none
};

/// A site's files sampled onto the block (filled by `site::loadSite`): per column (i, j) at index
/// i + nx · j, elevations in world metres at the column's centre; an empty vector: not given.
struct SiteData {
    int nx = 0, ny = 0;
    std::vector<double> landSurface, baseOfLimestone, waterTable;
    std::vector<std::vector<double>> horizons;  ///< one per Scenario::siteHorizons entry
    std::vector<SourceSpec> sources;            ///< sinkholes, after the scenario's [[source]] entries
    std::vector<SinkSpec> sinks;                ///< springs, after the scenario's [[sink]] entries
    std::vector<std::string> sourceNames, sinkNames;
    std::string crs;  ///< the CRS's name (e.g. "WGS 84 / UTM zone 33N"); empty without a DEM or raster
};

struct Scenario {
    std::string name = "scenario";
    std::uint64_t seed = 1;
    std::array<int, 3> size{60, 60, 20};  ///< voxels nx, ny, nz
    double voxelSize = 1.0;               ///< metres

    double rockPorosity = 0.05;  ///< background porosity
    NoiseSettings noise;
    std::vector<SphereObstacle> spheres;
    std::vector<PlaneFeature> planes;
    std::vector<ChannelFeature> channels;
    /// Bedding planes that are inception horizons (`[[rock.inception_horizon]]`): slabs like
    /// `planes` whose voxels also carry early flow in stage 2 (domain.h, `Domain::inception`).
    std::vector<PlaneFeature> inceptionHorizons;
    std::vector<FractureFamily> fractureFamilies;

    std::vector<SourceSpec> sources;
    std::vector<SinkSpec> sinks;
    std::vector<RechargeSpec> recharge;  ///< expanded into sources after `sources` (sim/recharge.h)

    Stage1Options stage1;
    Stage2Options stage2;
    OutputOptions output;
    SiteSettings site;
    std::vector<SiteHorizon> siteHorizons;  ///< [[site.horizon]]
    /// The site's files on the block; null until `site::loadSite` reads them (or without [site]).
    std::shared_ptr<const SiteData> siteData;
    SpeleothemOptions speleothems;

    std::string path;  ///< file it came from ("<built-in>" for the default)
    /// Line of each key the file gives, by dotted key (`stage1.max_graph_voxels`; an entry of a
    /// table of arrays with its 0-based index: `rock.fracture_family.min_length[1]`), for messages
    /// raised after reading (see `keyLine`).
    std::map<std::string, int> keyLines;
};

}  // namespace cavesim

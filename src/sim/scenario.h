/// @file scenario.h
/// @brief The scenario: everything a run needs, as a plain validated struct.
///
/// Parsed from TOML by `parseScenarioFile` (scenario_toml.cpp); every field has an in-class
/// default, a unit and a range, documented in docs/scenario-format.md. Positions and sizes are
/// in voxel (index) units unless a field says metres.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace cavesim {

using Vec3d = std::array<double, 3>;

/// An axis-aligned box of voxels, inclusive on both ends, in index units.
struct VoxelBox {
    std::array<int, 3> lo{0, 0, 0};
    std::array<int, 3> hi{0, 0, 0};
};

struct NoiseSettings {
    double amplitude = 0.0;  ///< porosity added at most (±), [0, 1]
    double scale = 8.0;      ///< feature size in voxels, (0, 1e6]
    int octaves = 3;         ///< fractal octaves, [1, 8]
};

/// A spherical obstacle: porosity falls from the rock value at the rim to `corePorosity` at the centre.
struct SphereObstacle {
    Vec3d center{0, 0, 0};       ///< voxel units
    double radius = 1.0;         ///< voxel units, (0, 1e6]
    double corePorosity = 0.005; ///< [0, 1]
};

/// A bedding plane or fracture: a slab of raised porosity around a plane of any orientation.
struct PlaneFeature {
    Vec3d point{0, 0, 0};     ///< a point on the plane, voxel units
    Vec3d normal{0, 0, 1};    ///< need not be unit; must be non-zero
    double thickness = 1.0;   ///< slab thickness in voxels, (0, 1e6]
    double porosity = 0.3;    ///< porosity inside the slab, [0, 1]
    /// Optional in-plane extent: voxels farther than this from `point` (within the plane) are
    /// untouched; 0 means unbounded.
    double extent = 0.0;
    std::string kind = "bedding";  ///< "bedding" or "fracture" (flags only)
};

/// A known conduit or synthetic protochannel: a polyline of raised porosity.
struct ChannelFeature {
    std::vector<Vec3d> points;  ///< at least two, voxel units
    double radius = 0.5;        ///< voxels, [0, 1e6]
    double porosity = 0.4;      ///< [0, 1]
    /// Treat the voxels as protochannel for the stage-2 pressure rule (stage-2-only runs).
    bool protochannel = true;
};

struct SourceSpec {
    VoxelBox box;            ///< `at = [x,y,z]` gives a one-voxel box
    double pressure = 1.0;   ///< relative pressure, (0, 1e6]
    int line = 0;            ///< line in the scenario file (for messages)
};

struct SinkSpec {
    VoxelBox box;
    int line = 0;
};

struct Stage1Settings {
    bool enabled = true;
    std::string protosinks = "boundary";  ///< "boundary" (isotropic) or "clustered"
    int clusters = 3;                     ///< clusters when clustered, [1, 64]
    double clusterRadius = 2.0;           ///< voxels, radius of one protosink cluster, [0, 1e6]
    std::vector<Vec3d> aim;               ///< optional: cluster centres nearest these points
    std::string permeability = "porosity"; ///< zone front speed rule: "uniform" or "porosity"
    double protochannelPorosity = 0.35;   ///< porosity set along protochannels after stage 1, [0, 1]
    double capacityExponent = 1.0;        ///< edge capacity = min(porosity)^exponent, (0, 8]
    long maxGraphVoxels = 4000000;        ///< zones larger than this are refused (memory), [1, 1e9]
    /// Grid faces that count as zone boundary (protosinks there): any of "-x", "+x", "-y", "+y",
    /// "-z", "+z", each at most once; empty = only the boundaries between zones. Default: all but
    /// the top (+z), the recharge side from which the sources are fed.
    std::vector<std::string> boundaryFaces{"-x", "+x", "-y", "+y", "-z"};
    /// Total drain of a zone's protosinks as a fraction of its source capacity (the summed
    /// capacity of the links leaving the source voxels), shared in proportion to porosity; (0, 1].
    double protosinkShare = 0.5;
    /// A voxel becomes protochannel only if at least this fraction of its zone's flow passes
    /// through it; [0, 1]. Smaller: more, longer branches reaching closer to the zone boundary.
    double branchFlow = 0.02;
    /// Relative random variation of link resistance (sub-voxel heterogeneity, seeded); breaks
    /// the ties among equally short staircase paths of the voxel grid; [0, 1].
    double resistanceNoise = 0.5;
};

struct Stage2Settings {
    bool enabled = true;
    int iterations = 240;         ///< [0, 1000000]
    double pRate = 0.50;          ///< pressure rise per voxel of rock, (0, 1e6]
    double pRateChannel = 0.001;  ///< pressure rise per voxel of channel, (0, pRate]
    double w0 = 0.15;             ///< erosion factor (Eq. 1), [0, 10]
    double wa = 0.25;             ///< blending factor (Eq. 2), [0, 100]
    double m = 1.0;               ///< erosion exponent (Eq. 1), (0, 4]
    /// Stage-2 pressure of a source = its `pressure` × this. 0 = automatic:
    /// 2 · pRate · (nx + ny + nz), well above anything the front reaches.
    double pressureScale = 0.0;
    double channelThreshold = 0.5;     ///< porosity at which an eroded voxel becomes channel, (0, 1]
    double protochannelPorosity = 0.25; ///< porosity of protochannel voxels at the interim step, [0, 1]
    /// Porosity (= water capacity = water injected per iteration at most) of source voxels, [0, 1].
    double sourcePorosity = 0.1;
    std::string weight = "proportional"; ///< transport weight rule: "proportional" or "uniform"
    /// Flow blending rule of Eq. 2: "max" (f_a = the largest f_c of the downhill neighbours) or
    /// "split" (each voxel's f_c split equally over its uphill neighbours).
    std::string blending = "max";
    std::vector<int> snapshots;   ///< iterations at which pictures are taken (2D/3D)
};

struct OutputSettings {
    std::string meshStyle = "smooth";  ///< "smooth" or "voxel" (also writes the blocky mesh)
    int imageWidth = 1024;             ///< pixels, [256, 8192]
    bool images = true;
    bool mesh = true;
    /// Which voxels are the cave (mesh, pictures, report): "channels" (the stage-2 channels) or
    /// "with_protochannels" (and the stage-1 protochannels, as side passages).
    std::string cave = "channels";
};

struct Scenario {
    std::string name = "scenario";
    std::uint64_t seed = 1;
    std::array<int, 3> size{60, 60, 20};  ///< voxels nx, ny, nz; each [1, 1024]
    double voxelSize = 1.0;               ///< metres, (0, 1e4]

    double rockPorosity = 0.05;  ///< [0, 1]
    NoiseSettings noise;
    std::vector<SphereObstacle> spheres;
    std::vector<PlaneFeature> planes;
    std::vector<ChannelFeature> channels;

    std::vector<SourceSpec> sources;
    std::vector<SinkSpec> sinks;

    Stage1Settings stage1;
    Stage2Settings stage2;
    OutputSettings output;

    std::string path;  ///< file it came from ("<built-in>" for the default)
};

}  // namespace cavesim

/// @file options.h
/// @brief The options of each stage of a run (paper §3.1 stage 1, §3.2 stage 2) and of its
/// outputs: one plain struct per algorithm, choices as `enum class`.
///
/// A stage takes its own options struct plus explicit inputs (the domain's fields and terminals,
/// the `Rng`), never the whole scenario. Every field is one scenario key; the key, its type, unit,
/// allowed range and description are declared once, in the parameter registry (src/sim/parameters.h,
/// entries in parameters.cpp), from which the parser, the effective-scenario writer, the report's
/// parameter table and docs/scenario-format.md are all made. A key's default is the in-class
/// initialiser here (the registry reads it from a default-constructed struct); the comments give
/// meaning and unit, the allowed ranges are in the registry only.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace cavesim {

using Vec3d = std::array<double, 3>;

/// How the protosinks of a stage-1 zone are chosen (stage1.h, step 2).
enum class ProtosinkMode : std::uint8_t {
    kBoundary,   ///< every voxel of the zone's boundary (isotropic)
    kClustered,  ///< only boundary voxels near a few cluster centres (seeded, or the aim points)
};

/// Speed rule of the stage-1 zone fronts (stage1.h, step 1).
enum class ZoneSpeed : std::uint8_t {
    kUniform,   ///< speed p_i everywhere: the multiplicatively weighted Voronoi division
    kPorosity,  ///< speed p_i · R(x)/R̄: fronts hurry along fractures, crawl through obstacles
};

/// A face of the grid, in the order −x, +x, −y, +y, −z, +z.
enum class GridFace : std::uint8_t { kMinusX, kPlusX, kMinusY, kPlusY, kMinusZ, kPlusZ };

/// Stage-2 transport weight of a lower-pressure neighbour (Listing 1).
enum class TransportWeight : std::uint8_t {
    kProportional,  ///< ΔP / distance
    kUniform,       ///< 1
};

/// Flow blending rule of Eq. 2.
enum class FlowBlending : std::uint8_t {
    kMax,    ///< f_a = the largest f_c of the downhill neighbours
    kSplit,  ///< each voxel's f_c split equally over its uphill neighbours
};

/// How a voxel's stage-2 pressure rate follows its state (docs/model.md, "Pressure rate").
enum class RateRule : std::uint8_t {
    kPorosity,     ///< from rock to channel with the porosity: protochannels are preferred, not finished
    kChannelFlag,  ///< the paper's rule: the channel rate on channel and protochannel voxels, else the rock rate
};

/// How much water a source takes in each iteration (docs/model.md, "Source inflow").
enum class SourceInflow : std::uint8_t {
    kHead,   ///< from its head above the field pressure at the source: stronger heads and breakthrough raise it
    kLevel,  ///< refill to a fixed level, its pressure / the largest source pressure
};

/// Which voxels make up the cave (mesh, pictures, report).
enum class CaveExtent : std::uint8_t {
    kChannels,           ///< the stage-2 channels (protochannels only when there are none)
    kWithProtochannels,  ///< the channels and the stage-1 protochannels, as side passages
};

/// The cave mesh written besides the smooth one.
enum class MeshStyle : std::uint8_t {
    kSmooth,  ///< cave.obj, cave.ply: the smooth closed mesh
    kVoxel,   ///< also cave_voxels.obj: the faces between cave and rock voxels
};

/// An export format of `[output] formats` (formats/exports.h lists the files of each).
enum class ExportFormat : std::uint8_t { kGlb, kVtk, kStl, kSvx, kTh, kGocad, kCsv, kVdb };

/// Which side the exported mesh's normals face.
enum class MeshNormals : std::uint8_t {
    kOutward,  ///< out of the cave, into the rock: the cave seen from outside
    kInward,   ///< into the cave: for renderers that cull back faces and show the walls from inside
};

/// Stage 1 (stage1.h): pressure zones, flow networks, protochannels.
struct Stage1Options {
    bool enabled = true;
    ProtosinkMode protosinks = ProtosinkMode::kBoundary;
    int clusters = 3;            ///< clusters when clustered
    double clusterRadius = 2.0;  ///< voxels, radius of one protosink cluster
    std::vector<Vec3d> aim;      ///< voxels: cluster centres nearest these points (optional)
    ZoneSpeed permeability = ZoneSpeed::kPorosity;
    double protochannelPorosity = 0.35;  ///< porosity shown along protochannels after stage 1
    double capacityExponent = 1.0;       ///< edge capacity = min(porosity)^exponent
    long maxGraphVoxels = 4000000;       ///< zones larger than this are refused (memory)
    /// Voxels of a flow network at most: a larger zone's network is its `networkVoxels` voxels
    /// the zone's front reached first (stage1.h, "Neighbourhood").
    long networkVoxels = 1000000;
    /// Grid faces that count as zone boundary (protosinks there), each at most once, in the order
    /// given; empty = only the boundaries between zones. Default: all but the top (+z), the
    /// recharge side from which the sources are fed.
    std::vector<GridFace> boundaryFaces{GridFace::kMinusX, GridFace::kPlusX, GridFace::kMinusY, GridFace::kPlusY,
                                        GridFace::kMinusZ};
    double protosinkShare = 0.5;   ///< total protosink drain / source capacity
    double branchFlow = 0.02;      ///< least fraction of a zone's flow through a protochannel voxel
    double resistanceNoise = 0.5;  ///< spread of the log-uniform random factor on link resistance
    /// voxels: no protochannel within this Chebyshev distance of a sink voxel (the rock stage 1
    /// leaves between protochannels and sinks)
    int sinkGap = 2;
};

/// The water table of stage 2 (docs/model.md, "Water table and gravity"): a plane in voxel (index)
/// units. Voxels whose centre lies above it are vadose: their water is not pressurised and moves
/// down under gravity; below it the paper's pressure model holds (phreatic).
struct Hydrology {
    /// voxels: height (z index) of the table above the block's centre column; −1 = none (every
    /// voxel phreatic, the paper's model)
    double waterTable = -1.0;
    double dip = 0.0;           ///< degrees: the table's dip (0 = level)
    double dipDirection = 0.0;  ///< degrees clockwise from +y: the direction the table falls towards
    /// fraction of the field pressure added to a vadose voxel's gravitational potential: how strongly
    /// vadose water drifts towards the sinks along a floor (0 = straight down only)
    double lateral = 0.1;
    /// the table is `[site] water_table` (sampled on the block's columns) instead of a plane
    bool fromSite = false;
    int line = 0;  ///< line of the `[hydrology]` table in the scenario file (for messages)
};

/// One base-level phase of stage 2 (`[[phase]]`): iterations run with its own water table and
/// active terminals, phases in file order.
struct Stage2Phase {
    int iterations = 0;        ///< iterations of the phase (at least 1)
    double waterTable = -1.0;  ///< voxels: the table's height at the centre column; −1 = `[hydrology]`'s
    std::vector<int> sinks;    ///< 1-based `[[sink]]` indices active in the phase; empty = all
    std::vector<int> sources;  ///< 1-based `[[source]]` indices active in the phase; empty = all
    int line = 0;              ///< line in the scenario file (for messages)
};

/// Stage 2 (stage2.h): pressure front, water transport, blending, erosion.
struct Stage2Options {
    bool enabled = true;
    int iterations = 240;         ///< iterations of pressure, transport, blending, erosion
    double pRate = 0.50;          ///< pressure rise per voxel of rock
    double pRateChannel = 0.001;  ///< pressure rise per voxel of channel
    double w0 = 0.15;             ///< erosion factor (Eq. 1)
    double wa = 0.25;             ///< blending factor (Eq. 2)
    double m = 1.0;               ///< erosion exponent (Eq. 1)
    /// Stage-2 pressure (head) of a source = its `pressure` × this; 0 = automatic: the strongest
    /// source's head is 2 · pRate · (nx + ny + nz), well above anything the front reaches, and the
    /// others in proportion to their `pressure`.
    double pressureScale = 0.0;
    double channelThreshold = 0.5;       ///< porosity at which an eroded voxel becomes channel
    double protochannelPorosity = 0.25;  ///< porosity of protochannel voxels at the interim step
    double sourcePorosity = 0.1;         ///< porosity (= water injected per iteration at most) of sources
    TransportWeight weight = TransportWeight::kProportional;
    FlowBlending blending = FlowBlending::kMax;
    RateRule rateRule = RateRule::kPorosity;
    SourceInflow inflow = SourceInflow::kHead;
    std::vector<int> snapshots;  ///< iterations at which pictures are taken, at most 32
    Hydrology hydrology;         ///< `[hydrology]`: the water table (none by default)
    /// `[[phase]]`: base-level phases run in order; when given, their iterations replace `iterations`
    std::vector<Stage2Phase> phases;

    /// The iterations stage 2 runs: the phases' sum when `[[phase]]` entries are given, else `iterations`.
    long totalIterations() const {
        if (phases.empty()) return iterations;
        long sum = 0;
        for (const Stage2Phase& ph : phases) sum += ph.iterations;
        return sum;
    }
};

/// Speleothems (src/speleo/speleothems.h): stalactites grown on the drained cave's ceiling by
/// Short's law, stalagmites below their drip points. Lengths in metres, times in years.
struct SpeleothemOptions {
    bool enabled = false;
    bool drained = true;             ///< treat the whole cave as air-filled (no water table yet)
    double years = 1000.0;           ///< years of growth
    double timeStep = 0.0;           ///< years between speed updates; 0 = the stable step
    double alpha = 1.0;              ///< Short's chemical rate α, 1/yr
    double lQ = 1.0e-4;              ///< Short's characteristic length l_Q, metres
    double voxelSize = 0.1;          ///< edge of the decoration level set's voxels, metres
    double convexity = 2.0;          ///< least mean curvature of a stalactite's surface, 1/m
    double minSize = 0.2;            ///< least horizontal radius of a convex ceiling patch, metres
    double tipRadius = 0.0;          ///< tip radius ε, metres; 0 = two voxels
    double roughness = 0.15;         ///< amplitude of the ceiling relief added before growth, metres
    double roughnessScale = 1.0;     ///< feature size of that relief, metres
    double dripVariability = 0.3;    ///< relative spread of α between drip sites
    std::uint64_t seed = 1;          ///< seeds the relief and the drip variability
    bool stalagmites = true;         ///< grow stalagmites below the drip points
    double stalagmiteRate = 1.0;     ///< stalagmite apex rate / its stalactite's tip speed
    double stalagmiteRadius = 0.15;  ///< stalagmite equilibrium radius, metres
    int frames = 4;                  ///< growth animation frames (0 = none)
};

/// The speleothem stage's growth step at largest normal speed `vmax` (m/yr, > 0) on a level set
/// of voxel edge `h` (metres): the stable step 0.5·h / vmax — the fastest point moves at most half
/// a voxel per speed update — capped by `options.timeStep` when it is set. Years.
inline double speleothemStep(const SpeleothemOptions& options, double h, double vmax) {
    const double dt = 0.5 * h / vmax;
    return options.timeStep > 0 ? std::min(dt, options.timeStep) : dt;
}

/// What a run writes besides the grids.
struct OutputOptions {
    MeshStyle meshStyle = MeshStyle::kSmooth;
    int imageWidth = 1024;  ///< pixels
    bool images = true;
    bool mesh = true;
    CaveExtent cave = CaveExtent::kChannels;
    /// Files for other tools, besides cave.obj/.ply, state.vdb and the skeleton files.
    std::vector<ExportFormat> formats{ExportFormat::kGlb, ExportFormat::kVtk, ExportFormat::kSvx, ExportFormat::kCsv};
    MeshNormals meshNormals = MeshNormals::kOutward;  ///< of cave.glb
};

}  // namespace cavesim

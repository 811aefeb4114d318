/// @file domain.h
/// @brief The simulation state: dense voxel grids built from a scenario.
///
/// Dense arrays (see core/grid.h, 25 bytes a voxel) rather than OpenVDB trees; stage 2 keeps its
/// per-iteration state on active 8³ tiles only (sim/stage2_steps.h). OpenVDB is used only at the
/// edges (state.vdb output, meshing).
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "core/grid.h"
#include "sim/scenario.h"

namespace cavesim {

/// Per-voxel flag bits.
enum VoxelFlag : std::uint8_t {
    kSource = 1u << 0,          ///< injects water (stage 2), seeds a zone (stage 1)
    kSink = 1u << 1,            ///< drains water; pressure 0
    kProtochannel = 1u << 2,    ///< traced by stage 1 or given as [[rock.channel]]
    kChannel = 1u << 3,         ///< eroded past the channel threshold in stage 2 (the cave)
    kObstacle = 1u << 4,        ///< inside a spherical obstacle
    kFracture = 1u << 5,        ///< inside a bedding plane or fracture slab
    kFeatureChannel = 1u << 6,  ///< inside a [[rock.channel]] polyline
    /// Not karst rock ([site]): air above the land surface or insoluble rock below the base of the
    /// limestone. Porosity 0 (holds no water), never eroded, never cave.
    kInert = 1u << 7
};

/// Explicit random engine, always passed by reference (never copied, never global).
using Rng = std::mt19937_64;

struct Domain {
    Dims dims;
    double voxelSize = 1.0;  ///< metres
    /// World position (metres) of the block's low corner, voxel (0, 0, 0)'s corner: `[site] origin`
    /// (0 without a site). World = origin + index-space metres; the grids do not depend on it.
    std::array<double, 3> origin{0, 0, 0};

    Grid3<float> porosity;   ///< R in [0, 1]: water capacity
    Grid3<float> porosity0;  ///< R at build time
    Grid3<std::uint8_t> flags;
    Grid3<std::int32_t> zone;  ///< stage-1 zone = source index, -1 where none
    Grid3<float> pressure;     ///< stage 2
    Grid3<float> water;        ///< stage 2 contents W in [0, R]
    Grid3<float> flow;         ///< stage 2 flow f of the last iteration
    /// 1 on an inception horizon ([[rock.inception_horizon]]) or a fracture of a family
    /// ([[rock.fracture_family]]), else 0; empty without either: early-flow paths. Stage 2
    /// reads such a voxel's pressure rate from its porosity against `rockPorosity` (stage2.h).
    Grid3<std::uint8_t> inception;
    float rockPorosity = 0.f;  ///< the background porosity `[rock] porosity`

    /// Linear voxel indices of each source / sink, in scenario order.
    std::vector<std::vector<std::size_t>> sourceVoxels;
    std::vector<double> sourcePressure;  ///< relative pressure of each source
    std::vector<std::vector<std::size_t>> sinkVoxels;
    /// A site's water table (`[site] water_table`): per column i + nx · j, the table's height z in
    /// voxel index units (voxel centres at integer k); empty without one.
    std::vector<double> siteWaterTable;
};

/// A domain of `dims` voxels of `voxelSize` metres, uniform porosity (porosity0 the same), no
/// flags, zone −1, zero pressure, water and flow, no sources or sinks: the starting point of
/// `buildDomain`, and of hand-made domains in tests and benchmarks.
Domain emptyDomain(const Dims& dims, double voxelSize, float porosity);

/// Builds the porosity grid and flags from a validated scenario. Deterministic for `rng`'s state.
/// @throw InputError if the scenario describes something impossible (caught by validation first).
Domain buildDomain(const Scenario& scenario, Rng& rng);

/// Sets the sources and sinks of `scenario` in `domain`: their voxels (boxes clipped to the
/// grid), the sources' relative pressures and the kSource / kSink flags. Sources in order: the
/// `[[source]]` entries, the recharge's (sim/recharge.h), a site's sinkholes. Part of `buildDomain`;
/// also recovers the terminals of a run from its scenario when its grids are read back.
void placeTerminals(Domain& domain, const Scenario& scenario);

/// World position (metres) of a voxel centre.
inline std::array<double, 3> worldFromIndex(const Index3& p, double voxelSize) {
    return {(p.i + 0.5) * voxelSize, (p.j + 0.5) * voxelSize, (p.k + 0.5) * voxelSize};
}

}  // namespace cavesim

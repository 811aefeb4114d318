/// @file stage2_checkpoint.h
/// @brief Stage 2 between two iterations, as bytes: everything `runStage2` (stage2.h) carries from
/// one iteration to the next, so that a run stopped after iteration K and continued from these
/// bytes gives the same bits as one that never stopped (checkpoint and resume, app/checkpoint.h).
///
/// The bytes hold the domain grids stage 2 changes (porosity, flags, flow, water, pressure), the
/// dense water contents, the pressure rates and the pressure field with its pending sweep
/// (fastmarch::EikonalField::save), the active tiles with every per-tile and per-voxel transient
/// (stage2_steps.h `Stage2State`), the reach of the sinks, the source refill levels and the result
/// so far (history, events, totals, the records of the base-level phases done and of the phase in
/// progress). Neither the porosity0 and zone grids (stage 1 fixes them) nor
/// the terminals are stored: the state is restored onto the domain stage 1 and `prepareStage2`
/// give, as `runStage2` started from it. What a phase sets up and the scenario fixes (its water
/// table, the vadose mask, which sinks drain and the flags of the others, the gravity potential) is
/// not stored either: `runStage2` derives it again from the phases and the iteration.
///
/// Two layouts are read: the current one (magic "STE3") and the one before phases could be
/// checkpointed ("STE2", written by checkpoint format version 1), which has no phase records.
#pragma once

#include <string>
#include <vector>

#include "core/bytes.h"
#include "core/grid.h"
#include "fastmarch/fast_marching.h"
#include "sim/domain.h"
#include "sim/stage2.h"
#include "sim/stage2_steps.h"

namespace cavesim::stage2 {

/// What runStage2 carries from one iteration to the next besides the domain.
struct Carry {
    explicit Carry(const Dims& dims) : state(dims) {}
    int iteration = 0;    ///< iterations done
    Stage2Result result;  ///< so far (its times too: they continue; `phases`: the phases done)
    /// The record of the base-level phase in progress (the one holding `iteration`), as far as it
    /// went; a default record in a run without phases.
    Stage2PhaseRecord phase;
    std::vector<Refill> refill;  ///< source voxels and their refill levels
    double stored = 0;           ///< water in the domain after `iteration`
    Grid3<float> rate;           ///< pressure rate of each voxel (only falls)
    fastmarch::EikonalField pressure;
    Stage2State state;
};

/// Appends the Stage2State's bytes (everything but `neighbourBase`, which `refreshTiles` derives
/// from the active tiles, and `tileWater`, which `recountWater` derives from the water).
void saveState(ByteWriter& out, const Stage2State& state);

/// Replaces `state` (made for the grid's dims) by what saveState wrote; checks every count against
/// the grid and the active tiles.
/// @throw InputError (from `in`) on bytes that are not such a state
void restoreState(ByteReader& in, Stage2State& state);

/// The bytes of `carry` and of the domain grids stage 2 changes.
std::string encodeCarry(const Carry& carry, const Domain& domain);

/// Restores `carry` (made for the domain's dims) and the domain grids stage 2 changes from bytes
/// encodeCarry wrote for the same grid and number of sources; `shown` names them in messages.
/// @throw InputError on bytes that are not such a state (never reads out of bounds)
void decodeCarry(const std::string& bytes, const std::string& shown, Carry& carry, Domain& domain);

}  // namespace cavesim::stage2

/// @file simulate.h
/// @brief A scenario's whole simulation in memory: the domain, stage 1, the interim step and
/// stage 2, in the order and with the random draws of a run (app/pipeline.cpp), without outputs.
#pragma once

#include "core/progress.h"
#include "sim/domain.h"
#include "sim/scenario.h"

namespace cavesim {

/// The final domain of `scenario`: built from its seed, then the enabled stages. Equal, grid for
/// grid, to the state a run of the same scenario writes (tests/app checks this).
/// @throw InputError for limits the scenario exceeds; RuntimeError on a failure while running
Domain simulate(const Scenario& scenario, const ProgressFn& progress = {});

}  // namespace cavesim

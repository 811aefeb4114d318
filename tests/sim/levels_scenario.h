/// @file
/// @brief A test scenario shared by tests/sim: base-level phases on a vertical section.
///
/// Two springs on the +x face drain a source at the top: phase 1 drains the upper spring under a
/// water table at z = 20 (the upper spring joins the source: a breakthrough of the phase), phase 2
/// the lower one under a table at z = 5 (a shaft cuts down to a lower level). Used by
/// test_stage2.cpp ("PhasesConserveWaterAndGrowALowerLevel") and test_stage2_checkpoint.cpp.
#pragma once

namespace cavesim::test {

inline constexpr const char* kLevelsScenario = R"(name = "levels"
seed = 4
[domain]
size = [48, 1, 30]
[rock]
porosity = 0.05
[[source]]
at = [8, 0, 29]
[[sink]]
box = [[47, 0, 19], [47, 0, 21]]
[[sink]]
box = [[47, 0, 4], [47, 0, 6]]
[stage1]
enabled = false
[stage2]
p_rate = 0.05
p_rate_channel = 0.001
[[phase]]
iterations = 150
water_table = 20
sinks = [1]
[[phase]]
iterations = 150
water_table = 5
sinks = [2]
)";

}  // namespace cavesim::test

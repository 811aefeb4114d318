/// @file colormap.h
/// @brief Colour maps: a perceptually uniform one for scalars and a distinct-colour palette for ids.
#pragma once

#include <cstdint>

#include "render/image.h"

namespace cavesim::render {

/// matplotlib's viridis (its 256-entry table, linear between entries: entry i at t = i/255),
/// dark blue → green → yellow; t in [0, 1] (clamped, NaN as 0).
Rgb viridis(double t);
/// matplotlib's inferno (256-entry table as viridis), black → red → yellow → white, for flow.
Rgb inferno(double t);
/// Warm-to-cool ramp used for depth cues in 3D views: near = warm sand, far = slate blue.
Rgb depthRamp(double t);
/// Distinct colours for zone ids (cycled after 12); negative ids give light grey.
Rgb zoneColour(int id);

/// Common fixed colours.
namespace colours {
inline constexpr Rgb kWhite{255, 255, 255};
inline constexpr Rgb kBlack{0, 0, 0};
inline constexpr Rgb kText{25, 25, 30};
inline constexpr Rgb kGrey{150, 150, 150};
inline constexpr Rgb kLightGrey{225, 225, 225};
inline constexpr Rgb kRock{205, 198, 186};
inline constexpr Rgb kSource{220, 30, 40};
inline constexpr Rgb kSink{30, 90, 220};
inline constexpr Rgb kChannelOutline{255, 255, 255};
}  // namespace colours

}  // namespace cavesim::render

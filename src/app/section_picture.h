/// @file section_picture.h
/// @brief images/sections.png: representative passage cross-sections (morpho/cross_sections.h),
/// drawn as the sampled slices, a column per class.
#pragma once

#include <string>

#include "morpho/cross_sections.h"
#include "render/image.h"

namespace cavesim::app {

/// Examples drawn per class: the longest passages of that class (ties: lowest id).
inline constexpr int kSectionExamplesPerClass = 3;

/// The picture: one column per class present (tube, canyon, keyhole, other), up to
/// kSectionExamplesPerClass panels each, the slice of each passage's example station drawn as
/// its samples (cave coloured by class over rock), looking along the passage, up at the top, a
/// scale bar and the passage's id, elevation, width and height. An empty image (0 × 0) when no
/// passage has a section.
render::Image sectionsPicture(const morpho::CrossSections& sections, const std::string& title);

/// Writes imagesDir/sections.png; nothing when there is no section.
/// @return the file name written, relative to imagesDir, or "" when none
/// @throw RuntimeError when the file cannot be written
std::string writeSectionsPicture(const morpho::CrossSections& sections, const std::string& title,
                                 const std::string& imagesDir);

}  // namespace cavesim::app

/// @file cross_sections.h
/// @brief Passage cross-sections from the voxels across the centreline: width, height and a
/// class — tube, canyon, keyhole or other (Palmer 2007; Paris et al. 2021 draw the same three
/// shapes) — per station and per passage. Rules and reasons: docs/geology.md, "Cross-sections".
///
/// A *station* is a centreline node of a passage (`findBranches`), every `stationStride`-th and
/// at least the previous station's radius along the chain from it, leaving out the passage's two
/// end nodes and the nodes within 1.5 junction radii + one voxel (along the chain) of a junction
/// end, where passages merge; a passage left without a station is `kShort`: listed, not
/// classified, no width or height. At a station the *slice* is the vertical plane through the
/// node perpendicular to the passage's horizontal heading (a surveyor's cross-section; a vertical
/// passage is sliced across north), sampled every `step` = voxel size / `samplesPerVoxel` on a
/// grid centred on the node: a sample is cave when the voxel holding it is. The section is the
/// 4-connected set of cave samples that holds the centre sample (or, when the smoothed node falls
/// outside the cave, the sample nearest it that is cave). Passages are measured in parallel, each
/// into its own slot: the result does not depend on the thread count.
///
/// Measures of a section (metres): height H = rows × step; width W = the widest row (cave samples
/// in the row × step); area = samples × step². Class, in this order:
///  - **keyhole**: some split between rows leaves a lower part (the slot) and an upper part each at
///    least `keyholeMinPart` · H high, the slot's widest row at most `keyholeSlotRatio` × the upper
///    part's widest row, and the upper part rounded above (its top row at most `keyholeTopRatio`
///    × its widest row: a V-shaped canyon, widest at the top, is not a keyhole);
///  - **canyon**: H ≥ `canyonRatio` · W;
///  - **tube**: W/H in [`tubeLow`, `tubeHigh`] and area ≥ `tubeFill` · W · H (an ellipse fills
///    π/4 ≈ 0.79 of its box; an L or a cross fills less);
///  - **other**: anything else (wide low sections, irregular ones).
/// A passage's class is the majority of its stations (ties: tube, canyon, keyhole, other); its
/// width and height are the medians over its stations.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/grid.h"
#include "core/vec3.h"
#include "morpho/skeleton_graph.h"

namespace cavesim::morpho {

/// The shape classes, and `kShort` for a passage with no station clear of its junctions (a stub
/// between two close junctions, where any slice cuts the junction chamber): not classified.
enum class SectionClass { kTube = 0, kCanyon = 1, kKeyhole = 2, kOther = 3, kShort = 4 };
/// The shape classes a station can get (kTube … kOther).
inline constexpr int kSectionClasses = 4;
/// "tube", "canyon", "keyhole", "other", "short".
const char* sectionClassName(SectionClass c);

/// Thresholds (docs/geology.md gives the reasons). Not scenario keys.
struct SectionOptions {
    double tubeLow = 0.67;          ///< lowest W/H of a tube
    double tubeHigh = 1.5;          ///< highest W/H of a tube
    double tubeFill = 0.6;          ///< least area / (W · H) of a tube
    double canyonRatio = 1.5;       ///< a canyon is at least this many times higher than wide
    double keyholeSlotRatio = 0.6;  ///< slot width / upper width at most this
    double keyholeMinPart = 0.25;   ///< slot and upper part each at least this share of H
    double keyholeTopRatio = 0.8;   ///< top row / widest row of the upper part at most this
    int samplesPerVoxel = 2;        ///< slice samples per voxel edge, ≥ 1
    int stationStride = 2;          ///< every n-th node of a passage is a station, ≥ 1
};

/// A sampled slice: `cols` × `rows` samples, row 0 at the top, 1 = in the section.
struct SectionSlice {
    int cols = 0, rows = 0;
    double step = 0;                  ///< metres between samples
    std::vector<std::uint8_t> cells;  ///< row-major, rows × cols
    bool clipped = false;             ///< the section reaches the slice border (larger than sampled)
};

/// Width, height, area and class of one section.
struct SectionShape {
    double width_m = 0, height_m = 0, area_m2 = 0;
    SectionClass cls = SectionClass::kOther;
};

/// Measures and classifies a slice (cells already reduced to the one section).
SectionShape measureSection(const SectionSlice& slice, const SectionOptions& options = {});

/// The slice of the cave at `position` across `heading` (see the file comment), `halfCols` /
/// `halfRows` samples either side of the centre, reduced to the section holding the centre.
/// @param mask       cave mask, index space
/// @param voxelSize  metres, > 0
/// @param position   metres, world space
/// @param heading    passage direction, world axes (only its horizontal part counts)
SectionSlice sliceAcross(const Grid3<std::uint8_t>& mask, double voxelSize, const Vec3d& position, const Vec3d& heading,
                         int halfCols, int halfRows, int samplesPerVoxel);

/// The cross-section of one passage.
struct PassageSection {
    int passage = 0;                           ///< position in findBranches
    double length_m = 0;                       ///< centreline length
    double width_m = 0, height_m = 0;          ///< medians over the stations
    double z_m = 0, z_min_m = 0, z_max_m = 0;  ///< mean, lowest and highest node elevation
    SectionClass cls = SectionClass::kOther;
    std::array<int, kSectionClasses> votes{};  ///< stations of each class
    SectionSlice example;                      ///< a station of the passage's class nearest its median shape
    SectionShape exampleShape;
};

struct CrossSections {
    std::vector<PassageSection> passages;
    int stations = 0;
};

/// Cross-sections of every passage of the skeleton.
/// @param mask       cave mask the skeleton was made from, index space
/// @param voxelSize  metres, > 0
/// @throw InternalError on an invalid skeleton, voxel size or options
CrossSections measureCrossSections(const Grid3<std::uint8_t>& mask, double voxelSize, const Skeleton& skeleton,
                                   const SectionOptions& options = {});

/// report.json "cross_sections": {"stations", "summary": [per class, "short" last: passages, length_m,
/// mean_width_m, mean_height_m, mean_w_over_h, z_mean_m (length-weighted), z_min_m, z_max_m],
/// "passages": [per passage: id, class, length_m, width_m, height_m, w_over_h, z_m, z_min_m,
/// z_max_m, votes]}.
nlohmann::json toJson(const CrossSections& c);

}  // namespace cavesim::morpho

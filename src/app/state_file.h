/// @file state_file.h
/// @brief The run's state in a format whose reader we control: `state.cavesim`, what `cavesim
/// report` reads back (state.vdb is the same grids as an OpenVDB export, never read by cavesim).
///
/// Layout, little-endian: the magic "CAVESIM-STATE\n\0\0" (16 bytes), u32 version (1), u32 nx, ny,
/// nz, f64 voxel size (m), u32 number of grids (at most kMaxStateGrids); per grid: u8 name length
/// (1-32), the name ([a-z0-9_]), u8 type (1 float32, 2 int32), u32 number of chunks, u64 FNV-1a of
/// the grid's raw values; per chunk: u32 values in it (at most kStateChunkValues), u32 compressed
/// bytes, then that many bytes of zlib data; after the last grid, u64 FNV-1a of every byte before.
/// Chunks hold kStateChunkValues values each (the last fewer), so the reader never allocates
/// more than the grid the caller expects, and decompresses into buffers of exactly known size.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/grid.h"

namespace cavesim::app {

inline constexpr int kMaxStateGrids = 16;
inline constexpr std::uint32_t kStateChunkValues = 1u << 20;

/// One named grid of a state file: exactly one of `floats`, `ints` is set.
struct StateGridRef {
    std::string name;
    const Grid3<float>* floats = nullptr;
    const Grid3<std::int32_t>* ints = nullptr;
};

/// One grid read back.
struct StateGrid {
    std::string name;
    bool isFloat = true;
    Grid3<float> floats;
    Grid3<std::int32_t> ints;
};

struct StateContents {
    Dims dims;
    double voxelSize = 0;  ///< m
    std::vector<StateGrid> grids;
};

/// The bytes of a state file holding `grids` (all of dims `dims`) with voxel size `voxelSize` (m).
/// Deterministic: the same grids give the same bytes whatever the thread count.
std::string encodeState(const Dims& dims, double voxelSize, const std::vector<StateGridRef>& grids);

/// Reads a state file's bytes; `shown` names the file in messages. Every size, count, name and
/// checksum is checked before it is used; the grid must be `expected` (voxels) unless
/// `expected.count() == 0`, when any grid of at most `maxVoxels` voxels is accepted.
/// @throw InputError naming `shown` and what is wrong, for any content that is not a state file
///        this program wrote (never crashes or reads out of bounds, whatever the bytes)
StateContents decodeState(const std::string& bytes, const std::string& shown, const Dims& expected,
                          std::size_t maxVoxels = std::size_t(1) << 24);

}  // namespace cavesim::app

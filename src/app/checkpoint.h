/// @file checkpoint.h
/// @brief Checkpoints of a run (`cavesim run --checkpoint-every N`) and what `cavesim resume`
/// reads back to finish it with the same files, byte for byte, as a run that never stopped.
///
/// **Where.** A run into `DIR` keeps its checkpoint in `.NAME.checkpoint/checkpoint.cavesim` beside
/// `DIR` (NAME = DIR's name), not in the hidden staging folder: the staging folder is removed when
/// a run is stopped or fails, and by the next run after a kill; the checkpoint folder stays until a
/// run into `DIR` succeeds. One file, replaced atomically (core/atomic_file.h) at each checkpoint, so
/// it always holds the newest complete checkpoint.
///
/// **What.** How the run was asked for (the scenario file's text and path, `--seed`, `--formats`,
/// `--mesh-style`, `--mesh-normals`, `--force`), a hash of the effective scenario, a fingerprint of
/// the domain at the start of stage 2, the stage-2 pictures taken so far (`images/iter_*.png` and
/// their reduced frames for `images/sequence.png`) and stage 2's whole state after the iteration
/// (sim/stage2_checkpoint.h). Stage 1 is not stored: `resume` builds the domain and runs stage 1
/// again (deterministic, and cheap beside stage 2), which also rewrites `stage1.vdb` and
/// `images/zones.png`, and refuses to go on unless the domain matches the fingerprint.
///
/// **Layout**, little-endian: the magic "CAVESIM-CHECKPT\n" (16 bytes), u32 version (2; 1 is still
/// read: the same layout, its stage-2 state without phase records), u64 bytes
/// of the payload, u32 number of chunks; per chunk: u32 payload bytes in it (at most 4 MiB), u32
/// compressed bytes, then that many bytes of zlib data; u64 FNV-1a of the payload; u64 FNV-1a of every
/// byte before. The payload is a ByteWriter stream (core/bytes.h), checked as it is read.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "render/image.h"
#include "sim/domain.h"
#include "sim/options.h"
#include "sim/scenario.h"

namespace cavesim::app {

inline constexpr const char* kCheckpointFile = "checkpoint.cavesim";

/// The checkpoint folder of runs into `target`: `.NAME.checkpoint` beside it.
std::filesystem::path checkpointDir(const std::filesystem::path& target);

/// A run's checkpoint, decoded.
struct Checkpoint {
    // How the run was asked for.
    std::string scenarioPath;  ///< as given; empty: the built-in default
    std::string scenarioText;  ///< the scenario file's text as the run read it
    std::optional<std::string> seed;
    std::optional<std::string> formats;
    std::optional<MeshStyle> meshStyle;
    std::optional<MeshNormals> meshNormals;
    bool force = false;
    int every = 0;                   ///< iterations between checkpoints
    std::uint64_t scenarioHash = 0;  ///< FNV-1a of the effective scenario (scenarioToToml)
    std::uint64_t domainHash = 0;    ///< domainFingerprint at the start of stage 2
    int iteration = 0;               ///< stage-2 iterations done
    /// Files of the staging folder written during stage 2 so far (path relative to it, bytes).
    std::vector<std::pair<std::string, std::string>> files;
    std::vector<render::Image> frames;  ///< reduced stage-2 frames for images/sequence.png
    std::string stage2;                 ///< stage 2's state (sim/stage2_checkpoint.h)
};

/// The bytes of a checkpoint file.
std::string encodeCheckpoint(const Checkpoint& checkpoint);

/// Reads a checkpoint file's bytes; `shown` names the file in messages.
/// @throw InputError naming `shown` and what is wrong for any content that is not a complete
///        checkpoint this program wrote (never crashes or reads out of bounds, whatever the bytes)
Checkpoint decodeCheckpoint(const std::string& bytes, const std::string& shown);

/// FNV-1a of the effective scenario (scenarioToToml of `scenario`, its [site] loaded): a resumed run
/// must read the same scenario.
std::uint64_t scenarioHash(const Scenario& scenario);

/// FNV-1a of the domain grids stage 1 and the interim step settle (porosity, porosity0, flags,
/// zone) and of the sources' pressures and the site's water table, which stage 2 reads: a resumed
/// run's domain must be the same.
std::uint64_t domainFingerprint(const Domain& domain);

/// Checks that `domainHash` (domainFingerprint at the start of stage 2 of a resumed run) is the
/// one `resume` was made from.
/// @throw InputError naming `shown` (the checkpoint's file), ending with `advice`, when it is not
void checkResumedDomain(std::uint64_t domainHash, const Checkpoint& resume, const std::string& shown,
                        const std::string& advice);

}  // namespace cavesim::app

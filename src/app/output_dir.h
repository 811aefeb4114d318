/// @file output_dir.h
/// @brief An output directory that appears complete or not at all.
///
/// Everything is written into a hidden staging directory beside the target; `commit()` renames it
/// into place (replacing an old directory only when `force` was given). If the run fails, the
/// staging directory is removed and the target is left exactly as it was.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace cavesim::app {

class OutputDir {
public:
    /// Checks the target before any work starts (the path is made absolute and normalised).
    /// @throw InputError if `target` exists and is not a directory, is not empty and `force` is
    ///        false, is the current directory, one of its parents or the root, or lies under a
    ///        non-directory or a directory that cannot be written
    OutputDir(std::filesystem::path target, bool force);
    ~OutputDir();
    OutputDir(const OutputDir&) = delete;
    OutputDir& operator=(const OutputDir&) = delete;

    /// Creates the staging directory (call once the run is about to write), after removing the
    /// staging directories that killed runs left beside the target.
    /// @throw InputError if it cannot be created
    void open();
    /// Path of a file inside the staging directory (subdirectories are created).
    std::filesystem::path file(const std::string& relative) const;
    /// Moves the staging directory into place.
    /// @throw RuntimeError on a file-system failure (the target is then unchanged)
    void commit();

    const std::filesystem::path& target() const { return target_; }
    /// The staging directory (empty before open()).
    const std::filesystem::path& staging() const { return staging_; }

private:
    std::filesystem::path target_, staging_;
    std::vector<std::filesystem::path> createdParents_;  ///< parents open() created, deepest first
    bool force_ = false, committed_ = false;
};

}  // namespace cavesim::app

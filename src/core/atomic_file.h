/// @file atomic_file.h
/// @brief Writing a file so that it appears whole or not at all, on disk, and never through a symlink.
///
/// Every byte a run writes goes through `writeFileAtomic`: each write is checked (a short write, a
/// full file system, a file-size limit are errors naming the file and the reason), the file is
/// `fsync`ed before it is renamed into place and its folder is `fsync`ed after, so a crash or a
/// power cut leaves the old file or the new one, never a cut one.
#pragma once

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

#include "core/error.h"

namespace cavesim {

/// Flushes a directory's entries (names created, renamed or removed in it) to disk.
/// @throw RuntimeError naming `dir` and the reason when it cannot be opened or synced
inline void syncDirectory(const std::filesystem::path& dir) {
    const std::filesystem::path d = dir.empty() ? std::filesystem::path(".") : dir;
    const int fd = ::open(d.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) throw RuntimeError("cannot sync folder " + d.string() + ": " + std::strerror(errno));
    const int rc = ::fsync(fd);
    const int err = errno;
    ::close(fd);
    // Some file systems do not sync directories (EINVAL): nothing more can be done there.
    if (rc != 0 && err != EINVAL && err != EROFS)
        throw RuntimeError("cannot sync folder " + d.string() + ": " + std::strerror(err));
}

/// Writes the concatenation of `pieces` to `path` through a new temporary file beside it, `fsync`
/// and a rename; then the folder is synced. The pieces are written where they lie (no copy joins
/// them), so a large file made of a header and grids needs no second copy of the grids in memory.
/// The temporary name is unique to this process and call and is created exclusively (O_CREAT |
/// O_EXCL | O_NOFOLLOW), so a file, directory or symlink already lying there is never written
/// through or clobbered; a symlink at `path` itself is replaced, not followed.
/// @throw RuntimeError "cannot write PATH: REASON" if any step fails (the temporary is removed and
///        `path` is left as it was)
inline void writeFileAtomic(const std::string& path, const std::vector<std::string_view>& pieces) {
    namespace fs = std::filesystem;
    static std::atomic<unsigned> counter{0};
    const fs::path target(path);
    fs::path tmp;
    int fd = -1;
    for (int attempt = 0; fd < 0; ++attempt) {  // a name already taken by something else: the next one
        tmp = target.parent_path() / ("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                                      std::to_string(counter++));
        fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
        if (fd < 0 && (errno != EEXIST || attempt == 100))
            throw RuntimeError("cannot write " + path + ": cannot create " + tmp.string() + ": " +
                               std::strerror(errno));
    }
    std::string why;  // empty while every step succeeds
    std::size_t total = 0, done = 0;
    for (const std::string_view& piece : pieces) total += piece.size();
    for (const std::string_view& piece : pieces) {
        std::size_t at = 0;
        while (why.empty() && at < piece.size()) {
            const ssize_t n = ::write(fd, piece.data() + at, piece.size() - at);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) {  // 0 cannot happen for a regular file; report it rather than loop
                why = n < 0 ? std::strerror(errno) : "no bytes written";
                why += " after " + std::to_string(done) + " of " + std::to_string(total) + " bytes";
                break;
            }
            at += std::size_t(n);
            done += std::size_t(n);
        }
        if (!why.empty()) break;
    }
    if (why.empty() && ::fsync(fd) != 0) why = std::string("cannot sync: ") + std::strerror(errno);
    if (::close(fd) != 0 && why.empty()) why = std::strerror(errno);
    std::error_code ec;
    if (why.empty()) {
        fs::rename(tmp, target, ec);
        if (ec) why = ec.message();
    }
    if (!why.empty()) {
        fs::remove(tmp, ec);
        throw RuntimeError("cannot write " + path + ": " + why);
    }
    try {
        syncDirectory(target.parent_path());
    } catch (const RuntimeError& e) {
        throw RuntimeError("cannot write " + path + ": " + e.what());
    }
}

/// Writes `text` to `path` as `writeFileAtomic(path, {text})` does.
inline void writeFileAtomic(const std::string& path, const std::string& text) {
    writeFileAtomic(path, std::vector<std::string_view>{std::string_view(text)});
}

/// A whole file's bytes.
/// @throw RuntimeError "cannot read PATH" when it cannot be opened
inline std::string readFileBytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw RuntimeError("cannot read " + path.string());
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace cavesim

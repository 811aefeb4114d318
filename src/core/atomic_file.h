/// @file atomic_file.h
/// @brief Writing a file so that it appears whole or not at all, and never through a symlink.
#pragma once

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>

#include <fcntl.h>
#include <unistd.h>

#include "core/error.h"

namespace cavesim {

/// Writes `text` to `path` through a new temporary file beside it and a rename. The temporary name
/// is unique to this process and call and is created exclusively (O_CREAT | O_EXCL | O_NOFOLLOW),
/// so a file, directory or symlink already lying there is never written through or clobbered; a
/// symlink at `path` itself is replaced, not followed.
/// @throw RuntimeError if the file cannot be written or renamed (the temporary is removed)
inline void writeFileAtomic(const std::string& path, const std::string& text) {
    namespace fs = std::filesystem;
    static std::atomic<unsigned> counter{0};
    const fs::path target(path);
    fs::path tmp;
    int fd = -1;
    for (int attempt = 0; fd < 0; ++attempt) {  // a name already taken by something else: the next one
        tmp = target.parent_path() /
              ("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
        fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
        if (fd < 0 && (errno != EEXIST || attempt == 100))
            throw RuntimeError("cannot create " + tmp.string() + ": " + std::strerror(errno));
    }
    std::size_t done = 0;
    bool ok = true;
    while (done < text.size()) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            ok = false;
            break;
        }
        done += std::size_t(n);
    }
    ok = (::close(fd) == 0) && ok;
    std::error_code ec;
    if (ok) fs::rename(tmp, target, ec);
    if (!ok || ec) {
        const std::string why = ok ? ec.message() : std::string(std::strerror(errno));
        fs::remove(tmp, ec);
        throw RuntimeError("cannot write " + path + ": " + why);
    }
}

}  // namespace cavesim

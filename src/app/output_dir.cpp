#include "app/output_dir.h"

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/atomic_file.h"
#include "core/error.h"

namespace fs = std::filesystem;

namespace cavesim::app {

namespace {

/// True when `a` is `b` or one of its ancestors (both absolute and normalised).
bool isSameOrAncestor(const fs::path& a, const fs::path& b) {
    auto ia = a.begin(), ib = b.begin();
    for (; ia != a.end() && !ia->empty(); ++ia, ++ib)
        if (ib == b.end() || *ia != *ib) return false;
    return true;
}

/// The file inside a staging directory that names the process writing it: host, PID and the
/// process's start time (so a PID reused by another process is not mistaken for the run).
constexpr const char* kOwnerFile = ".cavesim-owner";

std::string hostName() {
    char buf[256] = {};
    if (::gethostname(buf, sizeof buf - 1) != 0) return "?";
    return buf;
}

/// Start time of process `pid` in clock ticks since boot (field 22 of /proc/PID/stat), or "" when
/// there is no such process.
std::string startTime(long pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
    std::string line;
    if (!std::getline(in, line)) return "";
    const std::size_t close = line.rfind(')');  // the command name may hold spaces and parentheses
    if (close == std::string::npos) return "";
    std::istringstream rest(line.substr(close + 2));
    std::string field;
    for (int n = 3; n <= 22 && (rest >> field); ++n) {
        if (n == 22) return field;
    }
    return "";
}

std::string ownerLine(long pid) {
    return hostName() + " " + std::to_string(pid) + " " + startTime(pid);
}

/// True when the staging directory `dir`, named for process `pid`, belongs to a process of this
/// machine that no longer runs. Without an owner file (or written on another host) only a PID
/// that does not exist here and ten minutes without change say so: on a shared file system the
/// PID may belong to another machine.
bool ownerIsGone(const fs::path& dir, long pid) {
    std::ifstream in(dir / kOwnerFile);
    std::string host, pidText, start;
    if (in >> host >> pidText >> start && host == hostName() && pidText == std::to_string(pid)) {
        const std::string now = startTime(pid);
        return now.empty() || now != start;
    }
    std::error_code ec;
    const auto settled = fs::file_time_type::clock::now() - std::chrono::minutes(10);
    const auto modified = fs::last_write_time(dir, ec);
    if (ec || modified > settled) return false;
    return ::kill(pid_t(pid), 0) == -1 && errno == ESRCH;
}

/// The PID in a name this program gives its hidden directories, `.NAME.partial-PID[-N]` and
/// `.NAME.old-PID[-N]` (`tag` is ".partial-" or ".old-"), or 0 when `f` is not such a name.
long pidInName(const std::string& f, const std::string& tag) {
    const std::size_t at = f.rfind(tag);
    if (f.empty() || f[0] != '.' || at == std::string::npos || at == 0) return 0;
    std::string rest = f.substr(at + tag.size());
    const std::size_t dash = rest.find('-');
    if (dash != std::string::npos) {
        const std::string n = rest.substr(dash + 1);
        if (n.empty() || n.size() > 3 || n.find_first_not_of("0123456789") != std::string::npos) return 0;
        rest = rest.substr(0, dash);
    }
    if (rest.empty() || rest[0] == '0' || rest.size() > 9 || rest.find_first_not_of("0123456789") != std::string::npos)
        return 0;
    return std::stol(rest);
}

/// Staging (`.NAME.partial-PID`) and set-aside (`.NAME.old-PID`) directories that runs of any
/// target in `parent` left behind when they were killed are removed; those of live runs are left
/// alone (see ownerIsGone).
void removeStaleSiblings(const fs::path& parent) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(parent, ec)) {
        const std::string f = e.path().filename().string();
        for (const std::string tag : {".partial-", ".old-"}) {
            const long pid = pidInName(f, tag);
            if (pid == 0 || pid == long(::getpid())) continue;
            std::error_code ec2;
            if (e.is_symlink(ec2) || !e.is_directory(ec2)) continue;  // only real directories
            if (ownerIsGone(e.path(), pid)) fs::remove_all(e.path(), ec2);
        }
    }
}

/// Holds an exclusive flock on a directory while it lives: runs that move results into the same
/// folder take turns (another run's set-aside and rename never interleave with this one's).
class DirectoryLock {
public:
    explicit DirectoryLock(const fs::path& dir) : fd_(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)) {
        if (fd_ < 0) throw RuntimeError("cannot lock " + dir.string() + ": " + std::strerror(errno));
        while (::flock(fd_, LOCK_EX) != 0) {
            if (errno == EINTR) continue;
            const int err = errno;
            ::close(fd_);
            throw RuntimeError("cannot lock " + dir.string() + ": " + std::strerror(err));
        }
    }
    ~DirectoryLock() { ::close(fd_); }  // closing releases the lock
    DirectoryLock(const DirectoryLock&) = delete;
    DirectoryLock& operator=(const DirectoryLock&) = delete;

private:
    int fd_;
};

/// Syncs `dir` and every directory below it (the files were synced as they were written).
void syncTree(const fs::path& dir) {
    std::error_code ec;
    for (const auto& e : fs::recursive_directory_iterator(dir, ec))
        if (!e.is_symlink(ec) && e.is_directory(ec)) syncDirectory(e.path());
    if (ec) throw RuntimeError("cannot list " + dir.string() + ": " + ec.message());
    syncDirectory(dir);
}

/// True when `dir` (absolute, normalised) is a mount point: another device than its parent, or
/// listed in /proc/self/mountinfo (a bind mount keeps its device).
bool isMountPoint(const fs::path& dir) {
    struct stat here {
    }, above{};
    if (::stat(dir.c_str(), &here) == 0 && ::stat(dir.parent_path().c_str(), &above) == 0 &&
        here.st_dev != above.st_dev)
        return true;
    std::ifstream info("/proc/self/mountinfo");
    for (std::string line; std::getline(info, line);) {
        // Fields: id parent major:minor root mount-point ...; spaces in paths are written as \040.
        std::istringstream fields(line);
        std::string field;
        for (int n = 0; n < 5; ++n) fields >> field;
        std::string point;
        for (std::size_t c = 0; c < field.size(); ++c) {
            const bool octal =
                field[c] == '\\' && c + 3 < field.size() && field.find_first_not_of("01234567", c + 1) >= c + 4;
            if (octal) {
                point += char(std::stoi(field.substr(c + 1, 3), nullptr, 8));
                c += 3;
            } else {
                point += field[c];
            }
        }
        if (fs::path(point) == dir) return true;
    }
    return false;
}

/// The stem of the hidden names beside the target: the target's name, shortened so that
/// ".STEM.partial-PID" fits the usual 255-byte limit of a file name.
std::string siblingStem(const fs::path& target) {
    std::string name = target.filename().string();
    if (name.size() > 200) name = name.substr(0, 200);
    return name;
}

}  // namespace

OutputDir::OutputDir(fs::path target, bool force) : force_(force) {
    std::error_code ec;
    // A symlink that leads nowhere (dangling, or a loop) cannot be replaced by a directory.
    if (fs::is_symlink(fs::symlink_status(target, ec)) && !fs::exists(target, ec))
        throw InputError("--out " + target.string() + ": a symlink that leads nowhere (dangling or a loop)");
    // Absolute and normalised, so ".", "dir/" and "a/../b" name what they mean.
    target_ = fs::weakly_canonical(fs::absolute(target, ec), ec);
    if (ec || target_.empty()) target_ = fs::absolute(target).lexically_normal();
    if (target_.filename().empty()) target_ = target_.parent_path();
    const std::string shown = "--out " + target.string();
    const fs::path cwd = fs::current_path(ec);
    if (target_ == target_.root_path() || (!ec && isSameOrAncestor(target_, cwd)))
        throw InputError(shown +
                         ": is the current directory, one of its parents or the root; give a "
                         "directory of its own for the results");
    // Through a symlink the target may contain the very path that names it (a link to "..").
    fs::path written = fs::absolute(target, ec).lexically_normal();
    if (written.filename().empty()) written = written.parent_path();  // "res/", "res/." name res
    if (!ec && isSameOrAncestor(target_, written.parent_path()))
        throw InputError(shown + ": leads to " + target_.string() + ", which contains " + shown.substr(6) +
                         " itself; give a directory of its own for the results");
    if (fs::exists(target_, ec)) {
        if (!fs::is_directory(target_, ec)) throw InputError(shown + ": exists and is not a directory");
        // Results are written beside the target and renamed into place: a mount point cannot be.
        if (isMountPoint(target_))
            throw InputError(shown +
                             ": is a mount point; results are written beside it and moved into place, "
                             "which a mount point does not allow; give a directory inside it");
        if (!fs::is_empty(target_, ec) && !force_)
            throw InputError(shown + ": directory exists and is not empty; pass --force to replace it");
    }
    // The nearest existing ancestor must be a directory we can write in.
    fs::path up = target_.parent_path();
    while (!up.empty() && !fs::exists(up, ec) && up != up.root_path()) up = up.parent_path();
    if (!fs::is_directory(up, ec)) throw InputError(shown + ": " + up.string() + " is not a directory");
    if (::access(up.c_str(), W_OK | X_OK) != 0)
        throw InputError(shown + ": cannot write in " + up.string() + " (" + std::strerror(errno) + ")");
    // A name longer than the file system allows would fail only when the results are moved into
    // place, after the whole run.
    const long nameMax = ::pathconf(up.c_str(), _PC_NAME_MAX);
    if (nameMax > 0)
        for (const fs::path& part : target_.lexically_relative(up))
            if (long(part.native().size()) > nameMax)
                throw InputError(shown + ": the name '" + part.string().substr(0, 40) + "…' has " +
                                 std::to_string(part.native().size()) + " bytes; the file system allows at most " +
                                 std::to_string(nameMax));
}

OutputDir::~OutputDir() {
    if (committed_) return;
    std::error_code ec;
    if (!staging_.empty()) fs::remove_all(staging_, ec);
    for (const fs::path& p : createdParents_) fs::remove(p, ec);  // only if still empty
}

void OutputDir::open() {
    const fs::path parent = target_.parent_path();
    std::error_code ec;
    for (fs::path p = parent; !p.empty() && p != p.root_path() && !fs::exists(p, ec); p = p.parent_path())
        createdParents_.push_back(p);  // deepest first
    fs::create_directories(parent, ec);
    if (ec) throw InputError("--out " + target_.string() + ": cannot create " + parent.string() + ": " + ec.message());
    removeStaleSiblings(parent);
    // A name of our own: one already there (left by an earlier process with this PID) is not ours to
    // remove, so a suffix is added until the directory can be created afresh.
    const std::string base = "." + siblingStem(target_) + ".partial-" + std::to_string(::getpid());
    for (int n = 0;; ++n) {
        staging_ = parent / (n == 0 ? base : base + "-" + std::to_string(n));
        if (fs::create_directory(staging_, ec)) {
            writeFileAtomic((staging_ / kOwnerFile).string(), ownerLine(long(::getpid())) + "\n");
            break;
        }
        if (ec || n == 100) {
            const std::string why = ec ? ec.message() : std::string("the name is taken");
            staging_.clear();
            throw InputError("--out " + target_.string() + ": cannot create a staging directory beside it: " + why);
        }
    }
}

fs::path OutputDir::file(const std::string& relative) const {
    const fs::path p = staging_ / relative;
    std::error_code ec;
    fs::create_directories(p.parent_path(), ec);
    return p;
}

void OutputDir::commit() {
    std::error_code ec;
    fs::remove(staging_ / kOwnerFile, ec);
    syncTree(staging_);  // every name inside is on disk before the folder gets its final name
    fs::path old;
    {
        // Concurrent runs into the same target take turns to move the old folder aside and theirs
        // into place; without the lock two runs can both find the old folder and one fails to move it.
        const DirectoryLock lock(target_.parent_path());
        if (fs::exists(target_, ec)) {
            if (!force_ && !fs::is_empty(target_, ec))
                throw InputError("--out " + target_.string() +
                                 ": was filled by something else while this run worked; pass --force to replace it");
            const std::string base = "." + siblingStem(target_) + ".old-" + std::to_string(::getpid());
            old = target_.parent_path() / base;
            for (int n = 1; fs::exists(fs::symlink_status(old, ec)) && n <= 100; ++n)
                old = target_.parent_path() / (base + "-" + std::to_string(n));
            fs::rename(target_, old, ec);
            if (ec) throw RuntimeError("cannot move the old " + target_.string() + " aside: " + ec.message());
        }
        fs::rename(staging_, target_, ec);
        if (ec) {
            std::error_code ec2;
            if (!old.empty()) fs::rename(old, target_, ec2);
            throw RuntimeError("cannot move results into " + target_.string() + ": " + ec.message());
        }
        committed_ = true;
        syncDirectory(target_.parent_path());
    }
    if (!old.empty()) fs::remove_all(old, ec);
}

}  // namespace cavesim::app

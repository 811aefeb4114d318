/// @file memory.h
/// @brief How much memory this process may use: the machine's physical and available memory, the
/// address-space and data-segment limits (`ulimit -v`, `ulimit -d`) and the memory limit of its
/// control group (cgroup v2 `memory.max`, v1 `memory.limit_in_bytes`). The parsers take file
/// contents, so tests can feed them text.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/resource.h>
#include <unistd.h>

namespace cavesim {

/// The tighter of two memory limits in bytes, where 0 (or less) stands for "none known".
inline double tighterLimit(double a, double b) {
    if (!(b > 0)) return a;
    return a > 0 ? std::min(a, b) : b;
}

/// The machine's physical memory in bytes; 0 if unknown.
inline double physicalMemoryBytes() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
    return pages > 0 && page > 0 ? double(pages) * double(page) : 0;
}

/// The soft limit of `resource` (RLIMIT_AS, RLIMIT_DATA) in bytes; 0 when unlimited or unknown.
inline double resourceLimitBytes(int resource) {
    rlimit r{};
    return ::getrlimit(resource, &r) == 0 && r.rlim_cur != RLIM_INFINITY ? double(r.rlim_cur) : 0;
}

/// Bytes this process may allocate at most by the machine's physical memory and the
/// address-space and data-segment limits; 0 if nothing is known.
inline double memoryLimitBytes() {
    double limit = physicalMemoryBytes();
    for (int resource : {RLIMIT_AS, RLIMIT_DATA}) limit = tighterLimit(limit, resourceLimitBytes(resource));
    return limit;
}

/// The value of the line "`key`: N kB" of /proc text (/proc/meminfo, /proc/self/status), in
/// bytes; 0 when absent.
inline double parseProcKilobytes(const std::string& text, const std::string& key) {
    const std::string format = key + ": %llu kB";
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        unsigned long long kb = 0;
        if (std::sscanf(line.c_str(), format.c_str(), &kb) == 1) return double(kb) * 1024.0;
    }
    return 0;
}

/// `MemAvailable` of /proc/meminfo text, in bytes; 0 when absent.
inline double parseMemAvailable(const std::string& meminfo) {
    return parseProcKilobytes(meminfo, "MemAvailable");
}

/// The whole of a (small) file, as the `read` of `cgroupLimitUpwards` wants it: false when it
/// cannot be opened.
inline bool readWholeFile(const std::string& path, std::string& text) {
    std::ifstream f(path);
    if (!f) return false;
    std::ostringstream ss;
    ss << f.rdbuf();
    text = ss.str();
    return true;
}

/// A cgroup memory limit file's contents (v2 `memory.max`: bytes or "max"; v1
/// `memory.limit_in_bytes`: bytes, where values from 2^62 up mean no limit), in bytes; 0 for no
/// limit or unreadable text.
inline double parseCgroupMemoryLimit(const std::string& text) {
    const std::size_t a = text.find_first_not_of(" \t\r\n");
    if (a == std::string::npos) return 0;
    const std::string t = text.substr(a, text.find_first_of(" \t\r\n", a) - a);
    if (t == "max" || t.find_first_not_of("0123456789") != std::string::npos || t.size() > 20) return 0;
    const double v = std::stod(t);
    return v >= 4.6e18 ? 0 : v;  // 2^62 and above: the kernel's "unlimited" (v1 prints 2^63 − 4096)
}

/// This process's memory cgroup, from /proc/self/cgroup text: the v2 path (line "0::/path") and the
/// v1 path of the memory controller (line "N:...memory...:/path"); empty when absent.
struct CgroupPaths {
    std::string v2, v1;
    bool hasV2 = false, hasV1 = false;
};
inline CgroupPaths parseProcCgroup(const std::string& text) {
    CgroupPaths p;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        const std::size_t a = line.find(':'), b = a == std::string::npos ? a : line.find(':', a + 1);
        if (b == std::string::npos) continue;
        const std::string id = line.substr(0, a), controllers = line.substr(a + 1, b - a - 1),
                          path = line.substr(b + 1);
        if (id == "0" && controllers.empty()) {
            p.v2 = path;
            p.hasV2 = true;
        }
        std::istringstream cs(controllers);
        std::string c;
        while (std::getline(cs, c, ','))
            if (c == "memory") {
                p.v1 = path;
                p.hasV1 = true;
            }
    }
    return p;
}

/// The smallest memory limit on the way from the cgroup `path` up to the root of the hierarchy
/// mounted at `mount`, reading `file` in each directory that has it (a container often sees only
/// the root); 0 when none is set. `read(filePath, text)` returns false for a missing file.
template <typename ReadFn>
double cgroupLimitUpwards(const std::string& mount, std::string path, const std::string& file, ReadFn&& read) {
    double limit = 0;
    while (true) {
        std::string text;
        if (read(mount + (path == "/" ? std::string() : path) + "/" + file, text)) {
            limit = tighterLimit(limit, parseCgroupMemoryLimit(text));
        }
        if (path.empty() || path == "/") break;
        const std::size_t cut = path.find_last_of('/');
        path = cut == 0 || cut == std::string::npos ? "/" : path.substr(0, cut);
    }
    return limit;
}

/// Everything known about the memory this process may use, in bytes; 0 where nothing is known or
/// set.
struct MemoryLimits {
    double physical = 0;      ///< the machine's RAM
    double available = 0;     ///< MemAvailable: free now without swapping
    double addressSpace = 0;  ///< RLIMIT_AS (`ulimit -v`)
    double dataSegment = 0;   ///< RLIMIT_DATA (`ulimit -d`)
    double cgroup = 0;        ///< the smallest cgroup memory limit (v2 memory.max or v1 memory.limit_in_bytes)

    /// The smallest of the known limits (0 if none is known).
    double usable() const {
        double u = 0;
        for (double v : {available > 0 ? available : physical, addressSpace, dataSegment, cgroup})
            u = tighterLimit(u, v);
        return u;
    }
    /// "MemAvailable 21,000 MB, cgroup limit 8,000 MB, ..." listing the known limits.
    std::string describe() const {
        std::string s;
        const auto add = [&](const char* name, double v) {
            if (v <= 0) return;
            if (!s.empty()) s += ", ";
            s += std::string(name) + " " + std::to_string(long(v / 1e6)) + " MB";
        };
        add("physical memory", physical);
        add("MemAvailable", available);
        add("ulimit -v", addressSpace);
        add("ulimit -d", dataSegment);
        add("cgroup limit", cgroup);
        return s.empty() ? "no memory limit known" : s;
    }
};

/// Reads the limits of this process from /proc and /sys/fs/cgroup.
inline MemoryLimits readMemoryLimits() {
    MemoryLimits m;
    m.physical = physicalMemoryBytes();
    std::string text;
    if (readWholeFile("/proc/meminfo", text)) m.available = parseMemAvailable(text);
    m.addressSpace = resourceLimitBytes(RLIMIT_AS);
    m.dataSegment = resourceLimitBytes(RLIMIT_DATA);
    if (readWholeFile("/proc/self/cgroup", text)) {
        const CgroupPaths p = parseProcCgroup(text);
        double v2 = 0, v1 = 0;
        if (p.hasV2) {
            v2 = cgroupLimitUpwards("/sys/fs/cgroup", p.v2, "memory.max", readWholeFile);
            if (v2 == 0) v2 = cgroupLimitUpwards("/sys/fs/cgroup/unified", p.v2, "memory.max", readWholeFile);
        }
        if (p.hasV1) v1 = cgroupLimitUpwards("/sys/fs/cgroup/memory", p.v1, "memory.limit_in_bytes", readWholeFile);
        m.cgroup = tighterLimit(v2, v1);
    }
    return m;
}

/// Peak resident memory of this process so far (VmHWM of /proc/self/status), in bytes; 0 if unknown.
inline double peakResidentBytes() {
    std::string text;
    return readWholeFile("/proc/self/status", text) ? parseProcKilobytes(text, "VmHWM") : 0;
}

}  // namespace cavesim

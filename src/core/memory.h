/// @file memory.h
/// @brief How much memory this process may use: the smaller of the machine's physical memory and
/// the address-space and data-segment limits (`ulimit -v`, `ulimit -d`).
#pragma once

#include <algorithm>
#include <cstdint>

#include <sys/resource.h>
#include <unistd.h>

namespace cavesim {

/// Bytes this process may allocate at most; 0 if nothing is known.
inline double memoryLimitBytes() {
    double limit = 0;
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
    if (pages > 0 && page > 0) limit = double(pages) * double(page);
    for (int resource : {RLIMIT_AS, RLIMIT_DATA}) {
        rlimit r{};
        if (::getrlimit(resource, &r) == 0 && r.rlim_cur != RLIM_INFINITY)
            limit = limit > 0 ? std::min(limit, double(r.rlim_cur)) : double(r.rlim_cur);
    }
    return limit;
}

}  // namespace cavesim

/// @file fnv.h
/// @brief FNV-1a 64-bit hashing of byte streams: grid checksums, file fingerprints, file tags.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

namespace cavesim {

/// Incremental FNV-1a 64: feed bytes in any number of pieces, read `value()` or `hex()`.
class Fnv1a64 {
public:
    void add(const void* data, std::size_t bytes) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (std::size_t b = 0; b < bytes; ++b) h_ = (h_ ^ p[b]) * 1099511628211ull;
    }
    std::uint64_t value() const { return h_; }
    /// 16 lower-case hex digits.
    std::string hex() const {
        char buf[17];
        std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h_));
        return buf;
    }

private:
    std::uint64_t h_ = 1469598103934665603ull;
};

}  // namespace cavesim

/// @file detail.h
/// @brief Internal to src/formats: number text and byte packing (files are written by
/// core/atomic_file.h's `writeFileAtomic`, whose errors name the file).
#pragma once

#include <charconv>
#include <cstdio>
#include <cstring>
#include <string>

#include "core/text.h"

namespace cavesim::formats::detail {

/// Shortest decimal text that reads back to the same double.
inline std::string num(double v) {
    return shortestText(v);
}

/// Shortest decimal text that reads back to the same float.
inline std::string num(float v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

/// `v` with exactly `decimals` digits after the point (survey readings); "-0" never appears.
inline std::string fixed(double v, int decimals) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    std::string s(buf);
    if (s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
    return s;
}

/// Appends the bytes of `n` values (this machine is little-endian, as every format here wants).
template <typename T>
void appendBytes(std::string& out, const T* data, std::size_t n) {
    out.append(reinterpret_cast<const char*>(data), n * sizeof(T));
}
template <typename T>
void appendValue(std::string& out, const T& v) {
    appendBytes(out, &v, 1);
}

}  // namespace cavesim::formats::detail

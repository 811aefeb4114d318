/// @file text.h
/// @brief Numbers as text, the same way wherever cavesim writes them: the shortest decimal form
/// that reads back to the same double, and integers with thousands separators for messages.
#pragma once

#include <charconv>
#include <string>

namespace cavesim {

/// Shortest decimal text that reads back as the same double (0.3, not 0.29999999999999999),
/// by `std::to_chars`.
inline std::string shortestText(double v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

/// `v` with a comma between groups of three digits: 1234567 → "1,234,567" (for messages).
inline std::string withThousands(long v) {
    std::string s = std::to_string(v);
    for (int i = int(s.size()) - 3; i > 0; i -= 3) s.insert(std::size_t(i), ",");
    return s;
}

}  // namespace cavesim

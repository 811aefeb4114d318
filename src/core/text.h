/// @file text.h
/// @brief Numbers as text, the same way wherever cavesim writes them: the shortest decimal form
/// that reads back to the same double, integers with thousands separators, and quoted file text
/// with its control bytes shown, for messages.
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

/// `s` with every control byte (below 0x20, and 0x7f) written as \xNN, for messages that quote
/// what a file holds: a NUL in a quoted value once cut the message short.
inline std::string printable(const std::string& s) {
    std::string out;
    for (const char c : s) {
        const auto u = static_cast<unsigned char>(c);
        if (u < 0x20 || u == 0x7f) {
            static const char* const kHex = "0123456789abcdef";
            out += "\\x";
            out += kHex[u >> 4];
            out += kHex[u & 15];
        } else {
            out += c;
        }
    }
    return out;
}

}  // namespace cavesim

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

/// `v` with backslashes, double quotes and control bytes escaped as TOML writes them (\\, \", \n,
/// \t, \u00NN), for messages that show what a file holds: they stay on one line, and a NUL no
/// longer cuts them short.
inline std::string escaped(const std::string& v) {
    std::string out;
    for (unsigned char c : v) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += char(c);
        } else if (c == '\n') {
            out += "\\n";
        } else if (c == '\t') {
            out += "\\t";
        } else if (c < 0x20 || c == 0x7f) {
            static const char* const kHex = "0123456789abcdef";
            out += "\\u00";
            out += kHex[c >> 4];
            out += kHex[c & 15];
        } else {
            out += char(c);
        }
    }
    return out;
}

/// A string value as it would be written in TOML: in double quotes, escaped.
inline std::string quoted(const std::string& v) {
    return '"' + escaped(v) + '"';
}

}  // namespace cavesim

// User input quoted in a message: in double quotes, at most `max` characters, each byte
// that is neither printable ASCII nor part of valid UTF-8 shown as \xNN (NUL as \0), and
// a cut token ended by "..." and its whole size, so a 10 MB token or a binary file's bytes
// never reach the terminal. sanitized() is the same without the quotes and the cut: the
// net InputError casts over every message.
#pragma once
#include <cstdio>
#include <string>
#include <string_view>

namespace wmlt {

// The length of the valid UTF-8 sequence of 2 to 4 bytes at s[i], or 0.
inline size_t utf8Length(std::string_view s, size_t i) {
    const unsigned char c = (unsigned char)s[i];
    const size_t n = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
    if (n == 0 || i + n > s.size()) return 0;
    for (size_t k = 1; k < n; ++k)
        if (((unsigned char)s[i + k] & 0xC0) != 0x80) return 0;
    const unsigned char c1 = (unsigned char)s[i + 1];
    if ((c == 0xE0 && c1 < 0xA0) || (c == 0xED && c1 > 0x9F) || (c == 0xF0 && c1 < 0x90) || (c == 0xF4 && c1 > 0x8F)) return 0;
    return n;
}

// Appends s[i...] to out as shown text; returns the bytes consumed (1 to 4).
inline size_t appendShown(std::string& out, std::string_view s, size_t i) {
    const unsigned char c = (unsigned char)s[i];
    if (c >= 32 && c < 127) {
        out += char(c);
        return 1;
    }
    if (const size_t n = c >= 0x80 ? utf8Length(s, i) : 0) {
        out.append(s.substr(i, n));
        return n;
    }
    if (c == 0) {
        out += "\\0";
    } else {
        char hex[8];
        std::snprintf(hex, sizeof hex, "\\x%02X", c);
        out += hex;
    }
    return 1;
}

inline std::string quoteToken(std::string_view s, size_t max = 60) {
    std::string out = "\"";
    size_t i = 0, shown = 0;
    while (i < s.size() && shown < max) {
        i += appendShown(out, s, i);
        ++shown;
    }
    out += '"';
    if (i < s.size()) out.insert(out.size() - 1, "..."), out += " (" + std::to_string(s.size()) + " bytes)";
    return out;
}

inline std::string sanitized(std::string_view s) {
    std::string out;
    out.reserve(s.size());
    for (size_t i = 0; i < s.size();) i += appendShown(out, s, i);
    return out;
}

}  // namespace wmlt

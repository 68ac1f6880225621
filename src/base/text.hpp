// Names (file names, structure fields) put into text for people or into line-based files: a
// control character there would break the line or reach the terminal as an escape sequence;
// and text that must be UTF-8.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace fdmsurf::detail {

// The length of the valid UTF-8 sequence (2 to 4 bytes) that starts at text[i] (a byte of 0x80
// or more), or 0 where none does: overlong forms, surrogates and code points above U+10FFFF are
// not valid.
inline std::size_t utf8_sequence(std::string_view text, std::size_t i) {
    const auto c = static_cast<unsigned char>(text[i]);
    std::size_t length = 0;
    std::uint32_t code = 0;
    if (c >= 0xc2 && c <= 0xdf) {
        length = 2;
        code = c & 0x1f;
    } else if (c >= 0xe0 && c <= 0xef) {
        length = 3;
        code = c & 0x0f;
    } else if (c >= 0xf0 && c <= 0xf4) {
        length = 4;
        code = c & 0x07;
    }
    if (length == 0 || i + length > text.size()) return 0;
    for (std::size_t k = 1; k < length; ++k) {
        const auto next = static_cast<unsigned char>(text[i + k]);
        if ((next & 0xc0) != 0x80) return 0;
        code = (code << 6) | (next & 0x3f);
    }
    if ((length == 3 && (code < 0x800 || (code >= 0xd800 && code <= 0xdfff))) ||
        (length == 4 && (code < 0x10000 || code > 0x10ffff)))
        return 0;
    return length;
}

// `text` as valid UTF-8: each byte that starts no valid sequence becomes U+FFFD.
inline std::string valid_utf8(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size();) {
        if (static_cast<unsigned char>(text[i]) < 0x80) {
            out += text[i++];
        } else if (const std::size_t n = utf8_sequence(text, i); n != 0) {
            out.append(text.substr(i, n));
            i += n;
        } else {
            out += "\xef\xbf\xbd";  // U+FFFD
            ++i;
        }
    }
    return out;
}

// A CSV field (RFC 4180), in UTF-8: bytes that are not become U+FFFD (as in the JSON files);
// quoted, with its quotes doubled, when it holds a comma, a quote or a line break.
inline std::string csv_field(std::string_view raw) {
    const std::string text = valid_utf8(raw);
    if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
    std::string out = "\"";
    for (char c : text) {
        if (c == '"') out += '"';
        out += c;
    }
    return out + "\"";
}

// `text` with every control character as '?', as `ls -q` shows names: C0 (below 0x20), DEL, C1
// (U+0080 to U+009F: CSI and the like, which some terminals act on) and bytes that are not
// UTF-8; other characters as they are.
inline std::string printable(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size();) {
        const auto b = static_cast<unsigned char>(text[i]);
        if (b < 0x80) {
            out += b < 0x20 || b == 0x7f ? '?' : text[i];
            ++i;
            continue;
        }
        const std::size_t n = utf8_sequence(text, i);
        const bool c1 = n == 2 && b == 0xc2 && static_cast<unsigned char>(text[i + 1]) < 0xa0;
        if (n == 0 || c1) {
            out += '?';
            i += n == 0 ? 1 : n;
        } else {
            out.append(text.substr(i, n));
            i += n;
        }
    }
    return out;
}

}  // namespace fdmsurf::detail

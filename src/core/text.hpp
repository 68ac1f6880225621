// Names (file names, structure fields) put into text for people or into line-based files: a
// control character there would break the line or reach the terminal as an escape sequence.
#pragma once

#include <string>
#include <string_view>

namespace fdmsurf::detail {

// `text` with every control character (below 0x20, and 0x7f) as '?', as `ls -q` shows names;
// other bytes, UTF-8 included, as they are.
inline std::string printable(std::string_view text) {
    std::string out(text);
    for (char& c : out) {
        const auto b = static_cast<unsigned char>(c);
        if (b < 0x20 || b == 0x7f) c = '?';
    }
    return out;
}

}  // namespace fdmsurf::detail

// OFF writer: Geomview's Object File Format, or COFF with a colour per vertex. The reader is
// parse_off in src/io/read_off_msms.cpp, shared with `fdmsurf compare`.
#include <charconv>
#include <cstdint>
#include <string>

#include "io/formats.hpp"

namespace fdmsurf::detail {

void write_off(const Mesh& mesh, ByteSink& sink) {
    const bool colors = !mesh.colors.empty();
    // No comment line: not every OFF reader skips '#' lines.
    sink.write(std::string(colors ? "COFF\n" : "OFF\n") + std::to_string(mesh.vertex_count()) +
               " " + std::to_string(mesh.triangle_count()) + " 0\n");
    // Nine significant digits give back the same float, read as float or through a double.
    // A float in 9 digits takes at most 16 characters; the margin leaves room for the
    // separators written after a number.
    char line[256];
    char* const end = line + sizeof line - 16;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        char* out = line;
        for (int k = 0; k < 3; ++k) {
            if (k > 0) *out++ = ' ';
            out = std::to_chars(out, end, mesh.positions[3 * v + k], std::chars_format::general, 9)
                      .ptr;
        }
        if (colors) {
            for (int k = 0; k < 3; ++k) {
                *out++ = ' ';
                out = std::to_chars(out, end, int{mesh.colors[3 * v + k]}).ptr;
            }
            for (char c : std::string_view(" 255")) *out++ = c;
        }
        *out++ = '\n';
        sink.write(line, std::size_t(out - line));
    }
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        char* out = line;
        *out++ = '3';
        for (int k = 0; k < 3; ++k) {
            *out++ = ' ';
            out = std::to_chars(out, end, mesh.indices[3 * t + k]).ptr;
        }
        *out++ = '\n';
        sink.write(line, std::size_t(out - line));
    }
}

}  // namespace fdmsurf::detail

// read_mesh_any: PLY, OBJ, GLB, STL, OFF (OFF/NOFF/COFF/"OFF+N") and MSMS .vert/.face, gzipped or
// not.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "fdmsurf/compare.hpp"
#include "fdmsurf/error.hpp"
#include "io/gzip_input.hpp"
#include "io/mesh_io.hpp"

namespace fdmsurf {
namespace detail {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw Error(ErrorCode::Format, path + ": " + what);
}

bool ends_with_nocase(std::string_view text, std::string_view suffix) {
    if (text.size() < suffix.size()) return false;
    text.remove_prefix(text.size() - suffix.size());
    for (std::size_t i = 0; i < suffix.size(); ++i) {
        if (std::tolower(static_cast<unsigned char>(text[i])) != suffix[i]) return false;
    }
    return true;
}

// Splits off everything from '#' (OFF and MSMS comments) and returns the words of a line.
std::vector<std::string_view> words_of(std::string_view line) {
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) {
        line = line.substr(0, hash);
    }
    std::vector<std::string_view> words;
    std::size_t i = 0;
    while (true) {
        i = line.find_first_not_of(" \t\r\f\v", i);
        if (i == std::string_view::npos) break;
        const std::size_t j = std::min(line.find_first_of(" \t\r\f\v", i), line.size());
        words.push_back(line.substr(i, j - i));
        i = j;
    }
    return words;
}

// The lines of a text, one at a time, with their numbers for messages.
class Lines {
public:
    explicit Lines(std::string_view text) : text_(text) {}
    bool next(std::string_view& line) {
        if (pos_ >= text_.size()) return false;
        std::size_t eol = text_.find('\n', pos_);
        if (eol == std::string_view::npos) eol = text_.size();
        line = text_.substr(pos_, eol - pos_);
        pos_ = eol + 1;
        ++number_;
        return true;
    }
    // The next line with words on it (comments and blank lines skipped); false at the end.
    bool next_words(std::vector<std::string_view>& words) {
        std::string_view line;
        while (next(line)) {
            words = words_of(line);
            if (!words.empty()) return true;
        }
        return false;
    }
    std::size_t number() const { return number_; }

private:
    std::string_view text_;
    std::size_t pos_ = 0;
    std::size_t number_ = 0;
};

double parse_double(std::string_view word, const std::string& path, std::size_t line) {
    if (!word.empty() && word.front() == '+') word.remove_prefix(1);
    double value = 0.0;
    const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
    if (ec != std::errc() || end != word.data() + word.size()) {
        fail(path,
             "line " + std::to_string(line) + ": '" + std::string(word) + "' is not a number");
    }
    return value;
}

std::uint64_t parse_count(std::string_view word, const std::string& path, std::size_t line) {
    std::uint64_t value = 0;
    const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
    if (ec != std::errc() || end != word.data() + word.size()) {
        fail(path, "line " + std::to_string(line) + ": '" + std::string(word) +
                       "' is not a non-negative integer");
    }
    return value;
}

void add_position(Mesh& mesh, const std::vector<std::string_view>& words, const std::string& path,
                  std::size_t line) {
    if (words.size() < 3) fail(path, "line " + std::to_string(line) + ": fewer than 3 coordinates");
    for (int k = 0; k < 3; ++k) {
        mesh.positions.push_back(
            static_cast<float>(parse_double(words[std::size_t(k)], path, line)));
    }
}

// COFF colours: integers 0-255, or floats 0-1 when any channel of the file is not an integer.
struct OffColors {
    std::vector<double> values;  // 3 per vertex
    bool floats = false;

    void add(const std::vector<std::string_view>& words, std::size_t at, const std::string& path,
             std::size_t line) {
        for (std::size_t k = at; k < at + 3; ++k) {
            floats = floats || words[k].find_first_not_of("+0123456789") != std::string_view::npos;
            values.push_back(parse_double(words[k], path, line));
        }
    }

    std::vector<std::uint8_t> bytes() const {
        std::vector<std::uint8_t> out;
        out.reserve(values.size());
        for (double value : values) {
            const double byte = floats ? value * 255.0 : value;
            out.push_back(std::uint8_t(std::lround(std::clamp(byte, 0.0, 255.0))));
        }
        return out;
    }
};

// Reads a whole file; gzip-compressed data (by its magic bytes) is inflated by io/gzip_input,
// with the messages zlib's gzread gave when it read these files.
std::string read_maybe_gzipped(const std::string& path) {
    std::error_code ec;
    if (fs::is_directory(path, ec))
        throw Error(ErrorCode::Io, "cannot read " + path + ": it is a folder");
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                         &std::fclose);
    if (!file) throw Error(ErrorCode::Io, "cannot read " + path + ": " + std::strerror(errno));
    std::string data;
    const auto size = fs::file_size(path, ec);
    if (!ec) data.reserve(std::size_t(size));
    constexpr std::size_t kChunk = std::size_t{1} << 20;
    while (true) {
        const std::size_t old = data.size();
        data.resize(old + kChunk);
        const std::size_t n = std::fread(data.data() + old, 1, kChunk, file.get());
        data.resize(old + n);
        if (n < kChunk) break;
    }
    if (std::ferror(file.get()))
        throw Error(ErrorCode::Io, "cannot read " + path + ": " + std::strerror(errno));
    if (!is_gzip(data)) return data;
    std::string out;
    GzipProblem problem;
    if (gunzip(data, out, problem)) return out;
    switch (problem.kind) {
        case GzipProblem::Kind::Setup:
        case GzipProblem::Kind::OutOfMemory:
            fail(path, "bad gzip data: out of memory");
        case GzipProblem::Kind::Truncated:
            fail(path, "bad gzip data: " + path + ": unexpected end of file");
        case GzipProblem::Kind::Refused:
            fail(path, "bad gzip data: " + path + ": internal error: inflate stream corrupt");
        default:  // Corrupt
            break;
    }
    fail(path, "bad gzip data: " + path + ": " +
                   (problem.zlib_message.empty() ? "compressed data error" : problem.zlib_message));
}

// MSMS writes a count line "n spheres density probe" after '#' lines, then n records.
Lines msms_body(std::string_view text, const std::string& path, std::uint64_t& count) {
    Lines lines(text);
    std::vector<std::string_view> words;
    if (!lines.next_words(words)) fail(path, "empty MSMS file");
    count = parse_count(words[0], path, lines.number());
    return lines;
}

// The file next to `path` with `from` (".vert" or ".face", before an optional ".gz") turned
// into `to`; the compressed or plain variant that exists, else the name with the same suffix.
std::string msms_sibling(const std::string& path, std::string_view to) {
    const bool gz = ends_with_nocase(path, ".gz");
    const std::string stem = path.substr(0, path.size() - (gz ? 3 : 0) - 5);
    const std::string same = stem + std::string(to) + (gz ? ".gz" : "");
    const std::string other = stem + std::string(to) + (gz ? "" : ".gz");
    std::error_code ec;
    if (!fs::exists(same, ec) && fs::exists(other, ec)) return other;
    return same;
}

}  // namespace

Mesh parse_off(std::string_view text, const std::string& path) {
    Lines lines(text);
    std::vector<std::string_view> words;
    if (!lines.next_words(words) || words[0].find("OFF") == std::string_view::npos) {
        fail(path, "not an OFF file (no OFF header)");
    }
    if (words[0].find("BINARY") != std::string_view::npos ||
        (words.size() > 1 && words[1] == "BINARY")) {
        fail(path, "binary OFF is not supported");
    }
    std::vector<std::string_view> counts(words.begin() + 1, words.end());
    if (counts.size() < 2) {
        if (!lines.next_words(counts)) fail(path, "OFF file ends before its counts");
    }
    if (counts.size() < 2)
        fail(path, "line " + std::to_string(lines.number()) + ": bad OFF counts");
    const std::uint64_t vertices = parse_count(counts[0], path, lines.number());
    const std::uint64_t faces = parse_count(counts[1], path, lines.number());
    if (vertices > std::uint64_t{UINT32_MAX} || faces > text.size()) {
        fail(path, "OFF counts too large for the file");
    }
    Mesh mesh;
    mesh.positions.reserve(std::min<std::uint64_t>(3 * vertices, text.size()));
    // COFF, CNOFF: r g b a after the position (and the normal), integers 0-255 or floats 0-1.
    const std::string_view prefix = words[0].substr(0, words[0].find("OFF"));
    const bool colored = prefix.find('C') != std::string_view::npos &&
                         prefix.find_first_of("4n") == std::string_view::npos;
    const std::size_t color_at = prefix.find('N') != std::string_view::npos ? 6 : 3;
    OffColors colors;
    for (std::uint64_t i = 0; i < vertices; ++i) {
        if (!lines.next_words(words)) fail(path, "OFF file ends inside its vertices");
        add_position(mesh, words, path, lines.number());
        if (colored && words.size() >= color_at + 3)
            colors.add(words, color_at, path, lines.number());
    }
    // Colours only when every vertex has one.
    if (vertices > 0 && colors.values.size() == 3 * vertices) mesh.colors = colors.bytes();
    mesh.indices.reserve(std::min<std::uint64_t>(3 * faces, text.size()));
    std::vector<std::uint32_t> polygon;
    for (std::uint64_t f = 0; f < faces; ++f) {
        if (!lines.next_words(words)) fail(path, "OFF file ends inside its faces");
        const std::uint64_t n = parse_count(words[0], path, lines.number());
        if (n >= words.size()) {  // not words.size() < n + 1: n may be 2^64 - 1
            fail(path, "line " + std::to_string(lines.number()) +
                           ": face lists fewer indices "
                           "than its count");
        }
        polygon.clear();
        for (std::uint64_t k = 0; k < n; ++k) {
            const std::uint64_t index = parse_count(words[k + 1], path, lines.number());
            if (index >= vertices) {
                fail(path, "line " + std::to_string(lines.number()) + ": vertex index " +
                               std::to_string(index) + " out of range");
            }
            polygon.push_back(std::uint32_t(index));
        }
        for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
            mesh.indices.insert(mesh.indices.end(), {polygon[0], polygon[k], polygon[k + 1]});
        }
    }
    return mesh;
}

Mesh parse_msms(std::string_view vert_text, const std::string& vert_path,
                std::string_view face_text, const std::string& face_path) {
    Mesh mesh;
    std::uint64_t vertices = 0;
    Lines vlines = msms_body(vert_text, vert_path, vertices);
    if (vertices > std::uint64_t{UINT32_MAX} || vertices > vert_text.size()) {
        fail(vert_path, "vertex count too large for the file");
    }
    std::vector<std::string_view> words;
    mesh.positions.reserve(3 * vertices);
    // Normals (fields 3-5) and the 1-based atom (field 7) are kept when every line has them.
    bool normals = true, atoms = true;
    for (std::uint64_t i = 0; i < vertices; ++i) {
        if (!vlines.next_words(words)) fail(vert_path, "file ends inside its vertices");
        add_position(mesh, words, vert_path, vlines.number());
        normals = normals && words.size() >= 6;
        atoms = atoms && words.size() >= 8;
        for (std::size_t k = 3; normals && k < 6; ++k)
            mesh.normals.push_back(
                static_cast<float>(parse_double(words[k], vert_path, vlines.number())));
        if (atoms) {  // a field that is not an atom number drops the atoms, not the mesh
            std::uint32_t atom = 0;
            const auto [end, ec] =
                std::from_chars(words[7].data(), words[7].data() + words[7].size(), atom);
            atoms = ec == std::errc() && end == words[7].data() + words[7].size() && atom >= 1;
            if (atoms) mesh.atoms.push_back(atom - 1);
        }
    }
    if (!normals) mesh.normals.clear();
    if (!atoms) mesh.atoms.clear();
    std::uint64_t faces = 0;
    Lines flines = msms_body(face_text, face_path, faces);
    if (faces > face_text.size()) fail(face_path, "face count too large for the file");
    mesh.indices.reserve(3 * faces);
    for (std::uint64_t f = 0; f < faces; ++f) {
        if (!flines.next_words(words)) fail(face_path, "file ends inside its faces");
        if (words.size() < 3) {
            fail(face_path, "line " + std::to_string(flines.number()) + ": fewer than 3 indices");
        }
        for (int k = 0; k < 3; ++k) {
            const std::uint64_t index =
                parse_count(words[std::size_t(k)], face_path, flines.number());
            if (index < 1 || index > vertices) {  // MSMS counts from 1
                fail(face_path, "line " + std::to_string(flines.number()) + ": vertex index " +
                                    std::to_string(index) + " out of range");
            }
            mesh.indices.push_back(std::uint32_t(index - 1));
        }
    }
    return mesh;
}

}  // namespace detail

Mesh read_mesh_any(const std::string& path) {
    using detail::ends_with_nocase;
    const bool gz = ends_with_nocase(path, ".gz");
    const std::string inner = gz ? path.substr(0, path.size() - 3) : path;
    const std::string ext = detail::lowercase_extension(inner);
    std::error_code ec;
    if (ext == ".vert" || ext == ".face" ||
        (ext.empty() && !std::filesystem::exists(path, ec) &&
         std::filesystem::exists(path + ".vert", ec))) {
        std::string vert_path, face_path;
        if (ext.empty()) {
            vert_path = path + ".vert";
            face_path = path + ".face";
        } else {
            vert_path = ext == ".vert" ? path : detail::msms_sibling(path, ".vert");
            face_path = ext == ".face" ? path : detail::msms_sibling(path, ".face");
        }
        const std::string vert = detail::read_maybe_gzipped(vert_path);
        const std::string face = detail::read_maybe_gzipped(face_path);
        return detail::parse_msms(vert, vert_path, face, face_path);
    }
    const std::string data = detail::read_maybe_gzipped(path);
    if (auto mesh = detail::parse_mesh_data(data, path, ext)) return std::move(*mesh);
    throw Error(ErrorCode::Format,
                path +
                    ": not a mesh file fdmsurf reads (PLY, OBJ, GLB, STL, OFF, MSMS .vert/.face, "
                    "each optionally gzipped)");
}

}  // namespace fdmsurf

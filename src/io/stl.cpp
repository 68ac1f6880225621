// STL: the binary writer (a normal per face, no shared vertices) and a reader of binary and
// ASCII STL that welds corners with identical positions back into shared vertices.
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "fdmsurf/error.hpp"
#include "fdmsurf/fdmsurf.hpp"
#include "io/formats.hpp"

namespace fdmsurf::detail {
namespace {

constexpr std::size_t header_size = 80;
constexpr std::size_t record_size = 50;  // normal, 3 corners (12 floats), uint16 attribute

[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw Error(ErrorCode::Format, path + ": " + what);
}

// The unit normal of the face by the right-hand rule (counter-clockwise from outside), in
// double; zero for a degenerate face, as STL readers expect.
std::array<float, 3> face_normal(const float* a, const float* b, const float* c) {
    const double u[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
    const double v[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                         u[0] * v[1] - u[1] * v[0]};
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(length > 0.0) || !std::isfinite(length)) return {0.0f, 0.0f, 0.0f};
    return {float(n[0] / length), float(n[1] / length), float(n[2] / length)};
}

// Corners are welded when their three coordinates are equal as floats (-0 and +0 alike).
struct PositionKey {
    std::uint32_t bits[3];
    bool operator==(const PositionKey&) const = default;
};

struct PositionHash {
    std::size_t operator()(const PositionKey& k) const {
        std::uint64_t h = 0x9e3779b97f4a7c15ULL;
        for (std::uint32_t b : k.bits) h = (h ^ b) * 0xff51afd7ed558ccdULL;
        return std::size_t(h ^ (h >> 32));
    }
};

// Builds the welded mesh corner by corner, vertices numbered in order of first appearance.
class Welder {
public:
    explicit Welder(std::size_t triangles) {
        mesh_.indices.reserve(3 * triangles);
        index_of_.reserve(triangles);  // a closed mesh has about half as many vertices
    }

    void add_corner(const float p[3]) {
        PositionKey key;
        for (int k = 0; k < 3; ++k) {
            const float c = p[k] == 0.0f ? 0.0f : p[k];  // -0 is +0
            key.bits[k] = std::bit_cast<std::uint32_t>(c);
        }
        const auto [it, inserted] = index_of_.try_emplace(key, std::uint32_t(mesh_.vertex_count()));
        if (inserted) mesh_.positions.insert(mesh_.positions.end(), p, p + 3);
        mesh_.indices.push_back(it->second);
    }

    Mesh take() { return std::move(mesh_); }

private:
    Mesh mesh_;
    std::unordered_map<PositionKey, std::uint32_t, PositionHash> index_of_;
};

Mesh parse_binary(std::string_view data) {
    const std::uint32_t count = get_le<std::uint32_t>(data.data() + header_size);
    Welder welder(count);
    for (std::uint32_t t = 0; t < count; ++t) {
        const char* record = data.data() + header_size + 4 + record_size * std::size_t{t};
        for (int corner = 0; corner < 3; ++corner) {
            float p[3];
            for (int k = 0; k < 3; ++k) p[k] = get_le<float>(record + 12 * (corner + 1) + 4 * k);
            welder.add_corner(p);
        }
    }
    return welder.take();
}

// The words of an ASCII STL with their line numbers, for messages.
class Words {
public:
    Words(std::string_view text, const std::string& path) : text_(text), path_(path) {}

    // The next word, or "" at the end.
    std::string_view next() {
        while (pos_ < text_.size() && is_space(text_[pos_])) {
            if (text_[pos_] == '\n') ++line_;
            ++pos_;
        }
        const std::size_t start = pos_;
        while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
        return text_.substr(start, pos_ - start);
    }

    // Skips the rest of the line (a solid's name).
    void skip_line() {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    }

    void expect(std::string_view word) {
        const std::string_view got = next();
        if (got != word) bad("expected '" + std::string(word) + "', found " + quoted(got));
    }

    float number(const char* what) {
        std::string_view word = next();
        const std::string_view original = word;
        if (!word.empty() && word.front() == '+') word.remove_prefix(1);
        float value = 0.0f;
        const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
        if (ec != std::errc() || end != word.data() + word.size() || !std::isfinite(value)) {
            bad(std::string(what) + " " + quoted(original) + " is not a finite number");
        }
        return value;
    }

    [[noreturn]] void bad(const std::string& what) const {
        fail(path_, "line " + std::to_string(line_) + ": " + what);
    }

    static std::string quoted(std::string_view word) {
        if (word.empty()) return "the end of the file";
        std::string out = "'";
        return out.append(word).append("'");
    }

private:
    static bool is_space(char c) {
        return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
    }

    std::string_view text_;
    const std::string& path_;
    std::size_t pos_ = 0;
    std::size_t line_ = 1;
};

// solid NAME (facet normal n n n / outer loop / vertex x y z ×3 / endloop / endfacet)*
// endsolid NAME, possibly several solids one after the other.
Mesh parse_ascii(std::string_view data, const std::string& path) {
    Words words(data, path);
    Welder welder(data.size() / 256);  // about 250 bytes of text per facet
    std::size_t facets = 0;
    std::string_view word = words.next();
    if (word != "solid") fail(path, "not an STL file (neither binary nor starting with 'solid')");
    while (word == "solid") {
        words.skip_line();
        for (word = words.next(); word == "facet"; word = words.next()) {
            words.expect("normal");
            for (int k = 0; k < 3; ++k) words.number("normal component");
            words.expect("outer");
            words.expect("loop");
            for (int corner = 0; corner < 3; ++corner) {
                words.expect("vertex");
                float p[3];
                for (int k = 0; k < 3; ++k) p[k] = words.number("coordinate");
                welder.add_corner(p);
            }
            words.expect("endloop");
            words.expect("endfacet");
            ++facets;
        }
        if (word != "endsolid") {
            words.bad("expected 'facet' or 'endsolid', found " + Words::quoted(word));
        }
        words.skip_line();
        word = words.next();
    }
    if (!word.empty()) words.bad("expected 'solid' or the end, found " + Words::quoted(word));
    if (facets == 0) fail(path, "ASCII STL without a single facet");
    return welder.take();
}

}  // namespace

void write_stl(const Mesh& mesh, ByteSink& sink) {
    // Not starting with "solid": readers take such a header for ASCII STL.
    std::string header = "fdmsurf " + std::string(version()) + " binary STL, units: angstrom";
    header.resize(header_size, ' ');
    sink.write(header);
    char count[4];
    put_le(count, std::uint32_t(mesh.triangle_count()));
    sink.write(count, 4);
    char record[record_size];
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const float* corner[3];
        for (int k = 0; k < 3; ++k)
            corner[k] = &mesh.positions[3 * std::size_t{mesh.indices[3 * t + k]}];
        char* out = record;
        for (float n : face_normal(corner[0], corner[1], corner[2])) out = put_le(out, n);
        for (const float* p : corner) {
            for (int k = 0; k < 3; ++k) out = put_le(out, p[k]);
        }
        *out++ = 0;  // attribute byte count, 0 by convention
        *out++ = 0;
        sink.write(record, record_size);
    }
}

bool is_binary_stl(std::string_view data) {
    if (data.size() < header_size + 4) return false;
    const std::uint64_t count = get_le<std::uint32_t>(data.data() + header_size);
    return data.size() == header_size + 4 + record_size * count;
}

bool is_ascii_stl(std::string_view data) {
    const std::size_t start = data.find_first_not_of(" \t\r\n");
    if (start == std::string_view::npos || data.substr(start, 5) != "solid") return false;
    const std::string_view head = data.substr(start, 4096);
    return head.find("facet") != std::string_view::npos ||
           head.find("endsolid") != std::string_view::npos;
}

Mesh parse_stl(std::string_view data, const std::string& path) {
    if (is_binary_stl(data)) return parse_binary(data);
    const std::size_t start = data.find_first_not_of(" \t\r\n");
    if (start == std::string_view::npos || data.substr(start, 5) != "solid") {
        if (data.size() >= header_size + 4) {
            const std::uint64_t count = get_le<std::uint32_t>(data.data() + header_size);
            fail(path, "not a binary STL of " + std::to_string(count) + " triangles (" +
                           std::to_string(header_size + 4 + record_size * count) + " bytes) but " +
                           std::to_string(data.size()) +
                           " bytes, nor an ASCII STL (starting with 'solid')");
        }
        fail(path, "not an STL file (" + std::to_string(data.size()) +
                       " bytes, too short for binary STL, and not starting with 'solid')");
    }
    return parse_ascii(data, path);
}

}  // namespace fdmsurf::detail

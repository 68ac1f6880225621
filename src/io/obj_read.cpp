// OBJ parser: v (with optional r g b), vn and f records (v, v/vt, v//vn, v/vt/vn, negative
// indices); the rest ignored.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "fdmsurf/error.hpp"
#include "io/mesh_io.hpp"

namespace fdmsurf::detail {
namespace {

constexpr std::uint32_t no_normal = std::numeric_limits<std::uint32_t>::max();

class ObjParser {
public:
    ObjParser(std::string_view data, const std::string& path) : data_(data), path_(path) {}

    Mesh parse() {
        std::size_t pos = 0;
        while (pos < data_.size()) {
            std::size_t eol = data_.find('\n', pos);
            if (eol == std::string_view::npos) eol = data_.size();
            ++line_number_;
            parse_line(data_.substr(pos, eol - pos));
            pos = eol + 1;
        }
        // Checked at the end: some writers put faces before the vertices they use.
        for (std::uint32_t i : mesh_.indices) {
            if (i >= mesh_.vertex_count()) {
                throw Error(ErrorCode::Format,
                            path_ + ": vertex index " + std::to_string(i + 1) + " out of range");
            }
        }
        assign_normals();
        // Colours only when every vertex has one.
        if (colored_ > 0 && colored_ == mesh_.vertex_count()) mesh_.colors = std::move(colors_);
        return std::move(mesh_);
    }

private:
    [[noreturn]] void bad(const std::string& what) const {
        throw Error(ErrorCode::Format,
                    path_ + ": line " + std::to_string(line_number_) + ": " + what);
    }

    void split(std::string_view line) {
        words_.clear();
        std::size_t i = 0;
        while (true) {
            i = line.find_first_not_of(" \t\r", i);
            if (i == std::string_view::npos) return;
            const std::size_t j = std::min(line.find_first_of(" \t\r", i), line.size());
            words_.push_back(line.substr(i, j - i));
            i = j;
        }
    }

    void parse_line(std::string_view line) {
        split(line);
        if (words_.empty() || words_[0].starts_with('#')) return;
        if (words_[0] == "v") {
            read_vector(mesh_.positions);  // a w after x y z is ignored
            read_color();
        } else if (words_[0] == "vn") {
            read_vector(normals_);
        } else if (words_[0] == "f") {
            read_face();
        }
        // vt, o, g, s, usemtl, mtllib, l, p...: not part of a triangle mesh.
    }

    float number(std::size_t k) const {
        std::string_view w = words_[k];
        if (w.starts_with('+')) w.remove_prefix(1);
        float value = 0.0f;
        const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), value);
        if (ec != std::errc() || end != w.data() + w.size()) {
            bad("bad number '" + std::string(words_[k]) + "'");
        }
        return value;
    }

    void read_vector(std::vector<float>& out) {
        if (words_.size() < 4) bad("expected 3 coordinates");
        for (std::size_t k = 1; k <= 3; ++k) out.push_back(number(k));
    }

    // v x y z r g b: the vertex colour extension (MeshLab, Blender), channels in [0, 1].
    void read_color() {
        if (words_.size() != 7) return;
        colors_.resize(3 * (mesh_.vertex_count() - 1));  // vertices before it without colour
        for (std::size_t k = 4; k <= 6; ++k) {
            const float c = std::clamp(number(k), 0.0f, 1.0f);
            colors_.push_back(std::uint8_t(std::lround(c * 255.0f)));
        }
        ++colored_;
    }

    // A 1-based index, or negative: counted back from the end of the `count` defined so far.
    std::uint32_t resolve(std::string_view text, std::size_t count) {
        std::int64_t value = 0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (ec != std::errc() || end != text.data() + text.size() || value == 0) {
            bad("bad index '" + std::string(text) + "'");
        }
        const std::int64_t index = value > 0 ? value - 1 : std::int64_t(count) + value;
        if (index < 0 || index >= std::int64_t{no_normal}) {
            bad("index " + std::string(text) + " out of range");
        }
        return std::uint32_t(index);
    }

    void read_face() {
        if (words_.size() < 4) bad("face with fewer than 3 vertices");
        polygon_.clear();
        polygon_normals_.clear();
        for (std::size_t k = 1; k < words_.size(); ++k) {
            const std::string_view w = words_[k];
            const std::size_t slash = w.find('/');
            polygon_.push_back(resolve(w.substr(0, slash), mesh_.vertex_count()));
            std::uint32_t normal = no_normal;
            if (slash != std::string_view::npos) {
                const std::size_t slash2 = w.find('/', slash + 1);
                if (slash2 != std::string_view::npos && slash2 + 1 < w.size()) {
                    normal = resolve(w.substr(slash2 + 1), normals_.size() / 3);
                    if (normal >= normals_.size() / 3)
                        bad("normal index out of range in '" + std::string(w) + "'");
                }
            }
            polygon_normals_.push_back(normal);
        }
        // Fan triangulation: exact for the convex polygons that other tools write.
        for (std::size_t j = 1; j + 1 < polygon_.size(); ++j) {
            for (std::size_t k : {std::size_t{0}, j, j + 1}) {
                mesh_.indices.push_back(polygon_[k]);
                corner_normals_.push_back(polygon_normals_[k]);
            }
        }
    }

    bool same_normal(std::uint32_t a, std::uint32_t b) const {
        for (std::size_t k = 0; k < 3; ++k) {
            if (normals_[3 * std::size_t{a} + k] != normals_[3 * std::size_t{b} + k]) return false;
        }
        return true;
    }

    // Mesh normals are per vertex: kept only if every vertex got exactly one from the faces.
    void assign_normals() {
        std::vector<std::uint32_t> normal_of(mesh_.vertex_count(), no_normal);
        for (std::size_t c = 0; c < mesh_.indices.size(); ++c) {
            const std::uint32_t n = corner_normals_[c];
            std::uint32_t& assigned = normal_of[mesh_.indices[c]];
            if (n == no_normal) return;
            if (assigned != no_normal && !same_normal(assigned, n)) return;
            assigned = n;
        }
        mesh_.normals.resize(mesh_.positions.size());
        for (std::size_t v = 0; v < normal_of.size(); ++v) {
            if (normal_of[v] == no_normal) {
                mesh_.normals.clear();
                return;
            }
            for (std::size_t k = 0; k < 3; ++k) {
                mesh_.normals[3 * v + k] = normals_[3 * std::size_t{normal_of[v]} + k];
            }
        }
    }

    std::string_view data_;
    const std::string& path_;
    std::size_t line_number_ = 0;
    Mesh mesh_;
    std::vector<float> normals_;                 // the file's vn records
    std::vector<std::uint8_t> colors_;           // r g b per vertex up to the last coloured one
    std::size_t colored_ = 0;                    // vertices with a colour
    std::vector<std::uint32_t> corner_normals_;  // vn index of each triangle corner
    std::vector<std::string_view> words_;
    std::vector<std::uint32_t> polygon_;
    std::vector<std::uint32_t> polygon_normals_;
};

}  // namespace

Mesh parse_obj(std::string_view data, const std::string& path) {
    return ObjParser(data, path).parse();
}

}  // namespace fdmsurf::detail

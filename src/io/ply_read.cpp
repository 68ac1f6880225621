// PLY parser: ASCII and binary (either byte order), vertex positions, normals, atoms, colours and
// scalars, polygon faces.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "fdmsurf/error.hpp"
#include "mesh/mesh_attributes.hpp"
#include "io/mesh_io.hpp"

namespace fdmsurf::detail {
namespace {

enum class Type { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };
enum class Encoding { Ascii, LittleEndian, BigEndian };

struct Property {
    std::string name;
    Type type = Type::Float32;
    bool is_list = false;
    Type count_type = Type::UInt8;  // lists: the type of the leading count
};

struct Element {
    std::string name;
    std::size_t count = 0;
    std::vector<Property> properties;
};

struct Header {
    Encoding encoding = Encoding::Ascii;
    std::vector<Element> elements;
    std::size_t body_offset = 0;
};

[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw Error(ErrorCode::Format, path + ": " + what);
}

std::vector<std::string_view> split_words(std::string_view line) {
    std::vector<std::string_view> words;
    std::size_t i = 0;
    while (true) {
        i = line.find_first_not_of(" \t\r", i);
        if (i == std::string_view::npos) break;
        const std::size_t j = std::min(line.find_first_of(" \t\r", i), line.size());
        words.push_back(line.substr(i, j - i));
        i = j;
    }
    return words;
}

bool parse_type(std::string_view word, Type& type) {
    static const std::pair<std::string_view, Type> names[] = {
        {"char", Type::Int8},      {"int8", Type::Int8},       {"uchar", Type::UInt8},
        {"uint8", Type::UInt8},    {"short", Type::Int16},     {"int16", Type::Int16},
        {"ushort", Type::UInt16},  {"uint16", Type::UInt16},   {"int", Type::Int32},
        {"int32", Type::Int32},    {"uint", Type::UInt32},     {"uint32", Type::UInt32},
        {"float", Type::Float32},  {"float32", Type::Float32}, {"double", Type::Float64},
        {"float64", Type::Float64}};
    for (const auto& [name, t] : names) {
        if (word == name) {
            type = t;
            return true;
        }
    }
    return false;
}

Header parse_header(std::string_view data, const std::string& path) {
    Header header;
    bool has_format = false;
    std::size_t pos = 0;
    for (int line_number = 1;; ++line_number) {
        const std::size_t eol = data.find('\n', pos);
        if (eol == std::string_view::npos) fail(path, "PLY header without end_header");
        const auto words = split_words(data.substr(pos, eol - pos));
        pos = eol + 1;
        const auto bad = [&](const std::string& what) {
            fail(path, "PLY header line " + std::to_string(line_number) + ": " + what);
        };
        if (line_number == 1) {
            if (words.size() != 1 || words[0] != "ply") bad("not a PLY file");
            continue;
        }
        if (words.empty() || words[0] == "comment" || words[0] == "obj_info") continue;
        if (words[0] == "end_header") break;
        if (words[0] == "format") {
            if (words.size() != 3 || words[2] != "1.0") bad("unsupported format line");
            if (words[1] == "ascii") {
                header.encoding = Encoding::Ascii;
            } else if (words[1] == "binary_little_endian") {
                header.encoding = Encoding::LittleEndian;
            } else if (words[1] == "binary_big_endian") {
                header.encoding = Encoding::BigEndian;
            } else {
                bad("unknown format '" + std::string(words[1]) + "'");
            }
            has_format = true;
        } else if (words[0] == "element") {
            Element element;
            if (words.size() != 3) bad("malformed element line");
            element.name = words[1];
            const auto [end, ec] =
                std::from_chars(words[2].data(), words[2].data() + words[2].size(), element.count);
            if (ec != std::errc() || end != words[2].data() + words[2].size()) bad("bad count");
            header.elements.push_back(std::move(element));
        } else if (words[0] == "property") {
            if (header.elements.empty()) bad("property before any element");
            Property property;
            const bool ok =
                (words.size() == 3 && parse_type(words[1], property.type)) ||
                (words.size() == 5 && words[1] == "list" &&
                 parse_type(words[2], property.count_type) && parse_type(words[3], property.type));
            if (!ok) bad("malformed property line");
            property.is_list = words.size() == 5;
            property.name = words.back();
            header.elements.back().properties.push_back(std::move(property));
        } else {
            bad("unknown keyword '" + std::string(words[0]) + "'");
        }
    }
    if (!has_format) fail(path, "PLY header without a format line");
    header.body_offset = pos;
    return header;
}

std::size_t type_size(Type type) {
    switch (type) {
        case Type::Int8:
        case Type::UInt8:
            return 1;
        case Type::Int16:
        case Type::UInt16:
            return 2;
        case Type::Int32:
        case Type::UInt32:
        case Type::Float32:
            return 4;
        case Type::Float64:
            return 8;
    }
    return 0;
}

// Reads the body value by value, whatever the encoding, as doubles (exact for every PLY type).
class BodyReader {
public:
    BodyReader(std::string_view data, Encoding encoding, const std::string& path)
        : data_(data), encoding_(encoding), path_(path) {}

    double read(Type type) {
        return encoding_ == Encoding::Ascii ? read_text() : read_binary(type);
    }

    // The fewest bytes a value of `type` takes: its size, or in ASCII a digit and a separator.
    std::size_t min_bytes(Type type) const {
        return encoding_ == Encoding::Ascii ? 2 : type_size(type);
    }

    // A list count or an index: a non-negative integer below `limit`.
    std::uint32_t read_count(Type type, double limit, const char* what) {
        const double value = read(type);
        if (!(value >= 0.0 && value < limit) || value != std::floor(value)) {
            char text[32];
            const auto end = std::to_chars(text, text + sizeof text, value).ptr;
            fail(path_, std::string("bad ") + what + " " + std::string(text, end));
        }
        return std::uint32_t(value);
    }

    std::size_t remaining() const { return data_.size() - pos_; }

private:
    double read_text() {
        pos_ = data_.find_first_not_of(" \t\r\n", pos_);
        if (pos_ == std::string_view::npos) fail(path_, "unexpected end of file");
        if (data_[pos_] == '+') ++pos_;  // from_chars rejects a leading plus
        double value = 0.0;
        const auto [end, ec] =
            std::from_chars(data_.data() + pos_, data_.data() + data_.size(), value);
        const std::size_t stop = std::size_t(end - data_.data());
        if (ec != std::errc() || (stop < data_.size() && !std::strchr(" \t\r\n", data_[stop]))) {
            const std::size_t token_end =
                std::min(data_.find_first_of(" \t\r\n", pos_), data_.size());
            fail(path_, "bad number '" + std::string(data_.substr(pos_, token_end - pos_)) + "'");
        }
        pos_ = stop;
        return value;
    }

    double read_binary(Type type) {
        const std::size_t size = type_size(type);
        if (data_.size() - pos_ < size) fail(path_, "unexpected end of file");
        unsigned char bytes[8];
        std::memcpy(bytes, data_.data() + pos_, size);
        pos_ += size;
        const bool swap =
            (encoding_ == Encoding::BigEndian) != (std::endian::native == std::endian::big);
        if (swap) std::reverse(bytes, bytes + size);
        switch (type) {
            case Type::Int8:
                return as<std::int8_t>(bytes);
            case Type::UInt8:
                return as<std::uint8_t>(bytes);
            case Type::Int16:
                return as<std::int16_t>(bytes);
            case Type::UInt16:
                return as<std::uint16_t>(bytes);
            case Type::Int32:
                return as<std::int32_t>(bytes);
            case Type::UInt32:
                return as<std::uint32_t>(bytes);
            case Type::Float32:
                return as<float>(bytes);
            case Type::Float64:
                return as<double>(bytes);
        }
        return 0.0;
    }

    template <typename T>
    static double as(const unsigned char* bytes) {
        T value;
        std::memcpy(&value, bytes, sizeof value);
        return double(value);
    }

    std::string_view data_;
    Encoding encoding_;
    const std::string& path_;
    std::size_t pos_ = 0;
};

int find_property(const Element& element, std::string_view name) {
    for (std::size_t i = 0; i < element.properties.size(); ++i) {
        if (element.properties[i].name == name && !element.properties[i].is_list) return int(i);
    }
    return -1;
}

constexpr double count_limit = 4294967296.0;  // list counts and indices fit 32 bits

void skip_property(const Property& p, BodyReader& body) {
    const std::uint32_t n = p.is_list ? body.read_count(p.count_type, count_limit, "count") : 1;
    for (std::uint32_t i = 0; i < n; ++i) body.read(p.type);
}

// What a vertex property becomes.
enum class Role : std::uint8_t { Skip, Position, Normal, Atom, Color, Scalar };

struct Slot {
    Role role = Role::Skip;
    std::size_t index = 0;  // the component (0-2), or the scalar's number
};

// A colour channel as a byte: integer types clamped to 0-255, floating-point ones read as [0, 1].
std::uint8_t color_byte(Type type, double value) {
    if (type == Type::Float32 || type == Type::Float64) value = std::clamp(value, 0.0, 1.0) * 255.0;
    return std::uint8_t(std::lround(std::clamp(value, 0.0, 255.0)));
}

void read_vertices(const Element& element, BodyReader& body, Mesh& mesh, const std::string& path) {
    std::vector<Slot> slots(element.properties.size());
    // A group (x y z, nx ny nz, red green blue) is read only when all three are there.
    auto group = [&](const char* const (&names)[3], Role role) {
        int at[3];
        for (int k = 0; k < 3; ++k) at[k] = find_property(element, names[k]);
        if (at[0] < 0 || at[1] < 0 || at[2] < 0) return false;
        for (int k = 0; k < 3; ++k) slots[std::size_t(at[k])] = {role, std::size_t(k)};
        return true;
    };
    if (!group({"x", "y", "z"}, Role::Position)) fail(path, "vertex without x y z");
    const bool normals = group({"nx", "ny", "nz"}, Role::Normal);
    const bool colors = group({"red", "green", "blue"}, Role::Color);
    const int atom = find_property(element, "atom");
    if (atom >= 0) slots[std::size_t(atom)] = {Role::Atom, 0};
    // Every other single-valued property whose name write_mesh would accept becomes a scalar
    // (the first of each name); lists and other names are skipped.
    for (std::size_t i = 0; i < element.properties.size(); ++i) {
        const Property& p = element.properties[i];
        if (p.is_list || slots[i].role != Role::Skip || !valid_scalar_name(p.name)) continue;
        bool seen = false;
        for (const VertexScalars& s : mesh.scalars) seen = seen || s.name == p.name;
        if (seen) continue;
        slots[i] = {Role::Scalar, mesh.scalars.size()};
        mesh.scalars.push_back({p.name, {}});
    }

    // A lying count cannot make us allocate unbounded memory: each vertex takes at least the
    // bytes of its properties (in ASCII the last separator may be missing).
    std::size_t per_vertex = 0;
    for (const Property& p : element.properties)
        per_vertex += body.min_bytes(p.is_list ? p.count_type : p.type);
    if (element.count > (body.remaining() + 1) / std::max<std::size_t>(per_vertex, 1))
        fail(path, "unexpected end of file");
    mesh.positions.resize(3 * element.count);
    if (normals) mesh.normals.resize(3 * element.count);
    if (atom >= 0) mesh.atoms.resize(element.count);
    if (colors) mesh.colors.resize(3 * element.count);
    for (VertexScalars& s : mesh.scalars) s.values.resize(element.count);
    for (std::size_t v = 0; v < element.count; ++v) {
        for (std::size_t i = 0; i < element.properties.size(); ++i) {
            const Property& p = element.properties[i];
            const Slot slot = slots[i];
            switch (slot.role) {
                case Role::Skip:
                    skip_property(p, body);
                    break;
                case Role::Position:
                    mesh.positions[3 * v + slot.index] = float(body.read(p.type));
                    break;
                case Role::Normal:
                    mesh.normals[3 * v + slot.index] = float(body.read(p.type));
                    break;
                case Role::Atom:
                    mesh.atoms[v] = body.read_count(p.type, count_limit, "atom");
                    break;
                case Role::Color:
                    mesh.colors[3 * v + slot.index] = color_byte(p.type, body.read(p.type));
                    break;
                case Role::Scalar:
                    mesh.scalars[slot.index].values[v] = float(body.read(p.type));
                    break;
            }
        }
    }
}

void read_faces(const Element& element, BodyReader& body, Mesh& mesh, const std::string& path) {
    int list = -1;
    for (std::size_t i = 0; i < element.properties.size(); ++i) {
        const Property& p = element.properties[i];
        if (p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index")) list = int(i);
    }
    if (list < 0) fail(path, "face without a vertex_indices list");
    std::vector<std::uint32_t> polygon;
    for (std::size_t f = 0; f < element.count; ++f) {
        for (std::size_t i = 0; i < element.properties.size(); ++i) {
            const Property& p = element.properties[i];
            if (int(i) != list) {
                skip_property(p, body);
                continue;
            }
            const std::uint32_t n = body.read_count(p.count_type, count_limit, "count");
            if (n < 3) fail(path, "face " + std::to_string(f) + " has fewer than 3 vertices");
            polygon.clear();
            for (std::uint32_t j = 0; j < n; ++j) {
                polygon.push_back(body.read_count(p.type, count_limit, "vertex index"));
            }
            // Fan triangulation: exact for the convex polygons that other tools write.
            for (std::uint32_t j = 1; j + 1 < n; ++j) {
                mesh.indices.insert(mesh.indices.end(), {polygon[0], polygon[j], polygon[j + 1]});
            }
        }
    }
}

}  // namespace

Mesh parse_ply(std::string_view data, const std::string& path) {
    const Header header = parse_header(data, path);
    BodyReader body(data.substr(header.body_offset), header.encoding, path);
    Mesh mesh;
    bool has_vertices = false;
    for (const Element& element : header.elements) {
        if (element.name == "vertex" && !has_vertices) {
            read_vertices(element, body, mesh, path);
            has_vertices = true;
        } else if (element.name == "face") {
            read_faces(element, body, mesh, path);
        } else if (!element.properties.empty()) {
            // (an element without properties takes no bytes: nothing to skip, however many it
            // claims; found by fuzz_ply, which looped 4e18 times over one)
            for (std::size_t r = 0; r < element.count; ++r) {
                for (const Property& p : element.properties) skip_property(p, body);
            }
        }
    }
    if (!has_vertices) fail(path, "no vertex element");
    for (std::uint32_t i : mesh.indices) {
        if (i >= mesh.vertex_count()) {
            fail(path, "vertex index " + std::to_string(i) + " out of range");
        }
    }
    return mesh;
}

}  // namespace fdmsurf::detail

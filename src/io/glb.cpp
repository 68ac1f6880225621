// GLB (glTF 2.0 binary) through tinygltf: the writer (POSITION, NORMAL, COLOR_0, _ATOM, a
// _NAME per scalar, UNSIGNED_INT indices) and a reader of the triangle primitives of a scene.
// Layout and choices: docs/formats.md; glTF 2.0 specification, section 3.7 (meshes).
#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <ostream>
#include <streambuf>
#include <string>
#include <type_traits>
#include <vector>

#include "fdmsurf/error.hpp"
#include "fdmsurf/fdmsurf.hpp"
#include "io/formats.hpp"
#include "mesh/mesh_attributes.hpp"

namespace fdmsurf::detail {
namespace {

// The primitive's extras list the scalars' names as given (attribute names are upper case).
const char* const scalar_names_key = "fdmsurf_scalar_names";

[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw Error(ErrorCode::Format, path + ": " + what);
}

std::string lower(std::string_view text) {
    std::string out(text);
    for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

// glTF's COLOR_0 is linear RGB; Mesh::colors are sRGB bytes (IEC 61966-2-1 transfer curve).
// Every byte comes back unchanged through float (tested).
float srgb_to_linear(std::uint8_t byte) {
    const double c = byte / 255.0;
    return float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
}

std::uint8_t linear_to_srgb(double linear) {
    const double l = std::clamp(std::isfinite(linear) ? linear : 0.0, 0.0, 1.0);
    const double c = l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055;
    return std::uint8_t(std::lround(std::clamp(c, 0.0, 1.0) * 255.0));
}

// tinygltf writes to a std::ostream; this one hands its bytes to the sink, whose Error passes
// through the stream (badbit is in its exception mask).
class SinkBuffer final : public std::streambuf {
public:
    explicit SinkBuffer(ByteSink& sink) : sink_(sink) {}

protected:
    std::streamsize xsputn(const char* data, std::streamsize size) override {
        sink_.write(data, std::size_t(size));
        return size;
    }
    int_type overflow(int_type c) override {
        if (!traits_type::eq_int_type(c, traits_type::eof())) {
            const char byte = traits_type::to_char_type(c);
            sink_.write(&byte, 1);
        }
        return traits_type::not_eof(c);
    }

private:
    ByteSink& sink_;
};

// The model under construction: one buffer, one buffer view and accessor per attribute.
class GlbBuilder {
public:
    GlbBuilder() {
        model_.asset.version = "2.0";
        model_.asset.generator = "fdmsurf " + std::string(version());
        model_.buffers.emplace_back();
    }

    // Little-endian 4-byte values as a new buffer view; returns its accessor.
    template <typename T>
    int add(const std::vector<T>& values, int component_type, int type, std::size_t count,
            int target) {
        static_assert(sizeof(T) == 4);
        std::vector<unsigned char>& bytes = model_.buffers[0].data;
        tinygltf::BufferView view;
        view.buffer = 0;
        view.byteOffset = bytes.size();  // every view is a multiple of 4 bytes long
        view.byteLength = 4 * values.size();
        view.target = target;
        bytes.resize(bytes.size() + view.byteLength);
        char* out = reinterpret_cast<char*>(bytes.data() + view.byteOffset);
        if constexpr (std::endian::native == std::endian::little) {
            std::memcpy(out, values.data(), view.byteLength);
        } else {
            for (T value : values) out = put_le(out, value);
        }
        model_.bufferViews.push_back(std::move(view));
        tinygltf::Accessor accessor;
        accessor.bufferView = int(model_.bufferViews.size() - 1);
        accessor.byteOffset = 0;
        accessor.componentType = component_type;
        accessor.type = type;
        accessor.count = count;
        model_.accessors.push_back(std::move(accessor));
        return int(model_.accessors.size() - 1);
    }

    int add_floats(const std::vector<float>& values, int type, std::size_t count) {
        return add(values, TINYGLTF_COMPONENT_TYPE_FLOAT, type, count,
                   TINYGLTF_TARGET_ARRAY_BUFFER);
    }

    tinygltf::Accessor& accessor(int index) { return model_.accessors[std::size_t(index)]; }
    tinygltf::Model& model() { return model_; }
    void reserve(std::size_t bytes) { model_.buffers[0].data.reserve(bytes); }

private:
    tinygltf::Model model_;
};

// Unit normals, as glTF requires of NORMAL: each renormalized in double; one of zero length
// (or not finite) becomes the area-weighted normal of its triangles, or +z without any.
std::vector<float> unit_normals(const Mesh& mesh) {
    std::vector<float> out(mesh.normals.size());
    std::vector<std::size_t> bad;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        const float* n = &mesh.normals[3 * v];
        const double length =
            std::sqrt(double(n[0]) * n[0] + double(n[1]) * n[1] + double(n[2]) * n[2]);
        if (!(length > 1e-12) || !std::isfinite(length)) {
            bad.push_back(v);
            continue;
        }
        for (int k = 0; k < 3; ++k) out[3 * v + k] = float(n[k] / length);
    }
    if (bad.empty()) return out;
    std::vector<double> sum(3 * mesh.vertex_count(), 0.0);
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const float* p[3];
        for (int k = 0; k < 3; ++k)
            p[k] = &mesh.positions[3 * std::size_t{mesh.indices[3 * t + k]}];
        const double u[3] = {double(p[1][0]) - p[0][0], double(p[1][1]) - p[0][1],
                             double(p[1][2]) - p[0][2]};
        const double w[3] = {double(p[2][0]) - p[0][0], double(p[2][1]) - p[0][1],
                             double(p[2][2]) - p[0][2]};
        const double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                             u[0] * w[1] - u[1] * w[0]};
        for (int k = 0; k < 3; ++k) {
            for (int c = 0; c < 3; ++c) sum[3 * std::size_t{mesh.indices[3 * t + k]} + c] += n[c];
        }
    }
    for (std::size_t v : bad) {
        const double* n = &sum[3 * v];
        const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int k = 0; k < 3; ++k) {
            out[3 * v + k] = length > 0.0 && std::isfinite(length) ? float(n[k] / length)
                                                                   : (k == 2 ? 1.0f : 0.0f);
        }
    }
    return out;
}

// ---- reading ----

using Matrix = std::array<double, 16>;  // column-major, as glTF stores it

constexpr Matrix identity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

Matrix multiply(const Matrix& a, const Matrix& b) {
    Matrix m{};
    for (int col = 0; col < 4; ++col) {
        for (int row = 0; row < 4; ++row) {
            double s = 0.0;
            for (int k = 0; k < 4; ++k) s += a[4 * k + row] * b[4 * col + k];
            m[4 * col + row] = s;
        }
    }
    return m;
}

// The node's local transform: its matrix, or T · R · S.
Matrix local_transform(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) {
        Matrix m;
        std::copy(node.matrix.begin(), node.matrix.end(), m.begin());
        return m;
    }
    Matrix m = identity;
    if (node.scale.size() == 3) {
        for (int k = 0; k < 3; ++k) m[5 * k] = node.scale[std::size_t(k)];
    }
    if (node.rotation.size() == 4) {
        const double x = node.rotation[0], y = node.rotation[1], z = node.rotation[2],
                     w = node.rotation[3];
        const Matrix r{1 - 2 * (y * y + z * z),
                       2 * (x * y + z * w),
                       2 * (x * z - y * w),
                       0,
                       2 * (x * y - z * w),
                       1 - 2 * (x * x + z * z),
                       2 * (y * z + x * w),
                       0,
                       2 * (x * z + y * w),
                       2 * (y * z - x * w),
                       1 - 2 * (x * x + y * y),
                       0,
                       0,
                       0,
                       0,
                       1};
        m = multiply(r, m);
    }
    if (node.translation.size() == 3) {
        for (int k = 0; k < 3; ++k) m[12 + k] = node.translation[std::size_t(k)];
    }
    return m;
}

struct PlacedMesh {
    int mesh;
    Matrix transform;
};

class GlbReader {
public:
    GlbReader(const tinygltf::Model& model, const std::string& path) : model_(model), path_(path) {}

    Mesh read() {
        std::vector<PlacedMesh> placed;
        const int scene = model_.defaultScene >= 0 ? model_.defaultScene : 0;
        if (model_.scenes.empty()) {
            for (std::size_t m = 0; m < model_.meshes.size(); ++m)
                placed.push_back({int(m), identity});
        } else {
            if (std::size_t(scene) >= model_.scenes.size())
                fail(path_, "default scene out of range");
            for (int node : model_.scenes[std::size_t(scene)].nodes)
                visit(node, identity, 0, placed);
        }
        for (const PlacedMesh& p : placed) {
            for (const tinygltf::Primitive& primitive :
                 model_.meshes[std::size_t(p.mesh)].primitives) {
                add_primitive(primitive, p.transform);
            }
        }
        return finish();
    }

private:
    void visit(int node, const Matrix& parent, int depth, std::vector<PlacedMesh>& placed) {
        if (node < 0 || std::size_t(node) >= model_.nodes.size())
            fail(path_, "node index out of range");
        if (depth > 64) fail(path_, "nodes nested more than 64 deep (a cycle?)");
        const tinygltf::Node& n = model_.nodes[std::size_t(node)];
        const Matrix transform = multiply(parent, local_transform(n));
        if (n.mesh >= 0) {
            if (std::size_t(n.mesh) >= model_.meshes.size()) fail(path_, "mesh index out of range");
            placed.push_back({n.mesh, transform});
        }
        for (int child : n.children) visit(child, transform, depth + 1, placed);
    }

    const tinygltf::Accessor& accessor(int index, const std::string& what) const {
        if (index < 0 || std::size_t(index) >= model_.accessors.size()) {
            fail(path_, what + ": accessor index out of range");
        }
        return model_.accessors[std::size_t(index)];
    }

    // An accessor's elements as `components` values each, converted to T: floats as they are,
    // normalized integers to [0, 1] or [-1, 1], other integers as integers.
    template <typename T>
    std::vector<T> read_accessor(int index, int components, const std::string& what) const {
        const tinygltf::Accessor& a = accessor(index, what);
        if (a.sparse.isSparse) fail(path_, what + ": sparse accessors are not read");
        if (a.bufferView < 0 || std::size_t(a.bufferView) >= model_.bufferViews.size()) {
            fail(path_, what + ": accessor without a buffer view");
        }
        if (tinygltf::GetNumComponentsInType(std::uint32_t(a.type)) != components) {
            fail(path_,
                 what + ": accessor of " +
                     std::to_string(tinygltf::GetNumComponentsInType(std::uint32_t(a.type))) +
                     " components, expected " + std::to_string(components));
        }
        const tinygltf::BufferView& view = model_.bufferViews[std::size_t(a.bufferView)];
        if (view.buffer < 0 || std::size_t(view.buffer) >= model_.buffers.size()) {
            fail(path_, what + ": buffer index out of range");
        }
        const std::vector<unsigned char>& buffer = model_.buffers[std::size_t(view.buffer)].data;
        const int size = tinygltf::GetComponentSizeInBytes(std::uint32_t(a.componentType));
        if (size <= 0) fail(path_, what + ": unknown component type");
        const std::size_t element = std::size_t(size) * std::size_t(components);
        const std::size_t stride = view.byteStride != 0 ? view.byteStride : element;
        // Bounds in a form that cannot overflow, whatever sizes the file claims.
        const std::size_t bytes = buffer.size();
        const bool view_fits = view.byteOffset <= bytes && view.byteLength <= bytes - view.byteOffset;
        const std::size_t room = view_fits && a.byteOffset <= view.byteLength
                                     ? view.byteLength - a.byteOffset
                                     : 0;
        if (a.count > 0 && (!view_fits || a.byteOffset > view.byteLength || stride < element ||
                            element > room || a.count - 1 > (room - element) / stride)) {
            fail(path_, what + ": accessor reaches beyond its buffer view or buffer");
        }
        const std::size_t start = view.byteOffset + a.byteOffset;
        std::vector<T> out;
        out.reserve(a.count * std::size_t(components));
        const char* base = reinterpret_cast<const char*>(buffer.data()) + start;
        for (std::size_t i = 0; i < a.count; ++i) {
            for (int c = 0; c < components; ++c) {
                const double value = component(base + i * stride + std::size_t(c * size), a);
                if constexpr (std::is_integral_v<T>) {
                    // An index or atom number stored as float: it must be one (found by
                    // fuzz_glb: 4.5e21 converted to an index).
                    if (!(value >= 0.0 && value <= double(std::numeric_limits<T>::max()) &&
                          value == std::floor(value))) {
                        fail(path_, what + ": value " + std::to_string(value) +
                                        " is not an index");
                    }
                }
                out.push_back(T(value));
            }
        }
        return out;
    }

    static double component(const char* p, const tinygltf::Accessor& a) {
        auto le16 = [p] { return std::uint16_t(std::uint8_t(p[0]) | (std::uint8_t(p[1]) << 8)); };
        switch (a.componentType) {
            case TINYGLTF_COMPONENT_TYPE_FLOAT:
                return get_le<float>(p);
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
                return get_le<std::uint32_t>(p);
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
                return a.normalized ? le16() / 65535.0 : le16();
            case TINYGLTF_COMPONENT_TYPE_SHORT:
                return a.normalized ? std::max(std::int16_t(le16()) / 32767.0, -1.0)
                                    : std::int16_t(le16());
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
                return a.normalized ? std::uint8_t(p[0]) / 255.0 : std::uint8_t(p[0]);
            case TINYGLTF_COMPONENT_TYPE_BYTE:
                return a.normalized ? std::max(std::int8_t(p[0]) / 127.0, -1.0) : std::int8_t(p[0]);
            default:
                return 0.0;  // rejected by the size check before
        }
    }

    int attribute(const tinygltf::Primitive& primitive, const std::string& name) const {
        const auto it = primitive.attributes.find(name);
        return it == primitive.attributes.end() ? -1 : it->second;
    }

    // Scalars: every `_NAME` attribute but _ATOM, named by the extras fdmsurf writes, else
    // lower-cased.
    std::vector<std::pair<std::string, int>> scalars_of(const tinygltf::Primitive& p) const {
        std::map<std::string, std::string> given;  // attribute -> name written
        const tinygltf::Value& names =
            p.extras.Has(scalar_names_key) ? p.extras.Get(scalar_names_key) : tinygltf::Value();
        for (std::size_t i = 0; i < names.ArrayLen(); ++i) {
            const tinygltf::Value& name = names.Get(int(i));
            if (name.IsString())
                given[glb_attribute_name(name.Get<std::string>())] = name.Get<std::string>();
        }
        std::vector<std::pair<std::string, int>> out;
        for (const auto& [attribute, index] : p.attributes) {
            if (attribute.size() < 2 || attribute[0] != '_' || attribute == "_ATOM") continue;
            const auto it = given.find(attribute);
            const std::string name = it != given.end() ? it->second : lower(attribute.substr(1));
            if (valid_scalar_name(name)) out.emplace_back(name, index);
        }
        // In the order the extras list them (the order written), the rest after them.
        auto rank = [&](const std::string& name) {
            for (std::size_t i = 0; i < names.ArrayLen(); ++i) {
                const tinygltf::Value& n = names.Get(int(i));
                if (n.IsString() && n.Get<std::string>() == name) return i;
            }
            return names.ArrayLen();
        };
        std::stable_sort(out.begin(), out.end(), [&](const auto& a, const auto& b) {
            return rank(a.first) < rank(b.first);
        });
        return out;
    }

    void add_primitive(const tinygltf::Primitive& p, const Matrix& transform) {
        const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
        if (mode == TINYGLTF_MODE_LINE || mode == TINYGLTF_MODE_LINE_LOOP ||
            mode == TINYGLTF_MODE_LINE_STRIP) {
            return;  // lines bound no surface
        }
        const int position = attribute(p, "POSITION");
        if (position < 0) fail(path_, "a primitive without POSITION");
        const std::vector<double> xyz = read_accessor<double>(position, 3, "POSITION");
        const std::size_t n = xyz.size() / 3;
        const std::size_t first = mesh_.vertex_count();
        if (first + n > std::numeric_limits<std::uint32_t>::max()) fail(path_, "too many vertices");
        const bool moved = transform != identity;
        const Matrix& m = transform;
        const double det = m[0] * (m[5] * m[10] - m[9] * m[6]) -
                           m[4] * (m[1] * m[10] - m[9] * m[2]) + m[8] * (m[1] * m[6] - m[5] * m[2]);
        for (std::size_t v = 0; v < n; ++v) {
            const double* q = &xyz[3 * v];
            for (int k = 0; k < 3; ++k) {
                const double value = moved ? transform[k] * q[0] + transform[4 + k] * q[1] +
                                                 transform[8 + k] * q[2] + transform[12 + k]
                                           : q[k];
                mesh_.positions.push_back(float(value));
            }
        }

        std::vector<std::uint32_t> corners;
        if (p.indices >= 0) {
            corners = read_accessor<std::uint32_t>(p.indices, 1, "indices");
            if (accessor(p.indices, "indices").componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) {
                fail(path_, "float indices");
            }
        } else {
            corners.resize(n);
            for (std::size_t v = 0; v < n; ++v) corners[v] = std::uint32_t(v);
        }
        for (std::uint32_t c : corners) {
            if (c >= n) fail(path_, "vertex index " + std::to_string(c) + " out of range");
        }
        // A mirroring transform turns the winding round (glTF 2.0, 3.7.4).
        auto triangle = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
            if (det < 0) std::swap(b, c);
            mesh_.indices.insert(
                mesh_.indices.end(),
                {std::uint32_t(first + a), std::uint32_t(first + b), std::uint32_t(first + c)});
        };
        if (mode == TINYGLTF_MODE_TRIANGLES) {
            for (std::size_t i = 0; i + 2 < corners.size(); i += 3)
                triangle(corners[i], corners[i + 1], corners[i + 2]);
        } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
            for (std::size_t i = 0; i + 2 < corners.size(); ++i) {
                if (i % 2 == 0) {
                    triangle(corners[i], corners[i + 1], corners[i + 2]);
                } else {
                    triangle(corners[i + 1], corners[i], corners[i + 2]);
                }
            }
        } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
            for (std::size_t i = 1; i + 1 < corners.size(); ++i)
                triangle(corners[0], corners[i], corners[i + 1]);
        } else if (mode != TINYGLTF_MODE_POINTS) {
            fail(path_, "unknown primitive mode " + std::to_string(mode));
        }

        // Attributes, kept only when every primitive has them.
        ++primitives_;
        if (const int normal = attribute(p, "NORMAL"); normal >= 0 && normals_ok_) {
            const std::vector<double> nxyz = read_accessor<double>(normal, 3, "NORMAL");
            if (nxyz.size() != 3 * n) fail(path_, "NORMAL and POSITION counts differ");
            // The inverse transpose of the linear part carries normals; renormalized after.
            for (std::size_t v = 0; v < n; ++v) {
                const double* q = &nxyz[3 * v];
                if (!moved) {
                    for (int k = 0; k < 3; ++k) normals_.push_back(float(q[k]));
                    continue;
                }
                // Cofactor matrix times q (the inverse transpose up to 1/det).
                const double r[3] = {
                    (m[5] * m[10] - m[6] * m[9]) * q[0] + (m[2] * m[9] - m[1] * m[10]) * q[1] +
                        (m[1] * m[6] - m[2] * m[5]) * q[2],
                    (m[6] * m[8] - m[4] * m[10]) * q[0] + (m[0] * m[10] - m[2] * m[8]) * q[1] +
                        (m[2] * m[4] - m[0] * m[6]) * q[2],
                    (m[4] * m[9] - m[5] * m[8]) * q[0] + (m[1] * m[8] - m[0] * m[9]) * q[1] +
                        (m[0] * m[5] - m[1] * m[4]) * q[2]};
                const double length = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
                const double s = length > 0.0 ? (det < 0 ? -1.0 : 1.0) / length : 0.0;
                for (int k = 0; k < 3; ++k) normals_.push_back(float(r[k] * s));
            }
        } else {
            normals_ok_ = false;
        }
        if (const int color = attribute(p, "COLOR_0"); color >= 0 && colors_ok_) {
            const int components =
                tinygltf::GetNumComponentsInType(std::uint32_t(accessor(color, "COLOR_0").type));
            if (components != 3 && components != 4) fail(path_, "COLOR_0 is neither VEC3 nor VEC4");
            const std::vector<double> rgb = read_accessor<double>(color, components, "COLOR_0");
            if (rgb.size() != std::size_t(components) * n)
                fail(path_, "COLOR_0 and POSITION counts differ");
            for (std::size_t v = 0; v < n; ++v) {
                for (int k = 0; k < 3; ++k)
                    colors_.push_back(
                        linear_to_srgb(rgb[std::size_t(components) * v + std::size_t(k)]));
            }
        } else {
            colors_ok_ = false;
        }
        if (const int atom = attribute(p, "_ATOM"); atom >= 0 && atoms_ok_) {
            const std::vector<double> values = read_accessor<double>(atom, 1, "_ATOM");
            if (values.size() != n) fail(path_, "_ATOM and POSITION counts differ");
            for (double value : values) {
                if (!(value >= 0.0) || value > 4294967295.0 || value != std::floor(value)) {
                    fail(path_, "_ATOM value " + std::to_string(value) + " is not an atom index");
                }
                atoms_.push_back(std::uint32_t(value));
            }
        } else {
            atoms_ok_ = false;
        }
        std::vector<VertexScalars> found;
        for (const auto& [name, index] : scalars_of(p)) {
            VertexScalars s{name, read_accessor<float>(index, 1, glb_attribute_name(name))};
            if (s.values.size() != n)
                fail(path_, glb_attribute_name(name) + " and POSITION counts differ");
            found.push_back(std::move(s));
        }
        if (primitives_ == 1) {
            scalars_ = std::move(found);
        } else {
            // Only the names every primitive has.
            std::vector<VertexScalars> kept;
            for (VertexScalars& s : scalars_) {
                for (VertexScalars& f : found) {
                    if (f.name != s.name) continue;
                    s.values.insert(s.values.end(), f.values.begin(), f.values.end());
                    kept.push_back(std::move(s));
                    break;
                }
            }
            scalars_ = std::move(kept);
        }
    }

    Mesh finish() {
        if (primitives_ > 0) {
            if (normals_ok_) mesh_.normals = std::move(normals_);
            if (colors_ok_) mesh_.colors = std::move(colors_);
            if (atoms_ok_) mesh_.atoms = std::move(atoms_);
            mesh_.scalars = std::move(scalars_);
        }
        return std::move(mesh_);
    }

    const tinygltf::Model& model_;
    const std::string& path_;
    Mesh mesh_;
    std::size_t primitives_ = 0;
    bool normals_ok_ = true, colors_ok_ = true, atoms_ok_ = true;
    std::vector<float> normals_;
    std::vector<std::uint8_t> colors_;
    std::vector<std::uint32_t> atoms_;
    std::vector<VertexScalars> scalars_;
};

// Images are not decoded (a surface has none), external files not opened.
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                const unsigned char*, int, void*) {
    return true;
}
bool no_file(const std::string&, void*) { return false; }
std::string same_path(const std::string& path, void*) { return path; }
bool refuse_read(std::vector<unsigned char>*, std::string* err, const std::string& path, void*) {
    if (err) *err += "external file '" + path + "' not read (only GLB with embedded data)";
    return false;
}
bool refuse_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "no files are written";
    return false;
}

std::string one_line(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    for (char& c : text) {
        if (c == '\n' || c == '\r') c = ' ';
    }
    return text;
}

}  // namespace

void write_glb(const Mesh& mesh, ByteSink& sink) {
    GlbBuilder b;
    const std::size_t n = mesh.vertex_count();
    b.reserve(4 * (mesh.positions.size() + mesh.normals.size() + mesh.colors.size() +
                   mesh.atoms.size() + n * mesh.scalars.size() + mesh.indices.size()));
    tinygltf::Primitive primitive;
    if (n > 0) {
        const int position = b.add_floats(mesh.positions, TINYGLTF_TYPE_VEC3, n);
        // glTF requires POSITION's bounds.
        tinygltf::Accessor& a = b.accessor(position);
        a.minValues.assign(3, std::numeric_limits<double>::infinity());
        a.maxValues.assign(3, -std::numeric_limits<double>::infinity());
        for (std::size_t v = 0; v < n; ++v) {
            for (std::size_t k = 0; k < 3; ++k) {
                a.minValues[k] = std::min<double>(a.minValues[k], mesh.positions[3 * v + k]);
                a.maxValues[k] = std::max<double>(a.maxValues[k], mesh.positions[3 * v + k]);
            }
        }
        primitive.attributes["POSITION"] = position;
        if (!mesh.normals.empty()) {
            primitive.attributes["NORMAL"] =
                b.add_floats(unit_normals(mesh), TINYGLTF_TYPE_VEC3, n);
        }
        if (!mesh.colors.empty()) {
            std::vector<float> linear(mesh.colors.size());
            for (std::size_t i = 0; i < linear.size(); ++i)
                linear[i] = srgb_to_linear(mesh.colors[i]);
            primitive.attributes["COLOR_0"] = b.add_floats(linear, TINYGLTF_TYPE_VEC3, n);
        }
        if (!mesh.atoms.empty()) {
            // glTF forbids UNSIGNED_INT for vertex attributes; float is exact to 2^24
            // (check_format_limits).
            const std::vector<float> atoms(mesh.atoms.begin(), mesh.atoms.end());
            primitive.attributes["_ATOM"] = b.add_floats(atoms, TINYGLTF_TYPE_SCALAR, n);
        }
        tinygltf::Value::Array names;
        for (const VertexScalars& scalar : mesh.scalars) {
            primitive.attributes[glb_attribute_name(scalar.name)] =
                b.add_floats(scalar.values, TINYGLTF_TYPE_SCALAR, n);
            names.emplace_back(scalar.name);
        }
        if (!names.empty()) {
            tinygltf::Value::Object extras;
            extras[scalar_names_key] = tinygltf::Value(std::move(names));
            primitive.extras = tinygltf::Value(std::move(extras));
        }
        if (mesh.triangle_count() > 0) {
            primitive.mode = TINYGLTF_MODE_TRIANGLES;
            primitive.indices =
                b.add(mesh.indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                      mesh.indices.size(), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
        } else {
            primitive.mode = TINYGLTF_MODE_POINTS;  // vertices without triangles
        }
    }
    tinygltf::Model& model = b.model();
    model.scenes.emplace_back();
    model.scenes[0].name = "surface";  // tinygltf writes a scene without members as null
    model.defaultScene = 0;
    if (n > 0) {
        tinygltf::Mesh gltf_mesh;
        gltf_mesh.name = "surface";
        gltf_mesh.primitives.push_back(std::move(primitive));
        model.meshes.push_back(std::move(gltf_mesh));
        tinygltf::Node node;
        node.name = "surface";
        node.mesh = 0;
        model.nodes.push_back(std::move(node));
        model.scenes[0].nodes.push_back(0);
    } else {
        model.buffers.clear();  // an empty buffer is invalid glTF
    }

    SinkBuffer buffer(sink);
    std::ostream out(&buffer);
    out.exceptions(std::ios::badbit);  // the sink's Error reaches the caller
    tinygltf::TinyGLTF gltf;
    if (!gltf.WriteGltfSceneToStream(&model, out, false, true)) {
        throw Error(ErrorCode::Internal, "write_mesh: tinygltf could not serialize the GLB");
    }
    out.flush();
}

bool is_glb(std::string_view data) { return data.starts_with("glTF"); }

Mesh parse_glb(std::string_view data, const std::string& path) {
    if (data.size() > std::numeric_limits<unsigned int>::max()) fail(path, "larger than 4 GiB");
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&skip_image, nullptr);
    loader.SetFsCallbacks({&no_file, &same_path, &refuse_read, &refuse_write, nullptr});
    tinygltf::Model model;
    std::string err, warn;
    const bool ok = loader.LoadBinaryFromMemory(
        &model, &err, &warn, reinterpret_cast<const unsigned char*>(data.data()),
        static_cast<unsigned int>(data.size()), "", tinygltf::REQUIRE_VERSION);
    if (!ok) fail(path, "not a valid GLB (tinygltf: " + one_line(err.empty() ? warn : err) + ")");
    return GlbReader(model, path).read();
}

}  // namespace fdmsurf::detail

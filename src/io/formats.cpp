// The stream sink, the table of mesh formats and each format's limits.
#include "io/formats.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <ios>
#include <limits>

#include "fdmsurf/error.hpp"

namespace fdmsurf::detail {
namespace {

constexpr std::size_t chunk_size = std::size_t{1} << 20;

// Float holds every integer up to 2^24 exactly; GLB's _ATOM is a float attribute.
constexpr std::uint32_t max_float_atom = std::uint32_t{1} << 24;

void check_glb(const Mesh& mesh, const std::string& name) {
    auto fail = [&name](const std::string& what) {
        throw Error(ErrorCode::InvalidArgument, "write_mesh: " + name + ": " + what);
    };
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        if (!std::isfinite(mesh.positions[i])) {
            fail("vertex " + std::to_string(i / 3) +
                 " has a non-finite coordinate; glTF (GLB) allows none");
        }
    }
    for (std::size_t v = 0; v < mesh.atoms.size(); ++v) {
        if (mesh.atoms[v] > max_float_atom) {
            fail("atom index " + std::to_string(mesh.atoms[v]) + " (vertex " + std::to_string(v) +
                 ") is beyond 16777216 = 2^24, the largest that GLB's float _ATOM attribute "
                 "holds exactly; write PLY (uint atom) instead");
        }
    }
    std::vector<std::string> names;
    if (!mesh.atoms.empty()) names.push_back("_ATOM");
    for (const VertexScalars& scalar : mesh.scalars) {
        const std::string attribute = glb_attribute_name(scalar.name);
        for (const std::string& taken : names) {
            if (taken == attribute) {
                fail("scalar '" + scalar.name + "' would be the glTF attribute " + attribute +
                     " a second time (GLB attribute names are upper case)");
            }
        }
        names.push_back(attribute);
        for (std::size_t v = 0; v < scalar.values.size(); ++v) {
            if (!std::isfinite(scalar.values[v])) {
                fail("scalar '" + scalar.name + "' is not finite at vertex " + std::to_string(v) +
                     "; glTF (GLB) allows no NaN or infinity");
            }
        }
    }
    // The GLB header counts the whole file in 32 bits; the JSON part is a few kB.
    const std::uint64_t per_vertex = 12 + (mesh.normals.empty() ? 0 : 12) +
                                     (mesh.colors.empty() ? 0 : 12) + (mesh.atoms.empty() ? 0 : 4) +
                                     4 * mesh.scalars.size();
    const std::uint64_t bytes =
        per_vertex * mesh.vertex_count() + 4 * std::uint64_t{mesh.indices.size()};
    if (bytes > std::uint64_t{std::numeric_limits<std::uint32_t>::max()} - (1u << 20)) {
        fail("the mesh needs " + std::to_string(bytes) +
             " bytes of GLB data, beyond GLB's 4 GiB; write PLY instead");
    }
}

}  // namespace

StreamSink::StreamSink(std::ostream& out, std::string name)
    : out_(out), name_(std::move(name)), chunk_(chunk_size) {
    if (!out_) fail("the stream is in a failed state");
}

void StreamSink::write(const void* data, std::size_t size) {
    const char* bytes = static_cast<const char*>(data);
    while (size > 0) {
        if (used_ == chunk_.size()) drain();
        const std::size_t n = std::min(size, chunk_.size() - used_);
        std::memcpy(chunk_.data() + used_, bytes, n);
        used_ += n;
        bytes += n;
        size -= n;
    }
}

void StreamSink::drain() {
    try {
        out_.write(chunk_.data(), std::streamsize(used_));
    } catch (const Error&) {
        throw;
    } catch (const std::ios_base::failure& e) {
        fail(e.what());
    }
    if (!out_) fail("the stream failed");
    used_ = 0;
}

void StreamSink::finish() {
    drain();
    try {
        out_.flush();
    } catch (const Error&) {
        throw;
    } catch (const std::ios_base::failure& e) {
        fail(e.what());
    }
    if (!out_) fail("the stream failed");
}

void StreamSink::fail(const std::string& reason) const {
    throw Error(ErrorCode::Io, "cannot write " + name_ + ": " + reason);
}

std::string glb_attribute_name(std::string_view scalar_name) {
    std::string out = "_";
    for (char c : scalar_name) out += char(std::toupper(static_cast<unsigned char>(c)));
    return out;
}

std::string supported_extensions() {
    std::string out;
    for (std::size_t i = 0; i < kMeshFormats.size(); ++i) {
        if (i > 0) out += i + 1 == kMeshFormats.size() ? " or " : ", ";
        out += kMeshFormats[i].extension;
    }
    return out;
}

void check_format_limits(const Mesh& mesh, MeshFormat format, const std::string& name) {
    switch (format) {
        case MeshFormat::Ply:
            // PLY indices are signed 32-bit ints.
            if (mesh.vertex_count() > std::size_t(std::numeric_limits<std::int32_t>::max())) {
                throw Error(ErrorCode::InvalidArgument,
                            "write_mesh: too many vertices for PLY: " + name);
            }
            break;
        case MeshFormat::Glb:
            check_glb(mesh, name);
            break;
        case MeshFormat::Stl:
            // The count is 32-bit; validate_mesh keeps indices (3 per triangle) within that.
        case MeshFormat::Obj:
        case MeshFormat::Off:
        case MeshFormat::Auto:
            break;
    }
}

}  // namespace fdmsurf::detail

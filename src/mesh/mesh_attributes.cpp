// Per-vertex attributes: shape checks, and gathering every per-vertex array by a list of kept
// vertices.
#include "mesh/mesh_attributes.hpp"

#include <string>

#include "fdmsurf/error.hpp"

namespace fdmsurf::detail {
namespace {

// out[stride i + k] = in[stride kept[i] + k]. In place (&in == &out) when kept is increasing:
// kept[i] >= i, so every read is at or ahead of the write.
template <typename T>
void gather(const std::vector<T>& in, std::vector<T>& out, std::size_t stride,
            const std::vector<std::uint32_t>& kept) {
    if (in.empty()) {
        out.clear();
        return;
    }
    const bool in_place = &in == &out;
    if (!in_place) out.resize(stride * kept.size());
    for (std::size_t i = 0; i < kept.size(); ++i) {
        for (std::size_t k = 0; k < stride; ++k) out[stride * i + k] = in[stride * kept[i] + k];
    }
    if (in_place) out.resize(stride * kept.size());
}

}  // namespace

bool valid_scalar_name(std::string_view name) {
    if (name.empty() || name.size() > 64) return false;
    for (char c : name) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                        (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
        if (!ok) return false;
    }
    for (std::string_view taken :
         {"x", "y", "z", "nx", "ny", "nz", "atom", "red", "green", "blue"}) {
        if (name == taken) return false;
    }
    return true;
}

void validate_attributes(const Mesh& mesh, const char* who) {
    auto fail = [who](const std::string& what) {
        throw Error(ErrorCode::InvalidArgument, std::string(who) + ": " + what);
    };
    const std::size_t n = mesh.vertex_count();
    const std::string counts = " (" + std::to_string(n) + " vertices)";
    if (!mesh.atoms.empty() && mesh.atoms.size() != n) {
        fail("atoms must be empty or one per vertex, not " + std::to_string(mesh.atoms.size()) +
             counts);
    }
    if (!mesh.colors.empty() && mesh.colors.size() != 3 * n) {
        fail("colors must be empty or three per vertex, not " + std::to_string(mesh.colors.size()) +
             counts);
    }
    for (std::size_t s = 0; s < mesh.scalars.size(); ++s) {
        const VertexScalars& scalar = mesh.scalars[s];
        if (!valid_scalar_name(scalar.name)) {
            fail("scalar name '" + scalar.name +
                 "' is not a valid vertex property name (1-64 of A-Z a-z 0-9 _ - ., not x y z "
                 "nx ny nz atom red green blue)");
        }
        for (std::size_t o = 0; o < s; ++o) {
            if (mesh.scalars[o].name == scalar.name) fail("scalar '" + scalar.name + "' twice");
        }
        if (scalar.values.size() != n) {
            fail("scalar '" + scalar.name + "' has " + std::to_string(scalar.values.size()) +
                 " values" + counts);
        }
    }
}

void keep_vertices(Mesh& mesh, const std::vector<std::uint32_t>& kept) {
    gather(mesh.positions, mesh.positions, 3, kept);
    gather(mesh.normals, mesh.normals, 3, kept);
    gather(mesh.atoms, mesh.atoms, 1, kept);
    gather(mesh.colors, mesh.colors, 3, kept);
    for (VertexScalars& scalar : mesh.scalars) gather(scalar.values, scalar.values, 1, kept);
}

void copy_vertices(const Mesh& from, Mesh& to, const std::vector<std::uint32_t>& kept) {
    gather(from.positions, to.positions, 3, kept);
    gather(from.normals, to.normals, 3, kept);
    gather(from.atoms, to.atoms, 1, kept);
    gather(from.colors, to.colors, 3, kept);
    to.scalars.resize(from.scalars.size());
    for (std::size_t s = 0; s < from.scalars.size(); ++s) {
        to.scalars[s].name = from.scalars[s].name;
        gather(from.scalars[s].values, to.scalars[s].values, 1, kept);
    }
}

void clear_attributes(Mesh& mesh) {
    mesh.atoms.clear();
    mesh.colors.clear();
    mesh.scalars.clear();
}

}  // namespace fdmsurf::detail

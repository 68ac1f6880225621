// Shape checks on a Mesh's arrays, shared by the statistics and the writers.
#include "mesh/mesh_validate.hpp"

#include <cstdint>
#include <limits>
#include <string>

#include "fdmsurf/error.hpp"

namespace fdmsurf::detail {

void validate_mesh_arrays(const Mesh& mesh, const char* who, bool check_normals) {
    auto fail = [who](const std::string& what) {
        throw Error(ErrorCode::InvalidArgument, std::string(who) + ": " + what);
    };
    if (mesh.positions.size() % 3 != 0) fail("positions size is not a multiple of 3");
    if (mesh.indices.size() % 3 != 0) fail("indices size is not a multiple of 3");
    if (check_normals && !mesh.normals.empty() && mesh.normals.size() != mesh.positions.size()) {
        fail("normals must be empty or one per vertex");
    }
    // Corner numbers (3 t + k) and vertex numbers are kept in 32 bits internally.
    constexpr std::size_t limit = std::numeric_limits<std::uint32_t>::max();
    if (mesh.vertex_count() > limit || mesh.indices.size() > limit) fail("mesh too large");
}

void validate_mesh(const Mesh& mesh, const char* who, bool check_normals) {
    validate_mesh_arrays(mesh, who, check_normals);
    auto fail = [who](const std::string& what) {
        throw Error(ErrorCode::InvalidArgument, std::string(who) + ": " + what);
    };
    const std::size_t n = mesh.vertex_count();
    for (std::uint32_t i : mesh.indices) {
        if (i >= n) {
            fail("vertex index " + std::to_string(i) + " out of range (" + std::to_string(n) +
                 " vertices)");
        }
    }
}

}  // namespace fdmsurf::detail

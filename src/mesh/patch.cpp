// extract_patch: the open piece of a surface on a selection of atoms (issue 11), with every
// per-vertex attribute.
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "fdmsurf/error.hpp"
#include "fdmsurf/mesh.hpp"
#include "mesh/mesh_attributes.hpp"
#include "mesh/mesh_validate.hpp"

namespace fdmsurf {

Mesh extract_patch(const Mesh& mesh, const std::vector<std::uint8_t>& selected) {
    detail::validate_mesh(mesh, "extract_patch", true);
    detail::validate_attributes(mesh, "extract_patch");
    if (mesh.atoms.empty() && mesh.vertex_count() != 0) {
        throw Error(ErrorCode::InvalidArgument,
                    "extract_patch: the mesh has no per-vertex atoms (Mesh::atoms)");
    }
    for (std::uint32_t atom : mesh.atoms) {
        if (atom >= selected.size()) {
            throw Error(ErrorCode::InvalidArgument,
                        "extract_patch: vertex atom " + std::to_string(atom) +
                            " out of range of the selection (" + std::to_string(selected.size()) +
                            " atoms)");
        }
    }
    constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
    const std::size_t nv = mesh.vertex_count();
    std::vector<std::uint32_t> remap(nv, none);
    Mesh patch;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const std::uint32_t* tri = &mesh.indices[3 * t];
        if (!selected[mesh.atoms[tri[0]]] || !selected[mesh.atoms[tri[1]]] ||
            !selected[mesh.atoms[tri[2]]]) {
            continue;
        }
        for (int k = 0; k < 3; ++k) remap[tri[k]] = 0;  // marked; numbered below
        patch.indices.insert(patch.indices.end(), tri, tri + 3);
    }
    // The patch's vertices in the mesh's order, so that the patch of everything is the mesh
    // less its unreferenced vertices.
    std::vector<std::uint32_t> kept;
    for (std::size_t v = 0; v < nv; ++v) {
        if (remap[v] == none) continue;
        remap[v] = static_cast<std::uint32_t>(kept.size());
        kept.push_back(static_cast<std::uint32_t>(v));
    }
    for (std::uint32_t& i : patch.indices) i = remap[i];
    detail::copy_vertices(mesh, patch, kept);
    return patch;
}

}  // namespace fdmsurf

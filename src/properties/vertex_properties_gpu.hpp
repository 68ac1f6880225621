// The vertex-property passes on the device: the atom of each vertex with its per-atom
// attributes (shaders/vertex_atoms.comp) and the Coulomb potential (shaders/coulombic.comp).
#pragma once

#include <cstdint>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"
#include "vulkan/buffer.hpp"
#include "vulkan/pipeline.hpp"

namespace fdmsurf::detail {

class Commands;
class Context;

// 332 / 4: kcal/(mol e) per e/Å² with ChimeraX's distance-dependent dielectric eps = 4 r.
inline constexpr double kCoulombScale = 332.0 / 4.0;
// The colour ramp's full red and full blue, kcal/(mol e) (ChimeraX's coulombic default).
inline constexpr float kCoulombColorRange = 10.0f;
// coulombic.comp's cells (Å) and the Chebyshev distance in cells within which a charge site is
// summed exactly; farther ones go through the cell's Taylor expansion (second order).
inline constexpr float kCoulombCell = 4.0f;
inline constexpr std::uint32_t kCoulombNearCells = 3;

class VertexPropertiesPass {
public:
    explicit VertexPropertiesPass(Context& ctx);
    // Makes the vertex atoms' pipeline now (made at its first use otherwise); the Coulombic
    // one is left to its first use.
    void make_pipelines() const { atoms_pipeline_.make(); }

    // Per vertex of `mesh`: `1 + per_atom` words, the index of its atom (least power distance
    // to the balls of radius r + radius_add, ties to the lower index) and that atom's words of
    // `attributes` (per_atom words per atom, in atom order; may be empty when per_atom is 0).
    // Records, submits and waits; the stage is marked "vertex-atoms".
    std::vector<std::uint32_t> vertex_atoms(Commands& cmds, const Mesh& mesh, const Atoms& atoms,
                                            float radius_add,
                                            const std::vector<std::uint32_t>& attributes,
                                            std::uint32_t per_atom);

    // The same for a mesh left on the device: `vertices` holds `vertex_count` vertices of 6
    // floats (position, normal), all inside the box [lo, hi]. Returns a new device buffer of 2
    // words per vertex, its atom and that atom's word of `colors` (one per atom): a DeviceMesh's
    // attribute buffer. Nothing is read back. Records, submits and waits; "vertex-atoms".
    Buffer device_vertex_atoms(Commands& cmds, const Buffer& vertices, std::uint32_t vertex_count,
                               const float lo[3], const float hi[3], const Atoms& atoms,
                               float radius_add, const std::vector<std::uint32_t>& colors);

    // Per vertex: the potential (float bits) at `offset` Å out along its normal from every atom
    // of non-zero charge (near ones exactly, far ones through a Taylor expansion per cell),
    // followed, when `color` is set, by its packed red-white-blue colour. Marked "coulombic".
    std::vector<std::uint32_t> coulombic(Commands& cmds, const Mesh& mesh, const Atoms& atoms,
                                         const std::vector<float>& charges, float offset,
                                         bool color);

    // Whether vertex_atoms sorts the vertices by cell before the dispatch (its lanes then search
    // the same cells). It pays on a CPU device (lavapipe: 1AON's pass 0.67 -> 0.41 s) and not on
    // a GPU, where the sort's host time is 70 times the pass's (H100: 74 ms against 1.1 ms), so
    // the default is on for CPU devices only. The result is the same either way (tested).
    void set_sort_vertices(bool sort) { sort_vertices_ = sort; }

    // Whether vertex_atoms finds the atoms in C++ on the host's threads instead of the device
    // (host_vertex_atoms: vertex cells in groups sharing candidate lists, in the shader's float
    // arithmetic and tie rule; the same atoms but where the device's rounding decides a
    // near-tie). A CPU device runs the pass on the same cores, where the host's loop costs less
    // (docs/performance.md); the default is on for CPU devices (the engine sets it from
    // EngineOptions::vertex_atoms). Nothing is then submitted (no "vertex-atoms" device stage),
    // and set_sort_vertices does not apply.
    void set_on_host(bool on_host) { on_host_ = on_host; }
    bool on_host() const { return on_host_; }

private:
    Context& ctx_;
    ComputePipeline atoms_pipeline_, coulomb_pipeline_;
    bool sort_vertices_;
    bool on_host_;
};

}  // namespace fdmsurf::detail

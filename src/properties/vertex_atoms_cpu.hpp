// CPU references of the vertex-property passes (tests): the atom of least power distance per
// vertex and the Coulomb potential, both by brute force in double.
#pragma once

#include <cstdint>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"

namespace fdmsurf::detail {

// Per vertex of `mesh`: argmin_i |p - c_i|² - (r_i + radius_add)² over every atom, ties to the
// lower index. Atoms x vertices: for tests only.
std::vector<std::uint32_t> vertex_atoms_cpu(const Mesh& mesh, const Atoms& atoms,
                                            float radius_add);

// Per vertex of the n at `positions`: argmin_i of the float power ((p - c_i)² summed x, y, z) -
// (r_i + radius_add)², vertex_atoms.comp's expression, ties to the lower index; 0xffffffff where
// no power is below 3e38 (a vertex that is not finite). Atoms x vertices: the plain reference of
// the host's search (host_vertex_atoms), for tests only.
std::vector<std::uint32_t> vertex_atoms_float_cpu(const float* positions, std::size_t n,
                                                  const Atoms& atoms, float radius_add);

// The power distance of vertex v to atom i (double), for reporting near-ties.
double power_distance(const Mesh& mesh, std::size_t v, const Atoms& atoms, std::size_t i,
                      float radius_add);

// Per vertex: sum_i 332 q_i / (4 |x - c_i|²) at x = p + offset n, every atom (all pairs).
std::vector<double> coulombic_cpu(const Mesh& mesh, const Atoms& atoms,
                                  const std::vector<float>& charges, float offset);

}  // namespace fdmsurf::detail

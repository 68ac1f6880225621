// Per-atom areas: the solvent-accessible area of each atom, and a mesh's area shared out to the
// atoms its vertices belong to (docs/areas.md).
#pragma once

#include <cstddef>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"

namespace fdmsurf {

// The solvent-accessible area of every atom (Å², in the order of `atoms`): the part of its
// sphere of radius r + probe that no other atom's such sphere covers, by Shrake & Rupley's test
// points (1973): `points` points per atom on a golden-section spiral, each exposed point
// standing for 4π(r + probe)² / points. probe >= 0 (Å; 0 gives the van der Waals area);
// points >= 1. Runs on all threads. Throws Error(InvalidArgument) for a negative probe or no
// points. Of identical atoms (same centre and radius) the first keeps the area, the others get 0.
std::vector<double> atom_sas_areas(const Atoms& atoms, float probe, int points = 1000);

// A mesh's area shared out to the atoms of its vertices (mesh.atoms, as make_surface fills it):
// each triangle gives a third of its area to the atom of each of its three vertices. The sum
// is the mesh's area. atom_count: the number of atoms mesh.atoms indexes. Throws
// Error(InvalidArgument) when mesh.atoms is empty (on a non-empty mesh) or out of range.
std::vector<double> atom_mesh_areas(const Mesh& mesh, std::size_t atom_count);

}  // namespace fdmsurf

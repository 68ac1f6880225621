// MSMS's files: a surface as BASE.vert and BASE.face, per-atom areas as BASE.area, in the
// layout MSMS (Sanner et al. 1996) writes and the pipelines built on it parse (docs/formats.md).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"

namespace fdmsurf {

// The part of a solvent-excluded surface a vertex lies on, numbered as in the .vert files.
enum class SesPart : std::uint8_t { Contact = 1, Toric = 2, Reentrant = 3 };

// The part of the SES each vertex of `mesh` lies on, as far as the mesh tells: Contact when the
// vertex is within `tolerance` (Å) of its atom's sphere (mesh.atoms); otherwise the probe that
// made it is centred at p + probe·n (n the vertex normal), and the vertex is Reentrant when
// that probe touches three or more atoms (centre within r + probe + tolerance), else Toric.
// Needs mesh.atoms and mesh.normals; probe > 0, tolerance >= 0. Throws Error(InvalidArgument).
std::vector<SesPart> ses_vertex_parts(const Mesh& mesh, const Atoms& atoms, float probe,
                                      float tolerance);

// MSMS's components: [0] every piece of positive volume (the outer surface, what MSMS writes
// by default), then each cavity (a piece of negative volume) as a mesh of its own, largest
// first, as MSMS's -all_components writes them to BASE_1, BASE_2, ... Attributes are carried.
std::vector<Mesh> msms_components(const Mesh& mesh);

struct MsmsFileOptions {
    bool header = true;      // false: no header lines (MSMS's -no_header)
    std::string source;      // named in the first header line (the input file)
    float density = 1.0f;    // vertices per Å², written in the count line as MSMS does
    float probe = 1.5f;      // Å, written in the count line
};

// Writes BASE.vert and BASE.face. Vertex lines: x y z nx ny nz F ATOM T NAME, with F (MSMS's
// analytic face) 0, ATOM the 1-based atom (mesh.atoms + 1), T the part (`parts`) and NAME the
// atom's XYZRN name (left out when the atoms have none); face lines: v1 v2 v3 TYPE 0, 1-based,
// TYPE the part two or three of its vertices share (Toric when all three differ). Each file
// is written under a temporary name and both are renamed into place once both are complete.
// Throws Error (InvalidArgument for a mesh without atoms or normals, Io).
void write_msms_surface(const Mesh& mesh, const Atoms& atoms, const std::vector<SesPart>& parts,
                        const std::string& base, const MsmsFileOptions& options);

// Writes `path` (BASE.area): a header line, then per atom "INDEX SES SAS NAME" (1-based index,
// Å², NAME left out when the atoms have none). ses and sas have one value per atom. Atomic.
void write_msms_areas(const Atoms& atoms, const std::vector<double>& ses,
                      const std::vector<double>& sas, const std::string& path,
                      const MsmsFileOptions& options);

}  // namespace fdmsurf

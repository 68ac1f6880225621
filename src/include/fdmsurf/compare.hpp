// Mesh-to-mesh accuracy: the weighted RMSD of Giard & Macq (2010) and its companions.
#pragma once

#include <cstddef>
#include <string>

#include "fdmsurf/mesh.hpp"

namespace fdmsurf {

struct CompareOptions {
    double spacing = 0.5;          // H (Å): share_beyond_spacing counts d > H; must be > 0
    bool outer_only = false;       // compare only the largest-area piece of each mesh
    double weld_tolerance = 1e-5;  // Å: merge vertices this close first (0: exact duplicates
                                   // only, < 0: no welding)
};

// Distances d(v) are exact point-to-triangle distances (Å) from each vertex v of one mesh to
// the closest point of the other; weights w(v) are the mean area of the triangles around v.
// Both meshes are welded first (vertices within weld_tolerance merged, triangles that collapse
// and vertices no triangle uses dropped), as shared/tools/meshstat.py does.
struct CompareResult {
    double rmsd_weighted = 0;         // sqrt(Σ w d² / Σ w), reference vertices to tested mesh
    double mean_unsigned = 0;         // Σ w d / Σ w
    double mean_signed = 0;           // Σ w s d / Σ w, s > 0 where the reference vertex lies
                                      // outside the tested mesh (by the closest triangle's normal)
    double share_beyond_spacing = 0;  // Σ_{d > H} w / Σ w, a fraction in [0, 1]
    double hausdorff = 0;             // max(max_ref_to_test, max_test_to_ref), vertex-sampled
    double rmsd_tested_to_reference = 0;     // the weighted RMSD the other way round
    double area_ref = 0, area_test = 0;      // Å²
    double volume_ref = 0, volume_test = 0;  // Å³, signed (divergence theorem)
    double area_rel_error = 0;               // (area_test - area_ref) / area_ref
    double volume_rel_error = 0;             // (volume_test - volume_ref) / volume_ref; NaN if 0
    std::size_t ref_vertices = 0, test_vertices = 0;    // after welding (and --outer)
    std::size_t ref_triangles = 0, test_triangles = 0;  // after welding (and --outer)
    double max_ref_to_test = 0;                         // max over reference vertices of d
    double max_test_to_ref = 0;  // max over tested vertices of their distance to reference
};

// Compares `tested` against `reference`. Throws Error(InvalidArgument) for spacing <= 0 or
// malformed index arrays, Error(Format) when a mesh has no triangle of non-zero area left or a
// non-finite coordinate. Uses all hardware threads.
CompareResult compare_meshes(const Mesh& reference, const Mesh& tested,
                             const CompareOptions& options);

// Reads a mesh in any format compare understands: PLY and OBJ (as read_mesh), OFF (OFF, NOFF,
// COFF, NanoShaper's "OFF+N"; polygons fan-triangulated) and MSMS .vert/.face (either name; the
// sibling is found), each optionally gzip-compressed (.ply.gz, .vert.gz, ...). Positions are
// stored as float. Throws Error(Io) for a file that cannot be read, Error(Format) otherwise.
Mesh read_mesh_any(const std::string& path);

}  // namespace fdmsurf

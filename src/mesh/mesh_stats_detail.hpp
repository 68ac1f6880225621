// Mesh statistics with a chosen number of threads (mesh_stats.cpp), for the tests that check
// the figures do not depend on it; compute_stats uses all of the machine's threads.
#pragma once

#include "fdmsurf/mesh.hpp"

namespace fdmsurf::detail {

// compute_stats on `threads` threads (0: the machine's).
MeshStats total_stats(const Mesh& mesh, unsigned threads);

}  // namespace fdmsurf::detail

// Marching cubes on the host, on all threads: the production path where the Vulkan device is
// itself a CPU (lavapipe), whose compute passes for marching cubes cost more than the host's
// own loops (EngineOptions::marching_cubes). The same mesh as marching_cubes_cpu, vertex for
// vertex and triangle for triangle (the same arithmetic, mc_vertex), in a fraction of its time:
// the inside/outside state of each row is packed into 64-bit words, and only the points and
// cells where the words say an edge is crossed are visited.
#pragma once

#include <cstdint>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "isosurface/marching_cubes_cpu.hpp"

namespace fdmsurf::detail {

// A field given plane by plane, x fastest within a plane, rows `pitch` >= nx floats apart:
// value(x, y, z) = planes[z][y * pitch + x] (the slab pipeline's planes are in several host
// buffers; a field read back from the device has the FFT's padded rows).
struct PlaneStack {
    std::vector<const float*> planes;
    std::uint32_t nx = 0, ny = 0, nz = 0;  // nz = planes.size()
    std::uint32_t pitch = 0;

    float at(std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
        return planes[z][std::size_t(y) * pitch + x];
    }
};

// marching_cubes_cpu's mesh (its order and values; see there) of the z range p.z_begin ..
// p.z_end of `f`, on `threads` threads (0: all). Throws as marching_cubes_cpu does.
Mesh marching_cubes_host(const PlaneStack& f, const McParams& p, unsigned threads = 0);

// The same mesh appended to `out` (positions and normals only, as marching cubes makes them):
// its vertices after out's, its indices offset by out's vertex count; reserve_scale as in
// grow_mesh_for_part (marching_cubes_cpu.hpp).
void marching_cubes_host_append(const PlaneStack& f, const McParams& p, Mesh& out,
                                double reserve_scale = 1.0, unsigned threads = 0);

}  // namespace fdmsurf::detail

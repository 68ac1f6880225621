// z-slabs for a grid larger than one field buffer (slab_plan.hpp).
#include "engine/slab_plan.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "fdmsurf/error.hpp"
#include "grid/grid_plan.hpp"

namespace fdmsurf::detail {

namespace {

// The largest spacing change that brings `bytes` under `limit` (sizes scale as 1/h³).
std::string spacing_hint(double bytes, double limit, float spacing) {
    double h = spacing * std::cbrt(bytes / limit) * 1.05;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.2f", std::ceil(h * 100.0) / 100.0);
    return buf;
}

std::string atoms_note(const Atoms* atoms) { return atoms ? isolated_atoms_note(*atoms) : ""; }

std::string grid_words(const std::array<std::uint32_t, 3>& d) {
    return "the grid of " + std::to_string(d[0]) + " x " + std::to_string(d[1]) + " x " +
           std::to_string(d[2]) + " points";
}

}  // namespace

SlabPlan plan_slabs(const SlabInputs& in) {
    const auto& d = in.dims;
    const std::uint32_t overlap = in.overlap;
    const std::uint64_t limit = in.limit;
    const std::uint64_t plane_bytes = std::uint64_t(in.pitch) * d[1] * sizeof(float);
    // The fewest slabs whose planes fit one binding, each as thin as they allow (FFT sizes of
    // 2, 3, 5 and 7 only): every plane beyond the grid's is FFT work for nothing.
    const std::uint64_t fit =
        std::min<std::uint64_t>(limit / plane_bytes, std::uint64_t(d[2]) + 2 * overlap);
    auto planes_for = [&](std::uint32_t count) {
        std::uint32_t n = (d[2] + count - 1) / count + 2 * overlap;
        return in.filtered ? fft_friendly_size(n, false) : n;
    };
    // Marching cubes then reads a core with a plane under it and two above (pitch nx): that
    // must fit one binding too (it decides for the exact SES, whose slabs have no overlap).
    const std::uint64_t mc_plane_bytes = std::uint64_t(d[0]) * d[1] * sizeof(float);
    SlabPlan plan;
    plan.overlap = overlap;
    for (std::uint32_t count = 2; (d[2] + count - 1) / count >= 8; ++count) {
        const std::uint32_t n = planes_for(count);
        const std::uint64_t mc_planes = n - 2 * overlap + 3;  // the core, as rounded for the FFT
        if (n <= fit && mc_planes * mc_plane_bytes <= limit) {
            plan.slab_planes = n;
            break;
        }
    }
    if (plan.slab_planes == 0) {
        const double need =
            std::max(double(plane_bytes) * (2 * overlap + 8), double(mc_plane_bytes) * (8 + 3));
        throw Error(ErrorCode::DeviceLimit,
                    grid_words(d) + " is too wide to be processed in z-slabs " +
                        "within this device's maxStorageBufferRange (" +
                        std::to_string(limit >> 20) + " MiB); a spacing of " +
                        spacing_hint(need, double(limit), in.spacing) + " Å would fit" +
                        atoms_note(in.atoms));
    }
    plan.core = plan.slab_planes - 2 * overlap;
    // The host holds up to three cores at a time (the pending one, the one just read, the part
    // being uploaded), or the whole field where refinement reads it (the filtered SES): that
    // must fit the machine's memory, with room for the mesh.
    const double host_field = in.gather_field
                                  ? double(d[0]) * d[1] * d[2] * sizeof(float)
                                  : 3.0 * double(plan.core + 3) * double(mc_plane_bytes);
    if (in.host_memory > 0 && host_field > 0.5 * in.host_memory) {
        char figures[160];
        std::snprintf(figures, sizeof figures,
                      "%.1f GiB of host memory, more than half of this machine's %.1f GiB",
                      host_field / (1 << 30), in.host_memory / (1 << 30));
        throw Error(ErrorCode::DeviceLimit,
                    grid_words(d) + " is processed in slabs whose field needs " + figures +
                        "; a spacing of " +
                        spacing_hint(host_field, 0.5 * in.host_memory, in.spacing) +
                        " Å would fit" + atoms_note(in.atoms));
    }
    plan.slabs = (d[2] + plan.core - 1) / plan.core;
    return plan;
}

}  // namespace fdmsurf::detail

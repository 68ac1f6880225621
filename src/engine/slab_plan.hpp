// How a grid too large for one field buffer is cut into z-slabs (plan_slabs): a pure function of
// the grid's size, the filter's reach and the memory limits, so that it can be tested without a
// device. The engine's slab path (slabs.cpp) runs the plan.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "fdmsurf/surface.hpp"

namespace fdmsurf::detail {

struct SlabInputs {
    std::array<std::uint32_t, 3> dims{};  // the whole grid's points
    std::uint32_t pitch = 0;    // floats per row of the device's field (dims[0] or more)
    std::uint32_t overlap = 0;  // planes on each side of a core (filter_reach_planes)
    bool filtered = false;      // FFT filter: slab sizes of 2, 3, 5 and 7 only
    std::uint64_t limit = 0;    // bytes one field buffer may take (EngineImpl::field_budget)
    // Whether the host gathers the whole field (refinement of the filtered SES reads it
    // anywhere); otherwise it holds up to three cores at a time.
    bool gather_field = false;
    double host_memory = 0.0;  // bytes of the machine's memory (not positive: unknown)
    float spacing = 0.5f;      // Å, for the messages' hint
    // The atoms, for the messages' note on isolated atoms (isolated_atoms_note); may be null.
    const Atoms* atoms = nullptr;
};

struct SlabPlan {
    std::uint32_t slab_planes = 0;  // planes of each slab's field, overlaps included
    std::uint32_t overlap = 0;      // planes on each side of a core (SlabInputs::overlap)
    std::uint32_t core = 0;         // planes each slab contributes (slab_planes - 2 overlap)
    std::uint32_t slabs = 0;        // slabs over dims[2]
};

// The fewest slabs whose planes fit one binding (and whose cores, with the planes marching
// cubes reads beside them, fit too), each as thin as they allow; the host's memory for the
// cores (or the gathered field) must stay under half the machine's. Throws Error(DeviceLimit)
// with the spacing that would fit when no slab size does.
SlabPlan plan_slabs(const SlabInputs& in);

}  // namespace fdmsurf::detail

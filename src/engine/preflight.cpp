// What the engine checks and says before a surface's work: warnings on settings that cost
// accuracy (a spacing too coarse for the filter, coordinates far from the origin), and whether
// the field fits one piece or goes through slabs (slabs.cpp).
#include "engine/preflight.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/engine_impl.hpp"
#include "engine/engine_steps.hpp"

namespace fdmsurf::detail {

namespace {

// The largest field the host computes and marches in one piece (the exact SES on the host): 1 GiB
// (1AON at 0.5 Å takes 150 MB; the 4YVS assembly's 1.3 GB goes through slabs).
constexpr std::uint64_t kHostFieldBudget = std::uint64_t(1) << 30;

}  // namespace

std::vector<std::string> preflight_warnings(const Atoms& atoms, const SurfaceOptions& options,
                                            const GridPlan& plan) {
    std::vector<std::string> warnings;
    if (plan.filtered && options.spacing > 1.0f / (2.0f * plan.info.cutoff)) {
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "spacing %.3g Å is too coarse for the filter cut-off %.3g 1/Å: the filter "
                      "cannot act unless spacing <= 1/(2 cut-off) = %.3g Å",
                      options.spacing, plan.info.cutoff, 1.0 / (2.0 * plan.info.cutoff));
        warnings.emplace_back(buf);
    }
    // Coordinates far from the origin: single precision's step there is a sizeable part of
    // the spacing (1CRN moved to 1e6 Å: steps of 0.06 Å, area +0.3%; at 1e7, a ball loses a
    // third of its area).
    float far = 0.0f;
    for (float c : atoms.xyz) far = std::max(far, std::fabs(c));
    const double step = double(std::nextafter(far, INFINITY)) - double(far);
    if (step > 0.05 * options.spacing) {
        char buf[300];
        std::snprintf(buf, sizeof buf,
                      "coordinates reach %.3g Å from the origin, where single precision "
                      "steps by %.2g Å (%.0f%% of the spacing): the surface loses "
                      "accuracy; move the structure nearer the origin",
                      double(far), step, 100.0 * step / options.spacing);
        warnings.emplace_back(buf);
    }
    return warnings;
}

double EngineImpl::one_piece_limit(const SurfaceOptions& options, const GridPlan& plan,
                                   bool on_device) const {
    // The exact SES computed and marched on the host never enters a device binding: one piece
    // while the field fits the host's budget (kHostFieldBudget, an eighth of the memory at most,
    // and EngineOptions::max_buffer_range where set), slabs beyond, which bound the host's memory
    // to a few cores of planes.
    const bool host_field_only = plan.exact_ses && !on_device && field_only_on_host(options, plan);
    return host_field_only ? host_field_budget() : double(field_budget());
}

bool EngineImpl::field_only_on_host(const SurfaceOptions& options, const GridPlan& plan) const {
    return on_host(marching_cubes_place) &&
           (plan.exact_ses ? on_host(ses_distance_place) : density_on_host(options, plan));
}

double EngineImpl::host_field_budget() const {
    return std::min({double(kHostFieldBudget), physical_memory() / 8.0,
                     buffer_range_cap ? double(buffer_range_cap) : double(kHostFieldBudget)});
}

}  // namespace fdmsurf::detail

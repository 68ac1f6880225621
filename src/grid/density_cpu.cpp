// Brute-force density (Giard & Macq 2010, eq. of ALGORITHM.md §2): the reference for the GPU pass.
#include "grid/density_cpu.hpp"

#include <cmath>
#include <limits>

namespace fdmsurf::detail {

double density_at(const Atoms& atoms, const GridPlan& plan, std::uint32_t x, std::uint32_t y,
                  std::uint32_t z) {
    const GridInfo& g = plan.info;
    const double p[3] = {g.origin[0] + double(g.spacing) * x, g.origin[1] + double(g.spacing) * y,
                         g.origin[2] + double(g.spacing) * z};
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        double r = double(atoms.radius[i]) + plan.density.radius_add;
        double dx = p[0] - atoms.xyz[3 * i], dy = p[1] - atoms.xyz[3 * i + 1],
               dz = p[2] - atoms.xyz[3 * i + 2];
        best = std::min(best, dx * dx + dy * dy + dz * dz - r * r);
    }
    if (best > plan.density.pi_cut) return 0.0;
    double s = plan.density.sigma;
    return plan.density.level_t * std::exp(-best / (s * s));
}

std::vector<float> density_cpu(const Atoms& atoms, const GridPlan& plan) {
    const auto& d = plan.info.dims;
    std::vector<float> field(plan.field_floats(), 0.0f);
    for (std::uint32_t z = 0; z < d[2]; ++z)
        for (std::uint32_t y = 0; y < d[1]; ++y)
            for (std::uint32_t x = 0; x < d[0]; ++x)
                field[(std::size_t(z) * d[1] + y) * plan.pitch + x] =
                    static_cast<float>(density_at(atoms, plan, x, y, z));
    return field;
}

}  // namespace fdmsurf::detail

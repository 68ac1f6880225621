// Fields the host stages project onto (refine, snap) that need the engine's features.
#pragma once

#include <cmath>

#include "grid/ses_distance_host.hpp"
#include "refine/refine.hpp"

namespace fdmsurf::detail {

// The exact SES distance d (grid/ses_distance_cpu.hpp) as a field for the projection: it grows
// inwards, the surface is d = probe; defined where it is not clamped.
class SesDistanceField final : public SurfaceField {
public:
    SesDistanceField(const SesHostField& ses, double iso, double d_max)
        : ses_(ses), iso_(iso), d_max_(d_max) {}
    bool sample(const Vec3& p, double& value, Vec3& gradient) const override {
        double g[3];
        // ses_distance(features, p, d_max, g, false) (ses_distance_cpu.hpp), faster.
        value = ses_.distance(p.data(), d_max_, g);
        gradient = {g[0], g[1], g[2]};
        return std::abs(value) < d_max_ && (g[0] != 0.0 || g[1] != 0.0 || g[2] != 0.0);
    }
    double iso() const override { return iso_; }
    double outward() const override { return -1.0; }

private:
    const SesHostField& ses_;
    double iso_, d_max_;
};

}  // namespace fdmsurf::detail

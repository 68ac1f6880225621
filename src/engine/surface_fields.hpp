// Fields the host stages project onto (refine, snap) that need the engine's features.
#pragma once

#include <cmath>
#include <memory>

#include "grid/ses_distance_host.hpp"
#include "refine/refine.hpp"

namespace fdmsurf::detail {

// A sample of the exact SES distance from `distance(p, d_max, g)` (SesHostField's or its
// cursor's): defined where d is not clamped and its gradient is not 0.
template <class Distance>
bool sample_ses(Distance&& distance, const Vec3& p, double d_max, double& value, Vec3& gradient) {
    double g[3];
    value = distance(p.data(), d_max, g);
    gradient = {g[0], g[1], g[2]};
    return std::abs(value) < d_max && (g[0] != 0.0 || g[1] != 0.0 || g[2] != 0.0);
}

// The exact SES distance d (grid/ses_distance_cpu.hpp) as a field for the projection: it grows
// inwards, the surface is d = probe; defined where it is not clamped.
class SesDistanceField final : public SurfaceField {
public:
    // Has `ses` list its bins' arcs now (on all threads), before the projection's threads ask.
    SesDistanceField(const SesHostField& ses, double iso, double d_max)
        : ses_(ses), iso_(iso), d_max_(d_max) {
        ses.list_arcs_by_bin();
    }
    bool sample(const Vec3& p, double& value, Vec3& gradient) const override {
        // ses_distance(features, p, d_max, g, false) (ses_distance_cpu.hpp), faster.
        return sample_ses(
            [&](const double* q, double d, double* g) { return ses_.distance(q, d, g); }, p,
            d_max_, value, gradient);
    }
    double iso() const override { return iso_; }
    double outward() const override { return -1.0; }
    std::unique_ptr<SurfaceField> local() const override;
    // The features' bins: the balls and arcs the cursor keeps are those of one bin's points.
    bool visit_cells(Vec3& origin, double& cell) const override {
        const SesFeatures& f = ses_.features();
        origin = {f.origin[0], f.origin[1], f.origin[2]};
        cell = f.bin_size;
        return true;
    }

private:
    const SesHostField& ses_;
    double iso_, d_max_;
};

// SesDistanceField through a SesHostField::Cursor: the same values, for one thread.
class SesDistanceCursorField final : public SurfaceField {
public:
    SesDistanceCursorField(const SesHostField& ses, double iso, double d_max)
        : cursor_(ses), iso_(iso), d_max_(d_max) {}
    bool sample(const Vec3& p, double& value, Vec3& gradient) const override {
        return sample_ses(
            [&](const double* q, double d, double* g) { return cursor_.distance(q, d, g); }, p,
            d_max_, value, gradient);
    }
    double iso() const override { return iso_; }
    double outward() const override { return -1.0; }

private:
    mutable SesHostField::Cursor cursor_;  // what it keeps changes nothing seen from outside
    double iso_, d_max_;
};

inline std::unique_ptr<SurfaceField> SesDistanceField::local() const {
    return std::make_unique<SesDistanceCursorField>(ses_, iso_, d_max_);
}

// The snap stage's projection onto the exact SES at grid spacing h (snap_stage.cpp).
inline ProjectOptions ses_snap_options(double h) {
    ProjectOptions po = project_options_for_spacing(h);
    // Marching cubes put every vertex within a small part of a spacing of the surface; a longer
    // move would be onto another sheet of the level set (near a cusp).
    po.max_distance = 0.5 * h;
    // The last Newton step is taken unchecked once the first-order distance is under h/50: its
    // error is about d²/(2 r) (curvature radii from 1.4 Å, the probe), under 4e-5 Å at 0.5 Å,
    // against h/1000 after one more evaluation; the normal comes from the gradient there: one
    // evaluation of the distance for most vertices instead of three.
    po.tolerance = h / 50.0;
    po.set_normals = true;
    return po;
}

}  // namespace fdmsurf::detail

// The snap stage: marching cubes' mesh placed on the exact surface on the host. vdw and sas:
// crease recovery on the union of balls (src/snap/creases.cpp); the exact SES: every vertex
// projected onto the exact distance (src/refine/refine.cpp's projection, no subdivision).
#include <cmath>
#include <cstdio>

#include "engine/engine_impl.hpp"
#include "engine/surface_fields.hpp"
#include "snap/creases.hpp"
#include "refine/refine.hpp"

namespace fdmsurf::detail {

bool snaps(const SurfaceOptions& options, const GridPlan& plan) {
    return options.snap && !plan.filtered;
}

double chord_tolerance_for(const SurfaceOptions& options) {
    if (options.chord_tolerance >= 0.0f) return options.chord_tolerance;
    // h / 50: on one ball of 1.8 Å at 0.5 Å the chord deficit falls from -1.8% to -0.43% of the
    // area (-0.85% of the volume), and 1CRN's and 4HHB's vdw and sas areas come within 0.7% of
    // FreeSASA's (docs/accuracy.md); h / 25 left 4HHB's sas 0.84% short and 1CRN's vdw volume
    // 0.66%. Proportional to h, it splits less at finer spacings, where the marching-cubes
    // edges are already short.
    return options.spacing / 50.0;
}

void EngineImpl::snap(SurfaceResult& result, const Atoms& atoms, const SurfaceOptions& options,
                      const GridPlan& plan, const SesHostField* ses) {
    if (!snaps(options, plan) || result.mesh.triangle_count() == 0) return;
    const double t0 = now_ms();
    char buf[240];
    if (plan.exact_ses) {
        const SesDistanceField field(*ses, plan.iso, plan.ses_d_max);
        const std::size_t nv = result.mesh.vertex_count();
        const ProjectOptions po = ses_snap_options(plan.info.spacing);
        const ProjectStats p = project_onto_field(result.mesh, 0, field, po);
        result.times.push_back({"snap", now_ms() - t0, false});
        if (p.failed() > 0 && double(p.failed()) > 1e-3 * double(nv)) {
            std::snprintf(buf, sizeof buf,
                          "snap: %zu of %zu vertices (%.2f%%) could not be projected onto the "
                          "exact SES and keep their marching-cubes position",
                          p.failed(), nv, 100.0 * double(p.failed()) / double(nv));
            result.warnings.emplace_back(buf);
        }
        return;
    }
    // vdw and sas: the surface is the level set pi = pi_iso of the power distance, the union of
    // the balls of radius sqrt((r + radius_add)^2 + pi_iso).
    const double sigma2 = double(plan.density.sigma) * plan.density.sigma;
    const double pi_iso = -sigma2 * std::log(double(plan.iso) / plan.density.level_t);
    const BallUnion balls(atoms, plan.density.radius_add, pi_iso);
    CreaseOptions co;
    co.chord_tolerance = chord_tolerance_for(options);
    const std::size_t nv = result.mesh.vertex_count();
    const CreaseStats s = recover_creases(result.mesh, balls, co);
    result.times.push_back({"snap", now_ms() - t0, false});
    if (s.stopped_at_size) {
        std::snprintf(buf, sizeof buf,
                      "snap: stopped splitting at %zu triangles after %d of %d rounds; creases "
                      "and chords may be left (use a coarser spacing or a larger "
                      "--chord-tolerance)",
                      result.mesh.triangle_count(), s.rounds, co.max_rounds);
        result.warnings.emplace_back(buf);
    }
    if (s.unresolved > 0 && double(s.unresolved) > 1e-3 * double(nv)) {
        std::snprintf(buf, sizeof buf,
                      "snap: %zu of %zu vertices (%.2f%%) found no exposed point of the balls "
                      "near them and keep their marching-cubes position",
                      s.unresolved, nv, 100.0 * double(s.unresolved) / double(nv));
        result.warnings.emplace_back(buf);
    }
}

}  // namespace fdmsurf::detail

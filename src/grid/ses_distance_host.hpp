// The exact SES field on the host's threads, for CPU Vulkan devices (EngineOptions::ses_distance,
// --host-ses): the values of shaders/ses_distance.comp, computed by scattering each feature over
// the grid points it can be nearest to instead of gathering every candidate feature per point.
//
// The shader's workgroup reads every sphere within R + d_max of its box and every arc within
// d_max of it (30-50 spheres and 40-50 arcs per point near the surface at 0.5 Å). Here, per slab
// of a few planes:
//   1. each ball writes its depth R - |p - c| into the points it holds (the deepest and whether
//      another ball ties with it, per point): lb, the least d can be;
//   2. a point with 0 < lb < d_max tries the deepest ball's face alone, against that ball's
//      neighbours (the balls that intersect it): exposed, d = lb; buried, the point waits for
//      the arcs (the shader's reasoning, docs/architecture.md); a tie takes the CPU reference's
//      evaluation (ses_distance, every_face false);
//   3. each exposed arc lowers the waiting points within d_max of it (a box around the arc's own
//      points and the ball of radius rho + d_max around its circle's centre) to its distance.
// The same clamp to [plan.ses_d_min, plan.ses_d_max]. Float rounding differs from the shader's
// and the reference's (tests/grid/test_ses_distance_host.cpp: within the GPU test's 5e-5 Å).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "grid/grid_plan.hpp"
#include "grid/ses_features.hpp"

namespace fdmsurf::detail {

class SesHostField {
public:
    // Prepares each arc (its ends' directions, a ball and a box holding it) and, for
    // distance(), each bin's list of the arcs within `d_max` of it (the burial tests read the
    // features' neighbour lists). `f` must outlive the object. threads 0: the hardware's.
    SesHostField(const SesFeatures& f, double d_max, unsigned threads = 0);
    ~SesHostField();
    SesHostField(const SesHostField&) = delete;
    SesHostField& operator=(const SesHostField&) = delete;

    // Planes [z_begin, z_end) of `plan`'s grid (plan.exact_ses): plane z, row y goes to
    // out + ((z - z_begin) * ny + y) * pitch, nx values. Grid points as the shaders compute them
    // (origin + spacing * index, in float, with the plan's own origin and z index).
    // Throws Error(InvalidArgument) for an empty or out-of-range z range or pitch < nx.
    void evaluate(const GridPlan& plan, std::uint32_t z_begin, std::uint32_t z_end, float* out,
                  std::size_t pitch) const;

    // Frees the scratch that evaluate keeps from call to call (its planes' depths and arcs).
    void release_scratch() const;

    // The whole grid in plan.pitch floats per row (ses_field_cpu's layout; the padding is 0).
    std::vector<float> field(const GridPlan& plan) const;

    // d(p) and its gradient at one point: ses_distance(f, p, d_max, gradient, false) (the snap
    // and refine stages), the same value and gradient in exact arithmetic, from the balls of the
    // bins within r_max of p, the deepest's neighbours and the bin's arc list, without
    // trigonometry. d_max at most the constructor's. Points outside the balls, and the rare
    // ties between the two deepest balls, take ses_distance itself.
    double distance(const double p[3], double d_max, double* gradient = nullptr) const;

    const SesFeatures& features() const { return f_; }

    // Lists each bin's arcs for distance() and the Cursor, on all threads, once (they do it
    // themselves when not yet done; call it before running them on threads so that the
    // listing runs on all of them, not inside one). 0.35 GB for the 2.43 M-atom shell at 1 Å.
    void list_arcs_by_bin() const;

    struct Arc;       // an exposed arc's precomputed part, beside f.arcs (ses_distance_host.cpp)
    struct FloatArc;  // its float copy for the field's row kernel
    struct ArcView;   // an arc read whole: its circle in f.arcs and its Arc, by one index

    // distance() for one thread's run of nearby points (the snap's vertices and their Newton
    // steps): keeps the balls of the last block of bins and the arcs of the last bin, copied
    // side by side, while the points stay in them. The same value and gradient as distance(),
    // bit for bit (tests/grid/test_ses_distance_host.cpp).
    class Cursor {
    public:
        explicit Cursor(const SesHostField& field) : field_(field) { field.list_arcs_by_bin(); }
        double distance(const double p[3], double d_max, double* gradient = nullptr);

    private:
        static constexpr std::size_t kNoArc = std::size_t(-1);
        void gather_balls(const int lo[3], const int hi[3]);
        void gather_arcs(std::size_t bin);
        std::size_t nearest_arc(const double p[3], double d_max, double& distance);
        std::size_t near_arcs(const double p[3], double d_max);
        const SesHostField& field_;
        int lo_[3] = {-1, -1, -1}, hi_[3] = {-1, -1, -1};  // the block of the balls kept
        int bin_[3] = {-1, -1, -1};                         // the last point's bin
        // The points that certainly have the block and the bin of the last point (empty at
        // first): the next takes them without bin_cell.
        double inner_lo_[3] = {0, 0, 0}, inner_hi_[3] = {0, 0, 0};
        std::vector<double> ball_x_, ball_y_, ball_z_, ball_r_;  // its balls, bin by bin
        std::vector<std::uint32_t> ball_index_;
        std::vector<double> ball_depth_;  // their depths at the point (scratch)
        std::size_t arc_bin_ = std::size_t(-1);  // the bin of the arcs kept
        std::vector<double> arc_x_, arc_y_, arc_z_, arc_r_;  // their balls, in the bin's order
        std::vector<std::uint32_t> arc_index_;
        std::vector<std::uint32_t> near_;  // the arcs near the point: their places in the above
        std::vector<double> near_d2_;       // and the squared distances to their balls' centres
        std::uint32_t last_arc_ = std::uint32_t(-1);  // the arc the last point ended nearest to
        std::size_t last_at_ = kNoArc;                 // its place in the kept arcs (or none)
        // nearest_arc's answer is distance()'s (kNoArc: none within d_max).
        bool settled_ = false;
        // burier_, one of ball burier_of_'s neighbours, held the last face of it tried.
        std::uint32_t burier_of_ = std::uint32_t(-1), burier_ = 0;
    };

    // The field's row kernel for arc `arc` (an index into features().arcs): best[x] = min(best[x],
    // the float distance from (xs[x], y, z) to the arc) for x in [xa, xb]. For tests.
    void arc_row_distances(std::size_t arc, const float* xs, float y, float z, int xa, int xb,
                           float* best) const;

private:
    struct Box {
        float lo[3], hi[3];
    };
    struct Slab;  // one task of evaluate: a few planes and their scratch (ses_distance_host.cpp)
    struct Scratch;
    struct ScratchPool;
    // The items (balls or arcs, by `start`: the features' sphere_start or arc_start) of the
    // planes of bins that hold z in [z_lo, z_hi] widened by bin_margin_ (clamped to the bins, as
    // the features bin): [first, end) in the features' order, where the bins are z-major, so
    // each plane's items are consecutive.
    std::pair<std::uint32_t, std::uint32_t> in_planes_of_bins(
        double z_lo, double z_hi, const std::vector<std::uint32_t>& start) const;
    ArcView arc_view(std::size_t k) const;  // arc k of f.arcs with arcs_[k]
    void fill_bin_lists() const;            // list_arcs_by_bin's work
    static void arc_row(const FloatArc& arc, const float* xs, float y, float z, int xa, int xb,
                        float* best);
    const SesFeatures& f_;
    unsigned threads_;
    std::unique_ptr<Arc[]> arcs_;                              // beside f.arcs: ends, flags
    std::unique_ptr<std::array<double, 4>[]> arc_ball_;        // each arc's ball: centre, radius
    std::unique_ptr<Box[]> arc_box_;                           // each arc's points' bounds
    double reach_ = 0.0;                                       // the constructor's d_max
    double bin_margin_ = 0.0;  // Å: a centre lies within this of its bin's box
    // Arcs within reach_ of a bin, [start[b], start[b + 1]): for distance() and the Cursor
    // alone, so listed on their first need (list_arcs_by_bin), after the field's evaluation
    // has freed its buffers.
    mutable std::once_flag bins_listed_;
    mutable std::vector<std::uint32_t> bin_arc_start_;
    mutable std::unique_ptr<std::uint32_t[]> bin_arcs_;
    std::unique_ptr<ScratchPool> scratch_;                     // evaluate's, kept between calls
};

}  // namespace fdmsurf::detail

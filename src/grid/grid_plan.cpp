// Grid placement: the atoms' Gaussian support plus a guard band, sized for the FFT.
#include "grid/grid_plan.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "fdmsurf/error.hpp"

namespace fdmsurf {

const char* to_string(SurfaceKind kind) noexcept {
    switch (kind) {
        case SurfaceKind::Ses:
            return "ses";
        case SurfaceKind::Vdw:
            return "vdw";
        case SurfaceKind::Sas:
            return "sas";
    }
    return "?";
}

GridInfo plan_surface_grid(const Atoms& atoms, const SurfaceOptions& options) {
    return detail::plan_grid(atoms, options).info;
}

const char* to_string(SesMethod method) noexcept {
    switch (method) {
        case SesMethod::Fdm:
            return "fdm";
        case SesMethod::Edt:
            return "edt";
    }
    return "?";
}

float effective_cutoff(const SurfaceOptions& o) {
    auto bad = [](const std::string& what) { throw Error(ErrorCode::InvalidArgument, what); };
    if (!std::isfinite(o.spacing) || o.spacing <= 0.0f)
        bad("spacing must be a positive number of Å (got " + std::to_string(o.spacing) + ")");
    if (!std::isfinite(o.probe) || o.probe < 0.0f)
        bad("probe radius must be >= 0 Å (got " + std::to_string(o.probe) + ")");
    if (!std::isfinite(o.sigma) || o.sigma <= 0.0f)
        bad("sigma must be a positive number of Å (got " + std::to_string(o.sigma) + ")");
    if (!std::isfinite(o.cutoff) || o.cutoff < 0.0f)
        bad("cut-off must be >= 0 1/Å (got " + std::to_string(o.cutoff) + ")");
    if (!std::isfinite(o.level) || o.level < 0.0f)
        bad("level must be a positive multiple of T, or 0 for the default (got " +
            std::to_string(o.level) + ")");
    if (std::isnan(o.padding)) bad("padding must be a number of Å");
    if (!(o.density_cut > 0.0f && o.density_cut < 1.0f)) bad("density cut must lie in (0, 1)");
    if (std::isnan(o.chord_tolerance) || std::isinf(o.chord_tolerance))
        bad("chord tolerance must be a number of Å (< 0 for the default)");
    if (o.surface != SurfaceKind::Ses) return 0.0f;
    if (o.method == SesMethod::Edt) {
        if (o.probe <= 0.0f)
            bad("the exact SES (--method edt) needs probe > 0 (probe 0 is the vdw surface)");
        return 0.0f;
    }
    if (o.cutoff > 0.0f) return o.cutoff;
    if (o.probe <= 0.0f)
        bad("a ses surface needs probe > 0 or an explicit --cutoff (probe 0 is the vdw surface)");
    // 1.3: the Gaussian filter's scale that matched the SES best (docs/accuracy.md).
    const float scale = o.filter == FilterShape::Gaussian ? 1.3f : 1.0f;
    return scale / (4.0f * o.probe);
}

float effective_level(const SurfaceOptions& o) {
    if (o.level > 0.0f) return o.level;
    // 0.9: with the Gaussian filter at 1.3/(4 probe), the level that matched the SES volume.
    return o.surface == SurfaceKind::Ses && o.filter == FilterShape::Gaussian ? 0.9f : 1.0f;
}

SurfaceOptions paper_settings(SurfaceOptions options) {
    options.filter = FilterShape::Ideal;
    options.cutoff = 0.0f;
    options.level = 1.0f;
    options.min_cavity_volume = 0.0f;
    return options;
}

}  // namespace fdmsurf

namespace fdmsurf::detail {

std::uint32_t fft_friendly_size(std::uint32_t n, bool even) {
    for (std::uint32_t m = std::max<std::uint32_t>(n, 2);; ++m) {
        if (even && (m & 1)) continue;
        std::uint32_t r = m;
        for (std::uint32_t p : {2u, 3u, 5u, 7u})
            while (r % p == 0) r /= p;
        if (r == 1) return m;
    }
}

std::uint32_t r2c_axis_size(std::uint32_t n) {
    // VkFFT 1.2.26's R2C transform along x costs 1.3-1.8 times more per point at some
    // 2-3-5-7 sizes than at nearby ones (bench/fft_sizes.cpp on lavapipe, two sweeps of
    // x × 160 × 160 and x × 200 × 200 and alternating runs at x × 343 × 240; docs/performance.md):
    // from 240 up, 270, 294, 336, 350, 378 and 400 are slow, these are not. A larger grid at one
    // of them is cheaper overall (336 -> 384: 14% more points, 35-45% less FFT time). Below 240
    // the differences were within the machine's noise.
    static constexpr std::uint32_t kFast[] = {256, 288, 320, 324, 384, 420, 448, 504, 512};
    n = fft_friendly_size(n, true);
    if (n < 240) return n;
    for (std::uint32_t m : kFast)
        if (m >= n) return m;
    return n;
}

float ses_band_steps(const SurfaceOptions& options) {
    // Farther points only need their side, which the clamps keep; a narrower band also shrinks
    // every box's candidates (boxes wholly beyond a clamp are not evaluated, ses_boxes.comp),
    // the host's waiting points and the reach of its arcs and bins.
    return options.snap && options.refine <= 0 ? 1.0f : 2.0f;
}

std::uint32_t canonical_grid_size(const std::array<std::uint32_t, 3>& dims) {
    const std::uint32_t largest = std::max({dims[0], dims[1], dims[2]});
    for (std::uint32_t c : kCanonicalGridSizes) {
        if (c < largest) continue;
        const double points = double(dims[0]) * dims[1] * dims[2];
        const double cube = double(c) * c * c;
        return cube <= 2.5 * points || c <= 96 ? c : 0;
    }
    return 0;
}

namespace {

constexpr double kIsolation = 30.0;  // Å of empty space along an axis that separates groups

// Splits `group` along the first axis whose sorted coordinates leave a gap wider than
// kIsolation, recursively; appends the groups that no axis splits.
void split_groups(const Atoms& atoms, std::vector<std::uint32_t> group,
                  std::vector<std::vector<std::uint32_t>>& out, int depth = 0) {
    for (int a = 0; a < 3 && depth < 64; ++a) {
        std::sort(group.begin(), group.end(), [&](std::uint32_t i, std::uint32_t j) {
            return atoms.xyz[3 * i + a] < atoms.xyz[3 * j + a];
        });
        for (std::size_t k = 1; k < group.size(); ++k) {
            if (double(atoms.xyz[3 * group[k] + a]) - atoms.xyz[3 * group[k - 1] + a] <= kIsolation)
                continue;
            split_groups(atoms, {group.begin(), group.begin() + std::ptrdiff_t(k)}, out, depth + 1);
            split_groups(atoms, {group.begin() + std::ptrdiff_t(k), group.end()}, out, depth + 1);
            return;
        }
    }
    out.push_back(std::move(group));
}

std::string describe_atom(const Atoms& atoms, std::uint32_t i) {
    char where[96];
    std::snprintf(where, sizeof where, "at (%.1f, %.1f, %.1f)", atoms.xyz[3 * i],
                  atoms.xyz[3 * i + 1], atoms.xyz[3 * i + 2]);
    std::string text = "atom " + std::to_string(i + 1);
    if (i < atoms.meta.size()) {
        const AtomMeta& m = atoms.meta[i];
        text += " (" + std::string(m.hetero ? "HETATM " : "") + "serial " +
                std::to_string(m.serial) + " " + m.name + " " + m.residue_name + " " + m.chain +
                std::to_string(m.residue_number) +
                (m.insertion_code != ' ' ? std::string(1, m.insertion_code) : std::string()) + ")";
    }
    return text + " " + where;
}

// The density's and the level's settings of `options` (h: the spacing, cutoff: the filter's).
void set_field_settings(GridPlan& plan, const SurfaceOptions& options, float h, float cutoff) {
    plan.exact_ses = options.surface == SurfaceKind::Ses && options.method == SesMethod::Edt;
    plan.filtered = options.surface == SurfaceKind::Ses && !plan.exact_ses;
    plan.density.sigma = options.sigma;
    plan.density.level_t = 1.0f;
    plan.density.pi_cut = options.sigma * options.sigma * std::log(1.0f / options.density_cut);
    plan.density.radius_add = options.surface == SurfaceKind::Sas ? options.probe : 0.0f;
    plan.iso = effective_level(options) * plan.density.level_t;
    if (plan.exact_ses) {
        plan.iso = options.probe;
        const float band = ses_band_steps(options) * h;
        plan.ses_d_min = options.probe - band;
        plan.ses_d_max = options.probe + band;
    }
    plan.info.spacing = h;
    plan.info.cutoff = cutoff;
}

// The box the atoms' fields reach (the Gaussian support for ses, the balls otherwise), with the
// largest exponent of the density T exp(-pi/σ²) where it must stay finite, and its atom's
// radius; throws on a radius that is not positive or a coordinate that is not finite.
struct AtomExtent {
    double lo[3], hi[3];
    double exponent = 0.0, r_worst = 0.0;
};

AtomExtent atom_extent(const Atoms& atoms, const SurfaceOptions& options, const GridPlan& plan,
                       float h) {
    AtomExtent e;
    double* lo = e.lo;
    double* hi = e.hi;
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::numeric_limits<double>::max();
        hi[a] = -lo[a];
    }
    // The density T exp(-pi/σ²) must stay finite where it matters. ses (filtered): at every
    // point, since the FFT sums it over up to 1e9 points, so r²/σ² <= 60 (the peak on a centre).
    // vdw and sas: only at the points of the edges that cross the level, which lie within a
    // cell's diagonal of the balls' spheres (pi >= -(r² - (r - √3 h)²)), so that exponent <= 80
    // (float overflows at e^88.7): a 25 Å coarse-grained bead keeps the default sigma. Beyond,
    // the mesh had NaN vertices and normals. The largest exponent, and its atom's radius:
    const double h3 = std::sqrt(3.0) * double(h);
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        float r = atoms.radius[i] + plan.density.radius_add;
        if (!(r > 0.0f) || !std::isfinite(r))
            throw Error(ErrorCode::InvalidArgument,
                        "atom " + std::to_string(i + 1) + " has radius " + std::to_string(r));
        const double inner = plan.filtered ? 0.0 : std::max(0.0, double(r) - h3);
        const double x = (double(r) * r - inner * inner) / (double(options.sigma) * options.sigma);
        if (x > e.exponent) e.exponent = x, e.r_worst = r;
        // ses: the whole Gaussian support enters the filter; vdw and sas only need the balls.
        double reach = plan.filtered ? std::sqrt(double(r) * r + plan.density.pi_cut) : r;
        for (int a = 0; a < 3; ++a) {
            double c = atoms.xyz[3 * i + a];
            if (!std::isfinite(c))
                throw Error(ErrorCode::InvalidArgument,
                            "atom " + std::to_string(i + 1) + " has a non-finite coordinate");
            lo[a] = std::min(lo[a], c - reach);
            hi[a] = std::max(hi[a], c + reach);
        }
    }
    return e;
}

// Refuses a sigma whose density would overflow single precision (atom_extent's exponent).
void check_sigma(const GridPlan& plan, const SurfaceOptions& options, const AtomExtent& e,
                 float h) {
    if (plan.exact_ses) return;  // (the exact SES has no density)
    const double exponent = e.exponent, r_worst = e.r_worst;
    const double bound = plan.filtered ? 60.0 : 80.0;
    if (!(exponent <= bound)) {
        // The smallest sigma that passes, from the worst atom's exponent.
        const double least = double(options.sigma) * std::sqrt(exponent / bound);
        char buf[360];
        std::snprintf(buf, sizeof buf,
                      "sigma %.3g Å is too small for atoms of radius %.3g Å%s at spacing "
                      "%.3g Å: the density %s, T e^%.3g, would overflow single precision; "
                      "sigma must be at least %.3g Å (the method's default: 3 Å)",
                      double(options.sigma), r_worst,
                      plan.density.radius_add > 0.0f ? " (with the probe)" : "", double(h),
                      plan.filtered ? "at their centres, which the filter sums"
                                    : "near their spheres",
                      exponent, least + 0.0005);
        throw Error(ErrorCode::InvalidArgument, buf);
    }
}

// The grid's points and origin along each axis: the extent, padded, in points of `h` (FFT
// sizes for the filtered SES), centred.
void place_axes(GridPlan& plan, const Atoms& atoms, const SurfaceOptions& options,
                AtomExtent& e, float padding, float h) {
    double* lo = e.lo;
    double* hi = e.hi;
    for (int a = 0; a < 3; ++a) {
        lo[a] -= padding + 2.0 * h;  // two more points keep the surface off the border
        hi[a] += padding + 2.0 * h;
        double points = std::ceil((hi[a] - lo[a]) / h) + 1.0;
        if (points > 65536.0) {
            // A count past what an integer holds (a padding of 1e30 Å) is given in exponent form.
            char count[32];
            if (points < 1e15)
                std::snprintf(count, sizeof count, "%.0f", points);
            else
                std::snprintf(count, sizeof count, "%.3g", points);
            throw Error(ErrorCode::DeviceLimit,
                        "the grid would have " + std::string(count) +
                            " points along one axis at spacing " + std::to_string(h) +
                            " Å; use a coarser --spacing" +
                            (padding > 100.0 ? " or a smaller --padding" : "") +
                            isolated_atoms_note(atoms));
        }
        if (options.min_grid[a] > 65536)
            throw Error(ErrorCode::InvalidArgument, "min_grid asks for " +
                                                        std::to_string(options.min_grid[a]) +
                                                        " points along one axis; at most 65536");
        std::uint32_t n = std::max(static_cast<std::uint32_t>(points), options.min_grid[a]);
        // VkFFT 1.2.26 is only right for sizes with factors 2, 3, 5, 7 (NOTES.md), and wants
        // the contiguous R2C axis even (and fast: r2c_axis_size).
        if (plan.filtered)
            n = a == 0 ? r2c_axis_size(n) : fft_friendly_size(n, false);
        else
            n = std::max<std::uint32_t>(n, 2);
        plan.info.dims[a] = n;
        double extra = (n - 1) * double(h) - (hi[a] - lo[a]);  // centred in a larger grid
        plan.info.origin[a] = static_cast<float>(lo[a] - extra / 2.0);
    }
}

// Gaussian filter only: its kernel is the same on any box, while the ideal mask, sampled at
// steps of 1/(n h), passes other frequencies on another n (1CRN --paper moved 0.05 Å RMS).
void round_to_canonical(GridPlan& plan, const SurfaceOptions& options, float h) {
    if (plan.filtered && options.canonical_grid && options.filter == FilterShape::Gaussian) {
        // Points added on both sides on the grid's own lattice: the points of the smaller grid
        // keep their places (and densities), and the surface moves only as much as the
        // filter's periodic images farther apart move it.
        if (const std::uint32_t c = canonical_grid_size(plan.info.dims)) {
            for (int a = 0; a < 3; ++a) {
                const std::uint32_t before = (c - plan.info.dims[a]) / 2;
                plan.info.origin[a] =
                    static_cast<float>(double(plan.info.origin[a]) - double(before) * h);
                plan.info.dims[a] = c;
            }
        }
    }
}


}  // namespace

std::string isolated_atoms_note(const Atoms& atoms) {
    if (atoms.size() < 2 || atoms.xyz.size() != 3 * atoms.size()) return {};
    std::vector<std::uint32_t> all(atoms.size());
    for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    std::vector<std::vector<std::uint32_t>> groups;
    split_groups(atoms, std::move(all), groups);
    if (groups.size() < 2) return {};
    // The largest group is the structure; the others are named, smallest first.
    std::sort(groups.begin(), groups.end(),
              [](const auto& x, const auto& y) { return x.size() < y.size(); });
    std::size_t apart = 0;
    for (std::size_t g = 0; g + 1 < groups.size(); ++g) apart += groups[g].size();
    std::string text = "; " + std::to_string(apart) + " atom" + (apart == 1 ? "" : "s") +
                       (apart == 1 ? " lies" : " lie") + " more than " + std::to_string(int(kIsolation)) +
                       " Å from the other " + std::to_string(groups.back().size()) +
                       " across empty space and stretch the grid: ";
    std::size_t named = 0;
    for (std::size_t g = 0; g + 1 < groups.size() && named < 5; ++g)
        for (std::uint32_t i : groups[g]) {
            if (named == 5) break;
            text += (named++ ? ", " : "") + describe_atom(atoms, i);
        }
    if (apart > named) text += ", ...";
    return text + " (misplaced? leave them out with --select, or edit the file)";
}

GridPlan plan_grid(const Atoms& atoms, const SurfaceOptions& options) {
    GridPlan plan;
    const float cutoff = effective_cutoff(options);
    if (atoms.empty()) throw Error(ErrorCode::EmptySelection, "no atoms to build a surface from");
    if (atoms.xyz.size() != atoms.size() * 3)
        throw Error(ErrorCode::InvalidArgument, "atoms: xyz must hold 3 floats per radius");
    const float h = options.spacing;
    set_field_settings(plan, options, h, cutoff);

    float padding = options.padding;
    if (padding < 0.0f) padding = plan.filtered ? 1.0f / cutoff : 1.0f;
    AtomExtent extent = atom_extent(atoms, options, plan, h);
    check_sigma(plan, options, extent, h);
    place_axes(plan, atoms, options, extent, padding, h);
    round_to_canonical(plan, options, h);
    plan.pitch = plan.filtered ? 2 * (plan.info.dims[0] / 2 + 1) : plan.info.dims[0];
    return plan;
}

}  // namespace fdmsurf::detail

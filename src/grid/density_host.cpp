// The density pass on the host (density_host.hpp): shaders/density_tiles.comp's candidate rule
// and density.comp's evaluation, box by box, the boxes of each layer of planes on one thread.
// Compiled with -ffp-contract=off (CMakeLists.txt) so that the power expression is the shader's
// `precise` one, product and sum rounded apart.
#include "grid/density_host.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "base/cpu_features.hpp"
#include "base/parallel.hpp"

namespace fdmsurf::detail {
namespace {

// A box of kBoxX x kBoxY x kBoxZ points: the x rows are one vector of the inner loop, and a
// box is small enough that few atoms can win in it.
constexpr std::uint32_t kBoxX = 8, kBoxY = 8, kBoxZ = 4;

struct Candidates {
    std::vector<float> x, y, z, w;
    void clear() {
        x.clear();
        y.clear();
        z.clear();
        w.clear();
    }
};

// The least power over the candidates at the eight points (px[i], py, pz) into best[i]: the
// shader's expression, and its min as a select. Eight lanes in GCC and Clang vector extensions
// (two SSE vectors on any x86-64; one AVX2 vector where the CPU has it).
FDMSURF_AVX2_CLONES
void least_powers(const float* px, float py, float pz, const Candidates& c, float* best) {
    using V8 = float __attribute__((vector_size(32)));
    V8 x, b = V8{} + 3.0e38f;
    std::memcpy(&x, px, sizeof x);
    const std::size_t n = c.x.size();
    for (std::size_t k = 0; k < n; ++k) {
        const float dy = py - c.y[k], dz = pz - c.z[k];
        const float rest = (dy * dy + dz * dz) - c.w[k];
        const V8 dx = x - c.x[k];
        const V8 pw = dx * dx + rest;
        b = pw < b ? pw : b;
    }
    std::memcpy(best, &b, sizeof b);
}

class BoxDensity {
public:
    BoxDensity(const AtomBins& bins, const GridPlan& plan) : bins_(bins), plan_(plan) {
        const GridInfo& g = plan.info;
        for (int a = 0; a < 3; ++a) origin_[a] = g.origin[a];
        inv_sigma2_ = 1.0f / (plan.density.sigma * plan.density.sigma);
    }

    // Box (bx, by, bz)'s points into `field`.
    void fill(std::uint32_t bx, std::uint32_t by, std::uint32_t bz, float* field,
              std::uint32_t pitch, Candidates& c) const {
        const GridInfo& g = plan_.info;
        const std::uint32_t first[3] = {bx * kBoxX, by * kBoxY, bz * kBoxZ};
        const std::uint32_t size[3] = {kBoxX, kBoxY, kBoxZ};
        float lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            const std::uint32_t last = std::min(first[a] + size[a], g.dims[a]) - 1;
            lo[a] = origin_[a] + g.spacing * float(first[a]);
            hi[a] = origin_[a] + g.spacing * float(last);
        }
        gather(lo, hi, c);
        const float pi_cut = plan_.density.pi_cut, level = plan_.density.level_t;
        static_assert(kBoxX == 8);
        float px[kBoxX], best[kBoxX];
        for (std::uint32_t i = 0; i < kBoxX; ++i) px[i] = origin_[0] + g.spacing * float(first[0] + i);
        const std::uint32_t x_end = std::min(kBoxX, g.dims[0] - first[0]);
        for (std::uint32_t z = first[2]; z < std::min(first[2] + kBoxZ, g.dims[2]); ++z)
            for (std::uint32_t y = first[1]; y < std::min(first[1] + kBoxY, g.dims[1]); ++y) {
                least_powers(px, origin_[1] + g.spacing * float(y), origin_[2] + g.spacing * float(z),
                             c, best);
                float* row = field + (std::size_t(z) * g.dims[1] + y) * pitch + first[0];
                for (std::uint32_t i = 0; i < x_end; ++i)
                    row[i] = best[i] <= pi_cut ? level * std::exp(-best[i] * inv_sigma2_) : 0.0f;
            }
    }

private:
    // The atoms that can be the least power somewhere in the box [lo, hi]: U bounds the least
    // power from above everywhere in it (capped at pi_cut: beyond, the density is 0), and only
    // atoms whose least power over the box is at most U can win (density_tiles.comp).
    void gather(const float (&lo)[3], const float (&hi)[3], Candidates& c) const {
        c.clear();
        const float* atoms = bins_.atoms.data();
        const float near = std::sqrt(bins_.r2_max) + 0.5f * bins_.size;
        std::int32_t b_lo[3], b_hi[3];
        bin_range(lo, hi, near, b_lo, b_hi);
        float u = plan_.density.pi_cut;
        for (std::int32_t z = b_lo[2]; z <= b_hi[2]; ++z)
            for (std::int32_t y = b_lo[1]; y <= b_hi[1]; ++y) {
                const std::size_t row = (std::size_t(z) * bins_.dims[1] + y) * bins_.dims[0];
                for (std::uint32_t i = bins_.start[row + b_lo[0]];
                     i < bins_.start[row + b_hi[0] + 1]; ++i) {
                    const float* a = atoms + 4 * i;
                    float f2 = 0.0f;
                    for (int d = 0; d < 3; ++d) {
                        const float f = std::max(std::abs(a[d] - lo[d]), std::abs(a[d] - hi[d]));
                        f2 += f * f;
                    }
                    u = std::min(u, f2 - a[3]);
                }
            }
        // The slack keeps float rounding in the bounds below from dropping the true minimiser.
        u += 1e-3f * (1.0f + std::abs(u));
        const float reach = std::sqrt(std::max(u + bins_.r2_max, 0.0f));
        bin_range(lo, hi, reach, b_lo, b_hi);
        for (std::int32_t z = b_lo[2]; z <= b_hi[2]; ++z)
            for (std::int32_t y = b_lo[1]; y <= b_hi[1]; ++y) {
                // A row of bins whose y-z distance to the box exceeds the reach holds none.
                const float row_lo[2] = {bins_.origin[1] + float(y) * bins_.size,
                                         bins_.origin[2] + float(z) * bins_.size};
                float gap2 = 0.0f;
                for (int d = 0; d < 2; ++d) {
                    const float gap = std::max(
                        std::max(row_lo[d] - hi[d + 1], lo[d + 1] - (row_lo[d] + bins_.size)), 0.0f);
                    gap2 += gap * gap;
                }
                if (gap2 - bins_.r2_max > u) continue;
                const std::size_t row = (std::size_t(z) * bins_.dims[1] + y) * bins_.dims[0];
                for (std::uint32_t i = bins_.start[row + b_lo[0]];
                     i < bins_.start[row + b_hi[0] + 1]; ++i) {
                    const float* a = atoms + 4 * i;
                    float d2 = 0.0f;
                    for (int d = 0; d < 3; ++d) {
                        const float gap = std::max(std::max(lo[d] - a[d], a[d] - hi[d]), 0.0f);
                        d2 += gap * gap;
                    }
                    if (d2 - a[3] > u) continue;
                    c.x.push_back(a[0]);
                    c.y.push_back(a[1]);
                    c.z.push_back(a[2]);
                    c.w.push_back(a[3]);
                }
            }
    }

    void bin_range(const float (&lo)[3], const float (&hi)[3], float reach, std::int32_t (&b_lo)[3],
                   std::int32_t (&b_hi)[3]) const {
        for (int a = 0; a < 3; ++a) {
            const float top = float(bins_.dims[a] - 1);
            b_lo[a] = std::int32_t(
                std::clamp(std::floor((lo[a] - reach - bins_.origin[a]) / bins_.size), 0.0f, top));
            b_hi[a] = std::int32_t(
                std::clamp(std::floor((hi[a] + reach - bins_.origin[a]) / bins_.size), 0.0f, top));
        }
    }

    const AtomBins& bins_;
    const GridPlan& plan_;
    float origin_[3];
    float inv_sigma2_;
};

}  // namespace

void density_host(const AtomBins& bins, const GridPlan& plan, float* field, std::uint32_t pitch,
                  unsigned threads) {
    const GridInfo& g = plan.info;
    const std::uint32_t group[3] = {kBoxX, kBoxY, kBoxZ};
    const std::vector<std::uint32_t> boxes = reached_boxes(bins, plan, group);
    const std::uint32_t n[3] = {(g.dims[0] + kBoxX - 1) / kBoxX, (g.dims[1] + kBoxY - 1) / kBoxY,
                                (g.dims[2] + kBoxZ - 1) / kBoxZ};
    const std::size_t layer_boxes = std::size_t(n[0]) * n[1];
    const BoxDensity density(bins, plan);
    // A layer of kBoxZ planes per chunk: zeroed, then its reached boxes (a run of the ascending
    // list) filled. Its pages are first touched by the thread that fills them.
    parallel_chunks(n[2], thread_count(threads), [&](std::size_t layer) {
        const std::uint32_t z0 = std::uint32_t(layer) * kBoxZ;
        const std::uint32_t z1 = std::min(z0 + kBoxZ, g.dims[2]);
        for (std::uint32_t z = z0; z < z1; ++z)
            for (std::uint32_t y = 0; y < g.dims[1]; ++y)
                std::memset(field + (std::size_t(z) * g.dims[1] + y) * pitch, 0,
                            g.dims[0] * sizeof(float));
        const auto first = std::lower_bound(boxes.begin(), boxes.end(),
                                            std::uint32_t(layer * layer_boxes));
        const auto last = std::lower_bound(first, boxes.end(),
                                           std::uint32_t((layer + 1) * layer_boxes));
        thread_local Candidates c;
        for (auto it = first; it != last; ++it) {
            const std::uint32_t b = *it;
            density.fill(b % n[0], (b / n[0]) % n[1], std::uint32_t(layer), field, pitch, c);
        }
    });
}

}  // namespace fdmsurf::detail

// Benchmark of the spectral filter stage (VkFFT forward, mask, inverse) alone, per grid size:
// which 2-3-5-7 sizes are cheap on this device. Prints a Markdown table of GPU times (timestamp
// queries) per size, median of --reps runs after one warm-up run (plans and Mesa cache filled).
//
//   build/fdmsurf_bench_fft [--reps N] [NXxNYxNZ ...]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "bench_common.hpp"
#include "engine/engine_impl.hpp"
#include "fdmsurf/error.hpp"

using namespace fdmsurf;
using namespace fdmsurf::detail;
using fdmsurf::bench::median;
using fdmsurf::bench::stage;

int main(int argc, char** argv) {
    int reps = 3;
    std::vector<std::array<std::uint32_t, 3>> sizes;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--reps") && i + 1 < argc) {
            reps = std::max(1, std::atoi(argv[++i]));
            continue;
        }
        std::array<std::uint32_t, 3> d{};
        if (std::sscanf(argv[i], "%ux%ux%u", &d[0], &d[1], &d[2]) != 3 || d[0] < 2 || d[0] % 2 ||
            d[1] < 2 || d[2] < 2) {
            std::fprintf(stderr, "bad size %s (want NXxNYxNZ, NX even)\n", argv[i]);
            return 2;
        }
        sizes.push_back(d);
    }
    if (sizes.empty())
        sizes = {{192, 168, 168}, {192, 168, 160}, {192, 160, 160}, {336, 343, 288},
                 {336, 343, 245}, {336, 343, 250}, {336, 343, 256}, {336, 350, 256}};
    try {
        EngineImpl e{EngineOptions{}};
        std::printf("device: %s\n\n", e.context.info().name.c_str());
        std::printf(
            "| grid | Mpoints | forward (ms) | mask (ms) | inverse (ms) | FFT ns/point |\n");
        std::printf("|---|---|---|---|---|---|\n");
        for (const auto& d : sizes) {
            GridPlan plan;
            plan.info.dims = {d[0], d[1], d[2]};
            plan.info.spacing = 0.5f;
            plan.info.cutoff = 0.232f;
            plan.pitch = 2 * (d[0] / 2 + 1);
            plan.filtered = true;
            std::vector<float> field(plan.field_floats());
            std::uint32_t state = 1;
            for (float& v : field) {
                state = state * 1664525u + 1013904223u;
                v = float(state >> 8) / float(1u << 24);
            }
            std::vector<double> fwd, mask, inv;
            for (int r = 0; r <= reps; ++r) {
                e.filter_field(field, plan, FilterShape::Gaussian);
                if (r == 0) continue;  // warm-up: plan, pipelines
                fwd.push_back(stage(e.commands.stage_times(), "fft-forward"));
                mask.push_back(stage(e.commands.stage_times(), "mask"));
                inv.push_back(stage(e.commands.stage_times(), "fft-inverse"));
            }
            const double points = double(d[0]) * d[1] * d[2];
            std::printf("| %u×%u×%u | %.2f | %.0f | %.0f | %.0f | %.0f |\n", d[0], d[1], d[2],
                        points / 1e6, median(fwd), median(mask), median(inv),
                        (median(fwd) + median(inv)) * 1e6 / points);
            std::fflush(stdout);
        }
    } catch (const Error& err) {
        std::fprintf(stderr, "error: %s\n", err.what());
        return 1;
    }
    return 0;
}

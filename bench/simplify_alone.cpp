// Benchmark of simplify_mesh alone (no surface, no write): reads a mesh (PLY, OBJ, OFF, STL or
// GLB through read_mesh_any), simplifies it --reps times at --ratio and prints the median wall
// time, the process's CPU time per run, and the report's counts, so that a change to
// src/simplify/ can be timed without the surface's noise (docs/performance.md, simplification).
//
//   build/fdmsurf_bench_simplify MESH [--ratio 0.1] [--reps 3] [--no-distance]
//                                [--simplifier collapse|meshopt] [--whole-meshopt]
//
// --whole-meshopt times, as a reference, one meshopt_simplify call on the whole mesh instead:
// meshoptimizer 0.18 on one thread, with no regions and no topology check (what a caller that
// hands the mesh to the library directly gets; simplify_mesh cannot return this result, which
// may pinch necks).
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "fdmsurf/compare.hpp"
#include "fdmsurf/simplify.hpp"

#include <meshoptimizer.h>

using namespace fdmsurf;

namespace {

double cpu_seconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

// body() run `reps` times: the medians of its wall time and of the process's CPU time, ms.
struct Timing {
    double wall = 0.0, cpu = 0.0;
};
template <class Body>
Timing time_runs(int reps, Body&& body) {
    std::vector<double> wall, cpu;
    for (int r = 0; r < reps; ++r) {
        const double c0 = cpu_seconds();
        const auto t0 = std::chrono::steady_clock::now();
        body();
        wall.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count());
        cpu.push_back(1e3 * (cpu_seconds() - c0));
    }
    return {median(wall), median(cpu)};
}

}  // namespace

int main(int argc, char** argv) try {
    if (argc < 2) {
        std::fprintf(stderr,
                     "usage: %s MESH [--ratio R] [--reps N] [--no-distance] "
                     "[--simplifier collapse|meshopt] [--whole-meshopt]\n",
                     argv[0]);
        return 2;
    }
    SimplifyOptions options;
    options.ratio = 0.1;
    options.measure_distance = true;
    int reps = 3;
    bool whole_meshopt = false;
    for (int i = 2; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--whole-meshopt"))
            whole_meshopt = true;
        else if (!std::strcmp(argv[i], "--no-distance"))
            options.measure_distance = false;
        else if (!std::strcmp(argv[i], "--ratio") && i + 1 < argc)
            options.ratio = std::strtod(argv[++i], nullptr);
        else if (!std::strcmp(argv[i], "--simplifier") && i + 1 < argc &&
                 (!std::strcmp(argv[i + 1], to_string(Simplifier::kCollapse)) ||
                  !std::strcmp(argv[i + 1], to_string(Simplifier::kMeshopt))))
            options.simplifier = std::strcmp(argv[++i], to_string(Simplifier::kMeshopt))
                                     ? Simplifier::kCollapse
                                     : Simplifier::kMeshopt;
        else if (!std::strcmp(argv[i], "--reps") && i + 1 < argc)
            reps = std::max(1, std::atoi(argv[++i]));
        else {
            std::fprintf(stderr, "unknown option %s\n", argv[i]);
            return 2;
        }
    }
    if (!(options.ratio > 0.0 && options.ratio <= 1.0)) {
        std::fprintf(stderr, "--ratio must be in (0, 1], not %g\n", options.ratio);
        return 2;
    }
    const Mesh mesh = read_mesh_any(argv[1]);
    if (whole_meshopt) {
        // (--simplifier and --no-distance do not apply: no simplify_mesh, no distance.)
        const std::size_t target =
            3 * std::max<std::size_t>(1, std::size_t(std::llround(options.ratio *
                                                                  double(mesh.triangle_count()))));
        std::vector<std::uint32_t> out(mesh.indices.size());
        std::size_t kept = 0;
        const Timing t = time_runs(reps, [&] {
            kept = meshopt_simplify(out.data(), mesh.indices.data(), mesh.indices.size(),
                                    mesh.positions.data(), mesh.vertex_count(), 3 * sizeof(float),
                                    target, 1.0f);
        });
        std::printf("%s: %zu -> %zu triangles (target %zu), one meshopt_simplify call on the whole "
                    "mesh, no topology check\nmedian of %d: %.0f ms wall, %.0f ms CPU\n",
                    argv[1], mesh.triangle_count(), kept / 3, target / 3, reps, t.wall, t.cpu);
        return 0;
    }
    std::vector<double> stage, distance;
    SimplifyReport report;
    std::size_t out_triangles = 0;
    std::uint64_t hash = 0;
    const Timing timing = time_runs(reps, [&] {
        const Mesh out = simplify_mesh(mesh, options, &report);
        for (const auto& t : report.times)
            if (t.name == "simplify") stage.push_back(t.ms);
            else if (t.name == "simplify-compare") distance.push_back(t.ms);
        out_triangles = out.triangle_count();
        hash = 1469598103934665603ull;  // FNV-1a over the indices and the positions' bits
        for (std::uint32_t i : out.indices) hash = (hash ^ i) * 1099511628211ull;
        for (float x : out.positions) {
            std::uint32_t b;
            std::memcpy(&b, &x, 4);
            hash = (hash ^ b) * 1099511628211ull;
        }
    });
    std::printf(
        "%s: %zu -> %zu triangles (target %zu), %zu regions, %zu runs, frozen %zu, "
        "closed manifold %d, RMSD %.4f Å, Hausdorff %.3f Å, mesh hash %016llx\n",
        argv[1], mesh.triangle_count(), out_triangles, report.target_triangles, report.regions,
        std::size_t(report.attempts), report.frozen_triangles,
        int(report.stats_out.is_closed_manifold()), report.rmsd, report.hausdorff,
        static_cast<unsigned long long>(hash));
    std::printf("median of %d: simplify stage %.0f ms, distance (simplify-compare) %.0f ms, call "
                "%.0f ms wall, %.0f ms CPU\n",
                reps, median(stage), median(distance), timing.wall,
                timing.cpu);
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "fdmsurf_bench_simplify: %s\n", e.what());
    return 1;
}

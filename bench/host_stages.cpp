// Benchmark of the host stages that follow the device work on a real surface: mesh statistics,
// cavity classification, and writing the mesh (PLY). The surface is computed once with the
// default options; each host stage then runs --reps times on copies of its mesh, and a Markdown
// table of median milliseconds is printed, with the thread count the stages may use.
//
//   build/fdmsurf_bench_host STRUCTURE [--spacing H] [--reps N] [--out DIR] [--mesh FILE]
//
// --mesh FILE: the host stages on that mesh (a surface of STRUCTURE written before, e.g. by the
// CLI) instead of computing it: no device work, the same mesh for two builds. --only stats,
// cavities, fused or write: that stage alone (fused: the engine's path, the pieces and their
// statistics found once, the cavities removed with them, the statistics of the pieces kept).
// --only removal: the engine's cavities stage alone (the removal on the analysis found before
// it), each run on the mesh and analysis restored in place, so that no run pays fresh pages.
// --only ses-features: the exact SES's features of STRUCTURE (build_ses_features: neighbours,
// circles, exposed arcs; the CLI's ses-features stage less the host's index of them), without a
// surface, with a hash of them; --only ses-features-plain: the same by its plain reference
// (build_ses_features_plain: every circle cut by every neighbour), for an A/B in one binary.
// --only exact-areas: the exact per-atom SASA of STRUCTURE (atom_exact_areas at the
// probe, sphere patches: what Engine.trajectory computes per frame), without a surface.
// --only ses-field: the exact SES field of STRUCTURE on the host (--method edt's ses-host stage:
// SesHostField::evaluate over the whole grid), without a surface. --only ses-index: the host's
// index of the features alone (SesHostField's constructor, the arcs prepared, part of the CLI's
// ses-features stage; and its bins' lists of arcs, made at the CLI's snap). --only ses-snap: the
// exact SES snap (--method edt's snap stage, the bins' lists included) of the vertices of
// --mesh, a surface written with --no-snap.
// Both print a hash of their output (the field, the snapped positions and normals) and the CPU
// seconds beside the wall time, which a loaded machine spreads.
// --only vertex-atoms: each vertex's atom on the host (the CLI's vertex-atoms stage on a CPU
// device) for the mesh, --radius-add A for a sas mesh (the probe).
// --probe P: the probe radius of every stage (default 1.4 Å), e.g. to check the exact SES's
// features at another probe.
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "base/trace.hpp"
#include "engine/surface_fields.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf/fdmsurf.hpp"
#include "grid/ses_features.hpp"
#include "mesh/cavities.hpp"
#include "mesh/mesh_attributes.hpp"
#include "mesh/mesh_stats_detail.hpp"
#include "properties/vertex_atoms_host.hpp"

using namespace fdmsurf;

namespace {

double median_ms(int reps, const std::function<void()>& body) {
    std::vector<double> ms;
    for (int r = 0; r < reps; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        body();
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(ms.begin(), ms.end());
    return ms[ms.size() / 2];
}

// The process's CPU time, all threads.
double cpu_ms() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) / 1e6;
}

// FNV-1a over the bytes of a float array: the same output of two builds.
std::uint64_t hash_floats(const std::vector<float>& v) {
    std::uint64_t h = 1469598103934665603ull;
    const auto* b = reinterpret_cast<const unsigned char*>(v.data());
    for (std::size_t i = 0; i < v.size() * sizeof(float); ++i) h = (h ^ b[i]) * 1099511628211ull;
    return h;
}

// FNV-1a over the bytes of the exact SES's features: the arcs and their bins' starts, the
// spheres and their bins' starts, the neighbour rows, the counts and the largest radii.
std::uint64_t features_hash(const detail::SesFeatures& f) {
    std::uint64_t h = 1469598103934665603ull;
    auto bytes = [&](const void* data, std::size_t size) {
        const auto* b = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < size; ++i) h = (h ^ b[i]) * 1099511628211ull;
    };
    auto array = [&](const auto& v) { bytes(v.data(), v.size() * sizeof(v[0])); };
    array(f.arcs);
    array(f.arc_start);
    array(f.spheres);
    array(f.sphere_start);
    array(f.neighbour_start);
    array(f.neighbours);
    const std::uint64_t counts[2] = {f.circles, f.buried_circles};
    const float radii[2] = {f.r_max, f.rho_max};
    bytes(counts, sizeof counts);
    bytes(radii, sizeof radii);
    return h;
}

// The median wall and CPU milliseconds of `reps` runs of body, each after an untimed prepare.
struct WallCpu {
    double wall, cpu;
};
WallCpu median_wall_cpu(int reps, const std::function<void()>& prepare,
                        const std::function<void()>& body) {
    std::vector<double> wall, cpu;
    for (int r = 0; r < reps; ++r) {
        prepare();
        const auto t0 = std::chrono::steady_clock::now();
        const std::clock_t c0 = std::clock();
        body();
        cpu.push_back(double(std::clock() - c0) / CLOCKS_PER_SEC * 1e3);
        wall.push_back(std::chrono::duration<double, std::milli>(
                           std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(wall.begin(), wall.end());
    std::sort(cpu.begin(), cpu.end());
    return {wall[wall.size() / 2], cpu[cpu.size() / 2]};
}

// The exact SES's host stages alone: the host's index of the features (each run on its own
// object, its fresh pages included, as in the CLI's run), the field over the whole grid, or the
// snap of `mesh`.
int ses_stage(const Structure& structure, SurfaceOptions options, const std::string& only,
              const Mesh& mesh, int reps) {
    options.method = SesMethod::Edt;
    const detail::GridPlan plan = detail::plan_grid(structure.atoms, options);
    const detail::SesFeatures f = detail::build_ses_features(structure.atoms, options.probe);
    std::printf("%s: %zu atoms, %zu arcs, %zu vertices, grid %ux%ux%u, %u threads\n\n",
                only.c_str(), structure.atoms.size(), f.arcs.size(), mesh.vertex_count(),
                plan.info.dims[0], plan.info.dims[1], plan.info.dims[2],
                std::thread::hardware_concurrency());
    std::printf("| host stage | median ms (%d runs) | median CPU ms | hash |\n|---|---|---|---|\n",
                reps);
    if (only == "ses-index") {
        const WallCpu t = median_wall_cpu(
            reps, [] {}, [&] {
                const detail::SesHostField ses(f, plan.ses_d_max);
                ses.list_arcs_by_bin();
            });
        std::printf("| %s | %.1f | %.1f | (none) |\n", only.c_str(), t.wall, t.cpu);
        return 0;
    }
    const detail::SesHostField ses(f, plan.ses_d_max);
    std::uint64_t hash = 0;
    Mesh copy;
    const WallCpu t = median_wall_cpu(
        reps, [&] { copy = only == "ses-snap" ? mesh : Mesh{}; },
        [&] {
            if (only == "ses-field") {
                const std::vector<float> field = ses.field(plan);
                hash = hash_floats(field);
            } else {
                const detail::SesDistanceField field(ses, plan.iso, plan.ses_d_max);
                detail::project_onto_field(copy, 0, field,
                                           detail::ses_snap_options(plan.info.spacing));
                hash = hash_floats(copy.positions) ^ (hash_floats(copy.normals) << 1);
            }
        });
    std::printf("| %s | %.1f | %.1f | %016llx |\n", only.c_str(), t.wall, t.cpu,
                static_cast<unsigned long long>(hash));
    return 0;
}

}  // namespace

int main(int argc, char** argv) try {
    if (argc < 2) {
        std::fprintf(stderr,
                     "usage: %s STRUCTURE [--spacing H] [--reps N] [--out DIR] [--mesh FILE] "
                     "[--only STAGE] [--probe P]\n",
                     argv[0]);
        return 2;
    }
    SurfaceOptions options;
    int reps = 5;
    std::string out = std::filesystem::temp_directory_path().string();
    std::string mesh_file;
    std::string only;  // --only STAGE (above): that alone
    float radius_add = 0.0f;
    for (int i = 2; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--spacing")) options.spacing = std::strtof(argv[i + 1], nullptr);
        else if (!std::strcmp(argv[i], "--reps")) reps = std::max(1, std::atoi(argv[i + 1]));
        else if (!std::strcmp(argv[i], "--out")) out = argv[i + 1];
        else if (!std::strcmp(argv[i], "--mesh")) mesh_file = argv[i + 1];
        else if (!std::strcmp(argv[i], "--only")) only = argv[i + 1];
        else if (!std::strcmp(argv[i], "--radius-add")) radius_add = std::strtof(argv[i + 1], nullptr);
        else if (!std::strcmp(argv[i], "--probe")) options.probe = std::strtof(argv[i + 1], nullptr);
        else {
            std::fprintf(stderr, "unknown option %s\n", argv[i]);
            return 2;
        }
    }
    const auto t_read = std::chrono::steady_clock::now();
    const Structure structure = read_structure(argv[1]);
    const double read_ms = std::chrono::duration<double, std::milli>(
                               std::chrono::steady_clock::now() - t_read).count();
    const double file_mb = double(std::filesystem::file_size(argv[1])) / 1e6;
    if (only == "exact-areas") {
        std::vector<double> area;
        const double ms =
            median_ms(reps, [&] { area = atom_exact_areas(structure.atoms, options.probe); });
        double total = 0.0;
        std::size_t exposed = 0;
        for (const double a : area) {
            total += a;
            exposed += a > 0.0;
        }
        std::printf("%s: %zu atoms (%zu exposed), probe %.2f, %u threads, SASA %.3f A^2\n\n",
                    argv[1], structure.atoms.size(), exposed, options.probe,
                    std::thread::hardware_concurrency(), total);
        std::printf("| host stage | median ms (%d runs) | ns per atom |\n|---|---|---|\n", reps);
        std::printf("| exact areas | %.2f | %.0f |\n", ms,
                    ms * 1e6 / double(structure.atoms.size()));
        return 0;
    }
    if (only == "ses-features" || only == "ses-features-plain") {
        const bool plain = only == "ses-features-plain";
        detail::SesFeatures f;
        const double cpu0 = cpu_ms();
        const double ms = median_ms(reps, [&] {
            f = plain ? detail::build_ses_features_plain(structure.atoms, options.probe)
                      : detail::build_ses_features(structure.atoms, options.probe);
        });
        const double cpu = (cpu_ms() - cpu0) / reps;
        std::printf("%s: %zu atoms, %u threads\n\n", argv[1], structure.atoms.size(),
                    std::thread::hardware_concurrency());
        std::printf("| host stage | median ms (%d runs) | mean CPU ms | ns per atom |\n"
                    "|---|---|---|---|\n", reps);
        std::printf("| %s | %.1f | %.0f | %.0f |\n\n", only.c_str(), ms, cpu,
                    ms * 1e6 / double(structure.atoms.size()));
        std::printf("circles %zu (buried %zu), arcs %zu, neighbours %zu, bins %zu\n", f.circles,
                    f.buried_circles, f.arcs.size(), f.neighbours.size(), f.bin_count());
        std::printf("features' hash %016llx\n", static_cast<unsigned long long>(features_hash(f)));
        return 0;
    }
    if (only == "ses-field" || only == "ses-index")
        return ses_stage(structure, options, only, Mesh{}, reps);
    if (only == "ses-snap") {
        if (mesh_file.empty()) {
            std::fprintf(stderr, "--only ses-snap needs --mesh (a surface written with --no-snap)\n");
            return 2;
        }
        return ses_stage(structure, options, only, read_mesh(mesh_file), reps);
    }
    Mesh mesh;
    std::string device = "none (--mesh)";
    if (mesh_file.empty()) {
        Engine engine;
        mesh = engine.make_surface(structure.atoms, options).mesh;
        device = engine.device().name;
    } else {
        mesh = read_mesh(mesh_file);
    }
    std::printf("%s: %zu atoms, %zu vertices, %zu triangles, %u threads, device %s\n\n", argv[1],
                structure.atoms.size(), mesh.vertex_count(), mesh.triangle_count(),
                std::thread::hardware_concurrency(), device.c_str());
    std::printf("read %s: %.1f ms, %.0f MB/s of file (one run)\n\n", argv[1], read_ms,
                file_mb / (read_ms / 1e3));
    std::printf("| host stage | median ms (%d runs) |\n|---|---|\n", reps);
    MeshStats stats;
    const auto wanted = [&](const char* stage) { return only.empty() || only == stage; };
    if (wanted("stats")) {
        std::printf("| mesh statistics, 1 thread | %.1f |\n",
                    median_ms(reps, [&] { stats = detail::total_stats(mesh, 1); }));
        std::printf("| mesh statistics | %.1f |\n",
                    median_ms(reps, [&] { stats = compute_stats(mesh); }));
    }
    if (wanted("cavities")) {
        // The copy is made outside the timed part.
        std::vector<double> ms;
        std::size_t removed = 0;
        for (int r = 0; r < reps; ++r) {
            Mesh copy = mesh;
            const auto t0 = std::chrono::steady_clock::now();
            removed = detail::remove_cavities_without_probe(copy, structure.atoms, options.probe);
            ms.push_back(std::chrono::duration<double, std::milli>(
                             std::chrono::steady_clock::now() - t0).count());
        }
        std::sort(ms.begin(), ms.end());
        std::printf("| cavities (%zu removed) | %.1f |\n", removed, ms[ms.size() / 2]);
    }
    if (wanted("fused")) {
        // The engine's path: the pieces and their statistics once, the cavities removed with
        // them, the statistics of the pieces kept.
        std::vector<double> ms;
        std::size_t removed = 0;
        for (int r = 0; r < reps; ++r) {
            Mesh copy = mesh;
            detail::trace("bench: mesh copied");
            const auto t0 = std::chrono::steady_clock::now();
            detail::MeshAnalysis analysis = detail::analyse_mesh(copy, true, "bench");
            removed = detail::remove_cavities_without_probe(copy, structure.atoms, options.probe,
                                                            &analysis);
            stats = detail::total_stats(analysis, copy);
            ms.push_back(
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                    .count());
        }
        std::sort(ms.begin(), ms.end());
        std::printf("| pieces, cavities (%zu removed) and statistics in one | %.1f |\n", removed,
                    ms[ms.size() / 2]);
    }
    if (only == "removal") {
        // As the engine has it there: no per-vertex properties yet.
        detail::clear_attributes(mesh);
        Mesh copy = mesh;
        const detail::MeshAnalysis before = detail::analyse_mesh(mesh, true, "bench");
        detail::MeshAnalysis analysis = before;
        std::vector<double> ms, cpu;
        std::size_t removed = 0;
        for (int r = 0; r < reps; ++r) {
            // Assigned into the capacity of the last run: the same pages.
            copy.positions.assign(mesh.positions.begin(), mesh.positions.end());
            copy.normals.assign(mesh.normals.begin(), mesh.normals.end());
            copy.indices.assign(mesh.indices.begin(), mesh.indices.end());
            analysis.pieces.of_vertex.assign(before.pieces.of_vertex.begin(),
                                             before.pieces.of_vertex.end());
            analysis.pieces.count = before.pieces.count;
            analysis.stats = before.stats;
            analysis.runs = before.runs;
            detail::trace("bench: mesh restored");
            const auto t0 = std::chrono::steady_clock::now();
            const double c0 = cpu_ms();
            removed = detail::remove_cavities_without_probe(copy, structure.atoms, options.probe,
                                                            &analysis);
            ms.push_back(
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                    .count());
            cpu.push_back(cpu_ms() - c0);
            detail::trace("bench: removal");
        }
        stats = detail::total_stats(analysis, copy);
        std::sort(ms.begin(), ms.end());
        std::printf("| cavities stage (%zu removed), on the analysis | %.1f |\n", removed,
                    ms[ms.size() / 2]);
        std::sort(cpu.begin(), cpu.end());
        std::printf("| the same, CPU time of all threads | %.1f |\n", cpu[cpu.size() / 2]);
        std::printf("| runs | ");
        for (double x : ms) std::printf("%.1f ", x);
        std::printf("|\n");
    }
    if (wanted("write")) {
        const std::string path = out + "/fdmsurf-bench-host.ply";
        std::printf("| write PLY | %.1f |\n", median_ms(reps, [&] { write_mesh(mesh, path); }));
        std::filesystem::remove(path);
    }
    if (wanted("vertex-atoms")) {
        std::vector<std::uint32_t> atom(mesh.vertex_count());
        const std::clock_t c0 = std::clock();
        const double ms = median_ms(reps, [&] {
            detail::host_vertex_atoms(structure.atoms, mesh.positions.data(), atom.size(),
                                      radius_add, atom.data(), 1);
        });
        // CPU time of both threads: steadier than the wall's on a shared machine.
        std::printf("| vertex atoms | %.1f (CPU %.1f ms a run) |\n", ms,
                    1e3 * double(std::clock() - c0) / CLOCKS_PER_SEC / reps);
        std::uint64_t sum = 0;
        for (std::size_t v = 0; v < atom.size(); ++v) sum = sum * 1000003u + atom[v];
        std::printf("vertex atoms' hash %016llx\n", (unsigned long long)sum);
    }
    std::printf("\narea %.3f, volume %.3f, pieces %zu, closed manifold %d\n", stats.area, stats.volume,
                stats.pieces, int(stats.is_closed_manifold()));
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "fdmsurf_bench_host: %s\n", e.what());
    return 1;
}

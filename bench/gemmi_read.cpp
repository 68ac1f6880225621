// gemmi's own read of a PDB or mmCIF file beside fdmsurf's (issue 36: gemmi's speed is the
// bound of fdmsurf's PDB and mmCIF readers, which parse through it). Alternates the two in one
// process, --reps times each, and prints their medians in ms and MB/s of the file (not gzip
// data: Debian's gemmi-dev has no gzip reader in its headers):
//
//   build/fdmsurf_bench_gemmi_read FILE... [--reps N] [--only gemmi]
//
// --only gemmi: gemmi's read alone, printed as "read FILE: MS ms" (fdmsurf_bench_host's line),
// for bench/read_speed.py's fresh process per run.
// gemmi: gemmi::read_structure_file (its own file reading; PDB's parser, or CIF's parser and
// make_structure). fdmsurf:
// read_structure(FILE) with the default options (everything the CLI's parse stage does).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <gemmi/mmread.hpp>
#include <string>
#include <vector>

#include "fdmsurf/fdmsurf.hpp"

namespace {

double ms_of(const std::function<void()>& body) {
    const auto t0 = std::chrono::steady_clock::now();
    body();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) try {
    int reps = 5;
    bool gemmi_only = false;
    std::vector<std::string> files;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--reps") && i + 1 < argc)
            reps = std::max(1, std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--only") && i + 1 < argc &&
                 !std::strcmp(argv[i + 1], "gemmi"))
            gemmi_only = true, ++i;
        else
            files.push_back(argv[i]);
    }
    if (files.empty()) {
        std::fprintf(stderr, "usage: %s FILE... [--reps N]\n", argv[0]);
        return 2;
    }
    if (gemmi_only) {
        for (const std::string& file : files) {
            std::vector<double> g;
            for (int r = 0; r < reps; ++r)
                g.push_back(ms_of([&] { gemmi::Structure st = gemmi::read_structure_file(file); }));
            std::printf("read %s: %.1f ms\n", file.c_str(), median(g));
        }
        return 0;
    }
    std::printf("| file | MB | atoms | gemmi ms | gemmi MB/s | fdmsurf ms | fdmsurf MB/s | "
                "fdmsurf / gemmi |\n|---|---|---|---|---|---|---|---|\n");
    for (const std::string& file : files) {
        std::vector<double> g, f;
        std::size_t atoms = 0;
        for (int r = 0; r < reps; ++r) {
            g.push_back(ms_of([&] { gemmi::Structure st = gemmi::read_structure_file(file); }));
            f.push_back(ms_of([&] { atoms = fdmsurf::read_structure(file).atoms.size(); }));
        }
        const auto bytes = std::filesystem::file_size(file);
        const double mb = double(bytes) / 1e6, gm = median(g), fm = median(f);
        std::printf("| %s | %.2f | %zu | %.1f | %.0f | %.1f | %.0f | %.2f |\n", file.c_str(), mb,
                    atoms, gm, mb / (gm / 1e3), fm, mb / (fm / 1e3), fm / gm);
    }
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "fdmsurf_bench_gemmi_read: %s\n", e.what());
    return 1;
}

// Test helper: the total area FreeSASA (Debian package freesasa) gives for atoms with radii,
// Lee-Richards at resolution 100, the radii passed in the occupancy column
// (--radius-from-occupancy). FDMSURF_REQUIRE_TOOLS=1 turns its absence from a skip into a
// failure.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "fdmsurf/structure.hpp"
#include "support/meshstat_tool.hpp"

namespace fdmsurf::test {

// Why freesasa cannot run here, or "" when it can.
inline std::string freesasa_unavailable() {
    if (std::system("freesasa --version >/dev/null 2>&1") != 0)
        return "freesasa is not installed (Debian package freesasa)";
    return "";
}

// FreeSASA's total area (Å²) of `atoms` with the probe radius `probe` (Å; 1e-4 for the van der
// Waals area), or a negative number when it fails. Atom i's radius goes to the occupancy
// column of a PDB file written to `folder`.
inline double freesasa_total(const Atoms& atoms, double probe, const std::string& folder) {
    const std::string pdb = folder + "/freesasa-input.pdb";
    {
        std::ofstream out(pdb);
        char line[100];
        for (std::size_t i = 0; i < atoms.size(); ++i) {
            std::snprintf(line, sizeof line,
                          "ATOM  %5zu  C   ALA %c%4zu    %8.3f%8.3f%8.3f%6.2f%6.2f           C\n",
                          i % 100000, char('A' + (i / 100000) % 26), (i / 10) % 10000,
                          atoms.xyz[3 * i], atoms.xyz[3 * i + 1], atoms.xyz[3 * i + 2],
                          atoms.radius[i], 0.0);
            out << line;
        }
        out << "END\n";
    }
    char probe_text[32];
    std::snprintf(probe_text, sizeof probe_text, "%g", probe);
    int status = 0;
    const std::string text = run_capture(
        "freesasa --radius-from-occupancy --lee-richards "
        "--resolution 100 --probe-radius " +
            std::string(probe_text) + " '" + pdb + "' 2>&1",
        status);
    std::filesystem::remove(pdb);
    const std::size_t at = text.find("Total");
    if (status != 0 || at == std::string::npos) return -1.0;
    const std::size_t colon = text.find(':', at);
    return colon == std::string::npos ? -1.0 : std::atof(text.c_str() + colon + 1);
}

}  // namespace fdmsurf::test

// Skips the test (or fails it under FDMSURF_REQUIRE_TOOLS=1) when freesasa cannot run.
#define FDMSURF_REQUIRE_FREESASA()                                                                 \
    do {                                                                                           \
        const std::string why_ = ::fdmsurf::test::freesasa_unavailable();                          \
        if (!why_.empty()) {                                                                       \
            if (::fdmsurf::test::tools_required()) FAIL() << why_ << " (FDMSURF_REQUIRE_TOOLS=1)"; \
            GTEST_SKIP() << why_;                                                                  \
        }                                                                                          \
    } while (0)

// Test helper: the total area FreeSASA (Debian package freesasa) gives for atoms with radii,
// Lee-Richards at resolution 100, the radii passed in the occupancy column
// (--radius-from-occupancy). FDMSURF_REQUIRE_TOOLS=1 turns its absence from a skip into a
// failure.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

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

// Writes `atoms` as a PDB file for FreeSASA: ATOM records with their chain, residue and atom
// names (generic ones for atoms without metadata) and the radius in the occupancy column.
// Chains must be one character long.
inline void write_freesasa_pdb(const Atoms& atoms, const std::string& pdb) {
    std::ofstream out(pdb);
    const bool meta = atoms.meta.size() == atoms.size();
    char line[128];
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        std::string name = meta ? atoms.meta[i].name : "C";
        if (name.size() < 4) name = " " + name;
        const std::string res = meta ? atoms.meta[i].residue_name.substr(0, 3) : "ALA";
        const char chain = meta && !atoms.meta[i].chain.empty() ? atoms.meta[i].chain[0]
                                                                : char('A' + (i / 100000) % 26);
        const int number = meta ? atoms.meta[i].residue_number : int((i / 10) % 10000);
        const char icode = meta ? atoms.meta[i].insertion_code : ' ';
        std::snprintf(line, sizeof line,
                      "ATOM  %5zu %-4.4s %3s %c%4d%c   %8.3f%8.3f%8.3f%6.2f%6.2f          %2s\n",
                      (i + 1) % 100000, name.c_str(), res.c_str(), chain, number % 10000, icode,
                      atoms.xyz[3 * i], atoms.xyz[3 * i + 1], atoms.xyz[3 * i + 2], atoms.radius[i],
                      0.0, "C");
        out << line;
    }
    out << "END\n";
}

inline std::string freesasa_command(double probe, const std::string& extra) {
    char probe_text[32];
    std::snprintf(probe_text, sizeof probe_text, "%g", probe);
    return "freesasa --radius-from-occupancy --lee-richards --resolution 100 --probe-radius " +
           std::string(probe_text) + " " + extra;
}

// FreeSASA's area of every atom (Å², input order; 0.01 Å² steps: its PDB output's B-factor
// column), or an empty vector when it fails.
inline std::vector<double> freesasa_atom_areas(const Atoms& atoms, double probe,
                                               const std::string& folder) {
    const std::string pdb = folder + "/freesasa-atoms.pdb";
    write_freesasa_pdb(atoms, pdb);
    int status = 0;
    const std::string text =
        run_capture(freesasa_command(probe, "--format pdb '" + pdb + "' 2>/dev/null"), status);
    std::filesystem::remove(pdb);
    std::vector<double> area;
    if (status != 0) return area;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("ATOM", 0) == 0 && line.size() >= 66)
            area.push_back(std::atof(line.substr(60, 6).c_str()));
    if (area.size() != atoms.size()) area.clear();
    return area;
}

// The radii FreeSASA's own classifier (ProtOr) gives `atoms` (from its PDB output's occupancy
// column), or an empty vector when it fails. FreeSASA 2.1.2 applies --radius-from-occupancy to
// the whole structure but not to --chain-groups, whose groups get these radii: the buried-area
// tests give fdmsurf the same.
inline std::vector<double> freesasa_default_radii(const Atoms& atoms, const std::string& folder) {
    const std::string pdb = folder + "/freesasa-radii.pdb";
    write_freesasa_pdb(atoms, pdb);
    int status = 0;
    const std::string text = run_capture(
        "freesasa --lee-richards --resolution 20 --format pdb '" + pdb + "' 2>/dev/null", status);
    std::filesystem::remove(pdb);
    std::vector<double> radius;
    if (status != 0) return radius;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("ATOM", 0) == 0 && line.size() >= 60)
            radius.push_back(std::atof(line.substr(54, 6).c_str()));
    if (radius.size() != atoms.size()) radius.clear();
    return radius;
}

// FreeSASA's totals (Å²) for the chain groups of `groups` ("A+B+AB": A alone, B alone, A and B
// together), in that order, with its own radii (ProtOr; see freesasa_default_radii), or an
// empty vector when it fails.
inline std::vector<double> freesasa_chain_groups(const Atoms& atoms, double probe,
                                                 const std::string& groups,
                                                 const std::string& folder) {
    const std::string pdb = folder + "/freesasa-groups.pdb";
    write_freesasa_pdb(atoms, pdb);
    int status = 0;
    char probe_text[32];
    std::snprintf(probe_text, sizeof probe_text, "%g", probe);
    const std::string text = run_capture(
        "freesasa --lee-richards --resolution 100 --probe-radius " + std::string(probe_text) +
            " --chain-groups=" + groups + " '" + pdb + "' 2>/dev/null",
        status);
    std::filesystem::remove(pdb);
    std::vector<double> totals;
    if (status != 0) return totals;
    // The whole structure comes first, then each group.
    for (std::size_t at = text.find("Total"); at != std::string::npos;
         at = text.find("Total", at + 5)) {
        const std::size_t colon = text.find(':', at);
        if (colon != std::string::npos) totals.push_back(std::atof(text.c_str() + colon + 1));
    }
    if (!totals.empty()) totals.erase(totals.begin());
    return totals;
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

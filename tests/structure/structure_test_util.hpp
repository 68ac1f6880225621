// Helpers for the structure-input tests: data paths, temporary files, error expectations.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <string_view>

#include "fdmsurf/error.hpp"
#include "fdmsurf/structure.hpp"
#include "support/test_data.hpp"

namespace fdmsurf::test {

inline std::string read_text_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// A file under a per-process temporary folder, removed when the object goes.
class TempFile {
public:
    TempFile(const std::string& name, std::string_view bytes) {
        dir_ = std::filesystem::temp_directory_path() /
               ("fdmsurf_structure_test_" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir_);
        path_ = (dir_ / name).string();
        std::ofstream out(path_, std::ios::binary);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    }
    ~TempFile() {
        std::error_code ec;
        std::filesystem::remove(path_, ec);
        std::filesystem::remove(dir_, ec);  // only once empty
    }
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;
    const std::string& path() const { return path_; }

private:
    std::filesystem::path dir_;
    std::string path_;
};

// Runs `f` and expects an fdmsurf::Error with `code` whose message holds every one of `parts`.
template <typename F>
void expect_error(F&& f, ErrorCode code, std::initializer_list<std::string_view> parts) {
    try {
        f();
        ADD_FAILURE() << "no error thrown; expected " << to_string(code);
    } catch (const Error& e) {
        EXPECT_EQ(to_string(e.code()), std::string(to_string(code))) << e.what();
        for (std::string_view part : parts)
            EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
                << "message: " << e.what() << "\nmissing: " << part;
    }
}

inline void expect_memory_error(std::string_view text, const std::string& name, ErrorCode code,
                                std::initializer_list<std::string_view> parts,
                                const ReadOptions& options = {}) {
    SCOPED_TRACE(name);
    expect_error([&] { read_structure_from_memory(text, name, options); }, code, parts);
}

// The _atom_site columns of a minimal mmCIF file; rows follow, one atom per line:
// group id symbol atom alt comp asym seq x y z occupancy B auth_seq model
constexpr const char* kCifAtomSiteHeader =
    "data_test\n"
    "loop_\n"
    "_atom_site.group_PDB\n_atom_site.id\n_atom_site.type_symbol\n_atom_site.label_atom_id\n"
    "_atom_site.label_alt_id\n_atom_site.label_comp_id\n_atom_site.label_asym_id\n"
    "_atom_site.label_seq_id\n_atom_site.Cartn_x\n_atom_site.Cartn_y\n_atom_site.Cartn_z\n"
    "_atom_site.occupancy\n_atom_site.B_iso_or_equiv\n_atom_site.auth_seq_id\n"
    "_atom_site.pdbx_PDB_model_num\n";

// A PDB ATOM/HETATM record in the standard columns.
inline std::string pdb_atom(const char* record, int serial, const char* name, char altloc,
                            const char* residue, char chain, int seq, double x, double y, double z,
                            const char* element) {
    char line[96];
    std::snprintf(line, sizeof line,
                  "%-6s%5d %-4s%c%3s %c%4d    %8.3f%8.3f%8.3f%6.2f%6.2f          %2s\n", record,
                  serial, name, altloc, residue, chain, seq, x, y, z, 1.0, 10.0, element);
    return line;
}

}  // namespace fdmsurf::test

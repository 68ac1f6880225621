// The fuzz targets: what each harness does with its bytes, shared by the libFuzzer programs
// (fuzz_main.cpp, one per target) and by the regression test that replays every input a fuzzer
// ever broke (tests/core/test_fuzz_regressions.cpp, inputs in tests/fuzz/regressions).
#pragma once

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "cli/compare_command.hpp"
#include "cli/msms_command.hpp"
#include "cli/options.hpp"
#include "fuzz/fuzz_common.hpp"
#include "io/mesh_io.hpp"

namespace fdmsurf::fuzz {

// One structure reader. The input is the file's text; for PDB and mmCIF the last byte also
// picks the selection rules (waters, hydrogens, ligands, the first assembly, every model), so
// that the assembly builder and the model split see the fuzzed records too.
inline void structure_target(StructureFormat format, const std::uint8_t* data, std::size_t size) {
    ReadOptions options;
    options.format = format;
    const bool with_rules = format == StructureFormat::Pdb || format == StructureFormat::Mmcif;
    bool all_models = false;
    if (with_rules && size > 0) {
        const std::uint8_t rules = data[size - 1];
        options.keep_waters = rules & 1;
        options.keep_hydrogens = rules & 2;
        options.keep_ligands = !(rules & 4);
        options.assembly = (rules & 8) ? 1 : 0;
        all_models = rules & 16;
    }
    const std::string_view text = as_text(data, size);
    expect_success_or_error([&] {
        if (all_models) {
            options.model = kAllModels;
            for (const Structure& s : read_models_from_memory(text, "fuzz", options)) {
                check_atoms(s.atoms);
            }
        } else {
            const Structure s = read_structure_from_memory(text, "fuzz", options);
            check_atoms(s.atoms);
            FDMSURF_FUZZ_CHECK(!s.atoms.empty());  // empty is Error(EmptySelection)
        }
    });
}

// Standard input: bytes of any kind, gzip data decompressed (fdmsurf's own inflate loop,
// concatenated members, truncated streams), then the format told from the content, as
// `fdmsurf -` reads them.
inline void stdin_target(const std::uint8_t* data, std::size_t size) {
    std::istringstream in{std::string(as_text(data, size))};
    expect_success_or_error([&] { check_atoms(read_structure(in, "standard input").atoms); });
}

// A mesh reader of `fdmsurf compare`: the bytes are a whole file named "fuzz" + extension
// (PLY and GLB are also told by their magic whatever the name, OFF and STL by content).
inline void mesh_target(const std::string& extension, const std::uint8_t* data, std::size_t size) {
    expect_success_or_error([&] {
        if (auto mesh = detail::parse_mesh_data(as_text(data, size), "fuzz" + extension, extension)) {
            check_mesh(*mesh);
        }
    });
}

// MSMS's .vert/.face pair: the .vert text, a NUL byte, then the .face text.
inline void msms_target(const std::uint8_t* data, std::size_t size) {
    const std::string_view text = as_text(data, size);
    const std::size_t split = text.find('\0');
    const std::string_view vert = text.substr(0, split);
    const std::string_view face =
        split == std::string_view::npos ? std::string_view() : text.substr(split + 1);
    expect_success_or_error(
        [&] { check_mesh(detail::parse_msms(vert, "fuzz.vert", face, "fuzz.face")); });
}

// The command-line parsers: the first byte picks one (fdmsurf's own options, `fdmsurf msms`'s
// MSMS options, `fdmsurf compare`'s), the rest is the argument list, one argument per
// NUL-separated field. What parses must be usable (output names formed, a spacing found).
inline void options_target(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return;
    const int parser = data[0] % 3;
    std::vector<std::string> args;
    std::string_view rest = as_text(data + 1, size - 1);
    while (!rest.empty()) {
        const std::size_t end = rest.find('\0');
        args.emplace_back(rest.substr(0, end));
        rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
    }
    expect_success_or_error([&] {
        if (parser == 0) {
            const cli::CliOptions options = cli::parse_args(args);
            if (!options.output.empty()) {
                for (const std::string& input : options.inputs) {
                    FDMSURF_FUZZ_CHECK(!cli::primary_output(options, input, 1).empty());
                }
            }
        } else if (parser == 1) {
            const cli::MsmsOptions options = cli::parse_msms_args(args);
            if (!options.help && options.spacing <= 0.0f) {
                FDMSURF_FUZZ_CHECK(cli::spacing_for_density(options.density) > 0.0f);
            }
        } else {
            (void)cli::parse_compare_args(args);
        }
    });
}

// Every target by its harness name (fuzz_NAME): false for an unknown name.
inline bool run_target(std::string_view name, const std::uint8_t* data, std::size_t size) {
    struct Structure_ {
        std::string_view name;
        StructureFormat format;
    };
    for (const Structure_& s : {Structure_{"pdb", StructureFormat::Pdb},
                                Structure_{"mmcif", StructureFormat::Mmcif},
                                Structure_{"pqr", StructureFormat::Pqr},
                                Structure_{"xyzr", StructureFormat::Xyzr},
                                Structure_{"xyzrn", StructureFormat::Xyzrn}}) {
        if (name == s.name) {
            structure_target(s.format, data, size);
            return true;
        }
    }
    for (std::string_view ext : {"ply", "obj", "off", "stl", "glb"}) {
        if (name == ext) {
            mesh_target("." + std::string(ext), data, size);
            return true;
        }
    }
    if (name == "stdin") {
        stdin_target(data, size);
    } else if (name == "msms") {
        msms_target(data, size);
    } else if (name == "options") {
        options_target(data, size);
    } else {
        return false;
    }
    return true;
}

}  // namespace fdmsurf::fuzz

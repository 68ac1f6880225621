// libFuzzer harness for one structure reader, chosen at build time (FDMSURF_FUZZ_FORMAT:
// Pdb, Mmcif, Pqr, Xyzr, Xyzrn; tests/fuzz/CMakeLists.txt builds one program per format).
// The input is the file's text; for PDB and mmCIF the last byte also picks the selection
// rules (waters, hydrogens, ligands, the first assembly, every model), so that the
// assembly builder and the model split see the fuzzed records too.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fdmsurf/structure.hpp"
#include "fuzz_common.hpp"

#ifndef FDMSURF_FUZZ_FORMAT
#error "FDMSURF_FUZZ_FORMAT names the StructureFormat to fuzz"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace fdmsurf;
    ReadOptions options;
    options.format = StructureFormat::FDMSURF_FUZZ_FORMAT;
    const bool with_rules =
        options.format == StructureFormat::Pdb || options.format == StructureFormat::Mmcif;
    bool all_models = false;
    if (with_rules && size > 0) {
        const std::uint8_t rules = data[size - 1];
        options.keep_waters = rules & 1;
        options.keep_hydrogens = rules & 2;
        options.keep_ligands = !(rules & 4);
        options.assembly = (rules & 8) ? 1 : 0;
        all_models = rules & 16;
    }
    const std::string_view text = fuzz::as_text(data, size);
    fuzz::expect_success_or_error([&] {
        if (all_models) {
            options.model = kAllModels;
            for (const Structure& s : read_models_from_memory(text, "fuzz", options)) {
                fuzz::check_atoms(s.atoms);
            }
        } else {
            const Structure s = read_structure_from_memory(text, "fuzz", options);
            fuzz::check_atoms(s.atoms);
            FDMSURF_FUZZ_CHECK(!s.atoms.empty());  // empty is Error(EmptySelection)
        }
    });
    return 0;
}

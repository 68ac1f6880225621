// libFuzzer harness for standard input: bytes of any kind, gzip data decompressed (fdmsurf's
// own inflate loop, concatenated members, truncated streams), then the format told from the
// content (PDB, mmCIF, PQR, XYZR, XYZRN), as `fdmsurf -` reads them.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "fdmsurf/structure.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace fdmsurf;
    std::istringstream in(std::string(fuzz::as_text(data, size)));
    fuzz::expect_success_or_error([&] {
        const Structure s = read_structure(in, "standard input");
        fuzz::check_atoms(s.atoms);
    });
    return 0;
}

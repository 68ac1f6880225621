// One libFuzzer program per target of fuzz_targets.hpp: FDMSURF_FUZZ_NAME ("pdb", "ply",
// "options", ...) names it (tests/fuzz/CMakeLists.txt builds fuzz_NAME for each).
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "fuzz/fuzz_targets.hpp"

#ifndef FDMSURF_FUZZ_NAME
#error "FDMSURF_FUZZ_NAME names the target"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (!fdmsurf::fuzz::run_target(FDMSURF_FUZZ_NAME, data, size)) std::abort();
    return 0;
}

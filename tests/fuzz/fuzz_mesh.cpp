// libFuzzer harness for the mesh readers of `fdmsurf compare`, one program per format
// (FDMSURF_FUZZ_EXTENSION: ".ply", ".obj", ".off", ".stl", ".glb"; tests/fuzz/CMakeLists.txt):
// the bytes are the whole file, read as a file of that name would be (PLY and GLB are also
// told by their magic whatever the name, OFF and STL by content).
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_common.hpp"
#include "mesh/mesh_io.hpp"

#ifndef FDMSURF_FUZZ_EXTENSION
#error "FDMSURF_FUZZ_EXTENSION names the file extension to fuzz"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace fdmsurf;
    const std::string extension = FDMSURF_FUZZ_EXTENSION;
    fuzz::expect_success_or_error([&] {
        if (auto mesh = detail::parse_mesh_data(fuzz::as_text(data, size), "fuzz" + extension,
                                                extension)) {
            fuzz::check_mesh(*mesh);
        }
    });
    return 0;
}

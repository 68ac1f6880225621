// What every fdmsurf fuzz harness shares: the bytes as text, the errors the readers are allowed
// to throw, and checks of what they return. A harness that returns normally has met its
// contract; libFuzzer reports anything else (a sanitizer finding, an exception other than
// fdmsurf::Error, a failed check) as a crash with the input that caused it.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "fdmsurf/error.hpp"
#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"

namespace fdmsurf::fuzz {

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
    return {reinterpret_cast<const char*>(data), size};
}

// A broken invariant: printed, then abort() so that libFuzzer keeps the input.
[[noreturn]] inline void broken(const char* what) {
    std::fprintf(stderr, "fuzz check failed: %s\n", what);
    std::abort();
}

#define FDMSURF_FUZZ_CHECK(condition) \
    do {                              \
        if (!(condition)) ::fdmsurf::fuzz::broken(#condition); \
    } while (false)

// Runs `read`; fdmsurf::Error (bad input, refused clearly) is the expected way to fail, and
// its message must say something.
template <class Read>
void expect_success_or_error(Read&& read) {
    try {
        read();
    } catch (const Error& e) {
        FDMSURF_FUZZ_CHECK(e.what() != nullptr && e.what()[0] != '\0');
    }
}

// What the structure readers promise (structure.hpp): one radius per atom, three finite
// coordinates each, positive finite radii, metadata and elements absent or one per atom.
inline void check_atoms(const Atoms& atoms) {
    FDMSURF_FUZZ_CHECK(atoms.xyz.size() == 3 * atoms.radius.size());
    FDMSURF_FUZZ_CHECK(atoms.meta.empty() || atoms.meta.size() == atoms.size());
    FDMSURF_FUZZ_CHECK(atoms.element.empty() || atoms.element.size() == atoms.size());
    for (float v : atoms.xyz) FDMSURF_FUZZ_CHECK(std::isfinite(v));
    for (float r : atoms.radius) FDMSURF_FUZZ_CHECK(std::isfinite(r) && r > 0.0f);
}

// What the mesh readers promise (mesh.hpp): whole triangles, every index in range, per-vertex
// arrays absent or one entry per vertex.
inline void check_mesh(const Mesh& mesh) {
    FDMSURF_FUZZ_CHECK(mesh.positions.size() % 3 == 0);
    const std::size_t vertices = mesh.positions.size() / 3;
    FDMSURF_FUZZ_CHECK(mesh.indices.size() % 3 == 0);
    for (std::uint32_t i : mesh.indices) FDMSURF_FUZZ_CHECK(i < vertices);
    FDMSURF_FUZZ_CHECK(mesh.normals.empty() || mesh.normals.size() == mesh.positions.size());
    FDMSURF_FUZZ_CHECK(mesh.atoms.empty() || mesh.atoms.size() == vertices);
    FDMSURF_FUZZ_CHECK(mesh.colors.empty() || mesh.colors.size() == 3 * vertices);
    for (const VertexScalars& s : mesh.scalars) FDMSURF_FUZZ_CHECK(s.values.size() == vertices);
}

}  // namespace fdmsurf::fuzz

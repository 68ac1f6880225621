// Test helper: atoms written out in a test, ball by ball.
#pragma once

#include <array>
#include <initializer_list>

#include "fdmsurf/structure.hpp"

namespace fdmsurf_test {

// Atoms from {x, y, z, r} balls (Å), no elements.
inline fdmsurf::Atoms make_atoms(std::initializer_list<std::array<float, 4>> balls) {
    fdmsurf::Atoms a;
    for (const auto& b : balls) {
        a.xyz.insert(a.xyz.end(), {b[0], b[1], b[2]});
        a.radius.push_back(b[3]);
    }
    return a;
}

}  // namespace fdmsurf_test

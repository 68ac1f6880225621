// fdmsurf public API: molecular surfaces from the Filtered Density Map method on Vulkan.
#pragma once

#include "fdmsurf/error.hpp"
#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"

namespace fdmsurf {
const char* version() noexcept;
}

// fdmsurf public API: molecular surfaces from the Filtered Density Map method on Vulkan.
#pragma once

#include "fdmsurf/areas.hpp"
#include "fdmsurf/compare.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf/mesh.hpp"
#include "fdmsurf/msms.hpp"
#include "fdmsurf/properties.hpp"
#include "fdmsurf/render.hpp"
#include "fdmsurf/simplify.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "fdmsurf/vulkan_interop.hpp"

namespace fdmsurf {
const char* version() noexcept;
}

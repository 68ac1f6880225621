// The SPIR-V of every compute stage, compiled from shaders/ at build time and embedded here.
#pragma once

#include <cstddef>
#include <cstdint>

namespace fdmsurf::detail {

struct ShaderCode {
    const std::uint32_t* words;
    std::size_t bytes;
};

enum class Shader {
    DensityTiles,
    Density,
    SesDistance,
    SpectralMask,
    McOccupancy,
    McCount,
    McScan,
    McVertices,
    McTriangles,
    VertexAtoms,
    Coulombic
};

ShaderCode shader_code(Shader shader);

}  // namespace fdmsurf::detail

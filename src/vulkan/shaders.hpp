// The SPIR-V of every shader (compute stages and the renderer's), compiled from shaders/ at
// build time and embedded here.
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
    SesBoxes,
    SesDistance,
    SpectralMask,
    McOccupancy,
    McCount,
    McScan,
    McVertices,
    McTriangles,
    VertexAtoms,
    Coulombic,
    RenderBounds,   // render_bounds.comp
    RenderVert,     // render.vert: the scene pass
    RenderFrag,     // render.frag
    CompositeVert,  // composite.vert: the compositing pass
    CompositeFrag,  // composite.frag
};

ShaderCode shader_code(Shader shader);

}  // namespace fdmsurf::detail

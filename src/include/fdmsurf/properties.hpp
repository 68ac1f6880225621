// Per-vertex properties of a surface: colour schemes and scalars for viewers and learning
// pipelines, computed from the atom each vertex belongs to (docs/properties.md).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace fdmsurf {

// Vertex colours (Mesh::colors). Palettes in docs/properties.md.
enum class ColorScheme {
    None,            // no colours
    Uniform,         // PropertyOptions::rgb everywhere
    Chain,           // one colour per chain (PyMOL-like cycle of light colours, by order of appearance)
    Element,         // CPK/Jmol element colours
    Residue,         // one colour per residue type (amino acids by class, nucleotides)
    Hydrophobicity,  // Kyte-Doolittle per residue: blue (hydrophilic) - white - orange (-4.5..4.5)
    BFactor,         // blue - white - red over the structure's B-factor range
    Coulombic,       // red - white - blue over -10..+10 kcal/(mol e), ChimeraX's `coulombic`
};

// Per-vertex scalars (Mesh::scalars), named as to_string gives.
enum class VertexProperty {
    Coulombic,          // kcal/(mol e): sum 332 q_i / (4 r_i^2), 1.4 Å out along the normal
    Hydrophobicity,     // Kyte-Doolittle value of the vertex's residue (0 where unknown)
    BFactor,            // the vertex's atom's B-factor, Å²
    MeanCurvature,      // 1/Å, positive where convex (a sphere of radius R: 1/R)
    GaussianCurvature,  // 1/Å²
    ShapeIndex,         // Koenderink's shape index in [-1, 1]: +1 convex cap, -1 concave cup
};

struct PropertyOptions {
    ColorScheme color = ColorScheme::None;
    std::array<std::uint8_t, 3> rgb{200, 200, 200};  // ColorScheme::Uniform
    std::vector<VertexProperty> scalars;              // written in this order
    // Coulombic: the potential is evaluated this far out along each vertex normal (Å).
    float coulombic_offset = 1.4f;
};

const char* to_string(ColorScheme scheme) noexcept;
const char* to_string(VertexProperty property) noexcept;

}  // namespace fdmsurf

// Embedded SPIR-V words (generated headers from cmake/FdmsurfShaders.cmake).
#include "vulkan/shaders.hpp"

#include "fdmsurf/error.hpp"
#include "fdmsurf_generated/shaders/composite_frag.spv.h"
#include "fdmsurf_generated/shaders/composite_vert.spv.h"
#include "fdmsurf_generated/shaders/coulombic.spv.h"
#include "fdmsurf_generated/shaders/density.spv.h"
#include "fdmsurf_generated/shaders/density_tiles.spv.h"
#include "fdmsurf_generated/shaders/mc_count.spv.h"
#include "fdmsurf_generated/shaders/mc_occupancy.spv.h"
#include "fdmsurf_generated/shaders/mc_scan.spv.h"
#include "fdmsurf_generated/shaders/mc_triangles.spv.h"
#include "fdmsurf_generated/shaders/mc_vertices.spv.h"
#include "fdmsurf_generated/shaders/render_bounds.spv.h"
#include "fdmsurf_generated/shaders/render_frag.spv.h"
#include "fdmsurf_generated/shaders/render_vert.spv.h"
#include "fdmsurf_generated/shaders/ses_boxes.spv.h"
#include "fdmsurf_generated/shaders/ses_distance.spv.h"
#include "fdmsurf_generated/shaders/spectral_mask.spv.h"
#include "fdmsurf_generated/shaders/vertex_atoms.spv.h"

namespace fdmsurf::detail {

ShaderCode shader_code(Shader shader) {
    switch (shader) {
        case Shader::DensityTiles:
            return {density_tiles_spv, sizeof(density_tiles_spv)};
        case Shader::Density: return {density_spv, sizeof(density_spv)};
        case Shader::SesBoxes: return {ses_boxes_spv, sizeof(ses_boxes_spv)};
        case Shader::SesDistance: return {ses_distance_spv, sizeof(ses_distance_spv)};
        case Shader::SpectralMask: return {spectral_mask_spv, sizeof(spectral_mask_spv)};
        case Shader::McOccupancy: return {mc_occupancy_spv, sizeof(mc_occupancy_spv)};
        case Shader::McCount: return {mc_count_spv, sizeof(mc_count_spv)};
        case Shader::McScan: return {mc_scan_spv, sizeof(mc_scan_spv)};
        case Shader::McVertices: return {mc_vertices_spv, sizeof(mc_vertices_spv)};
        case Shader::McTriangles: return {mc_triangles_spv, sizeof(mc_triangles_spv)};
        case Shader::VertexAtoms: return {vertex_atoms_spv, sizeof(vertex_atoms_spv)};
        case Shader::Coulombic: return {coulombic_spv, sizeof(coulombic_spv)};
        case Shader::RenderBounds: return {render_bounds_spv, sizeof(render_bounds_spv)};
        case Shader::RenderVert: return {render_vert_spv, sizeof(render_vert_spv)};
        case Shader::RenderFrag: return {render_frag_spv, sizeof(render_frag_spv)};
        case Shader::CompositeVert: return {composite_vert_spv, sizeof(composite_vert_spv)};
        case Shader::CompositeFrag: return {composite_frag_spv, sizeof(composite_frag_spv)};
    }
    throw Error(ErrorCode::Internal, "unknown shader");
}

}  // namespace fdmsurf::detail

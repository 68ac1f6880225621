// Shared by C++ and GLSL: workgroup sizes and push-constant layouts of every compute stage and
// of the renderer's shaders, so that the host computes dispatch counts from the same constants
// the shaders declare.
#ifndef FDMSURF_SHADER_INTERFACE_H
#define FDMSURF_SHADER_INTERFACE_H

#ifdef __cplusplus
#include <cstdint>
namespace fdmsurf::detail::shader {
using uint = std::uint32_t;
#define FDM_CONST inline constexpr uint
#else
#define FDM_CONST const uint
#endif

// Density: the grid is cut into boxes (tiles) of kDensityGroup* points (x a multiple of 4).
// density_tiles.comp: one invocation per tile, kDensityTileGroup per workgroup. density.comp:
// kDensityTileLanes invocations per tile (each evaluates quads of 4 points along x),
// kDensityPointGroup per workgroup. Flat workgroups: lavapipe vectorises along local x only.
FDM_CONST kDensityGroupX = 4;
FDM_CONST kDensityGroupY = 4;
FDM_CONST kDensityGroupZ = 4;
FDM_CONST kDensityTileGroup = 64;
FDM_CONST kDensityTileLanes = 8;
FDM_CONST kDensityPointGroup = 64;
// A tile's candidate count when its list did not fit (density.comp then searches per point).
FDM_CONST kDensityOverflow = 0xffffffffu;

// Exact SES distance (ses_distance.comp): 3D workgroups of 8 x 4 x 2 invocations (8 along x:
// lavapipe fills its 8-wide vectors along local x only; 28% faster on 4HHB than 4 x 4 x 4, which
// ran half-empty vectors; 8 x 8 x 1, 16 x 2 x 2, 8 x 2 x 4 were slower), each invocation up to
// kSesPointsZ points along z (push constant points_z, chosen by the host: ses_points_z), which
// share one gather per box and one read of each sphere.
FDM_CONST kSesGroupX = 8;
FDM_CONST kSesGroupY = 4;
FDM_CONST kSesGroupZ = 2;
FDM_CONST kSesPointsZ = 4;
// Spheres (one vec4) and arcs (three vec4) each workgroup copies into shared memory
// (300 x 16 + 230 x 48 = 15,840 bytes: within the 16 KiB every Vulkan device has); a box with
// more falls back to reading the bins per point. At 0.5 Å a box has about 60-100 spheres.
FDM_CONST kSesSphereCapacity = 300;
FDM_CONST kSesArcCapacity = 230;
// ses_boxes.comp: one invocation per box of ses_distance.comp (a workgroup's points), flat
// workgroups of kSesBoxGroup; each box's class: evaluated (kSesBoxBand), or wholly outside the
// balls with d <= d_min (kSesBoxOutside: the field is d_min there).
FDM_CONST kSesBoxGroup = 64;
FDM_CONST kSesBoxBand = 0;
FDM_CONST kSesBoxOutside = 1;

// Spectral mask: one invocation per complex coefficient of the half spectrum.
FDM_CONST kMaskGroupX = 64;
FDM_CONST kMaskGroupY = 4;

// Marching cubes works on segments: 32 consecutive points of an x row, whose inside/outside
// states are the bits of one word (mc_occupancy.comp). mc_count.comp: one invocation per run of
// kMcRun segments; mc_occupancy, mc_vertices and mc_triangles: one invocation per segment. All
// in flat workgroups of kMcGroup (2D dispatch of workgroups).
FDM_CONST kMcSegment = 32;
FDM_CONST kMcRun = 32;
FDM_CONST kMcGroup = 64;
// Run-sum scan: one workgroup.
FDM_CONST kScanGroup = 1024;

// Vertex properties: vertex_atoms.comp, one invocation per vertex; coulombic.comp, one workgroup
// per target cell. Flat workgroups of kVertexGroup (2D dispatch of workgroups). coulombic.comp
// copies kCoulombTile charge sites at a time into shared memory for the far field, and the near
// sites kCoulombNearCapacity at a time.
FDM_CONST kVertexGroup = 64;
FDM_CONST kCoulombTile = 256;
FDM_CONST kCoulombNearCapacity = 512;

// Filter shapes (SpectralMaskPush::shape).
FDM_CONST kFilterIdeal = 0;
FDM_CONST kFilterGaussian = 1;

struct DensityPush {
    float origin_x, origin_y, origin_z, spacing;  // grid point (0,0,0) and spacing, Å
    uint nx, ny, nz, pitch;                       // points per axis; floats per x row
    float bin_origin_x, bin_origin_y, bin_origin_z, bin_size;
    uint bin_nx, bin_ny, bin_nz, max_shell;
    float inv_sigma2;  // 1/σ²
    float pi_cut;      // power distance beyond which G < cut · T: the density is 0 there
    float r2_max;      // largest r² among atoms
    float level_t;     // T
    uint boxes_x, boxes_y;  // tiles per axis of the whole grid (x, y)
    uint tile_count;        // tiles in the `tiles` buffer (the boxes some atom reaches)
    uint groups_x;          // workgroups along x of the 2D dispatch (folded into rows)
    uint capacity;          // candidate atoms a tile may store; more: the per-point search
    uint pool_words;        // atom indices the candidates' pool holds (all tiles together)
};

struct SesDistancePush {
    float origin_x, origin_y, origin_z, spacing;  // grid point (0,0,0) and spacing, Å
    uint nx, ny, nz, pitch;                       // points per axis; floats per x row
    float bin_origin_x, bin_origin_y, bin_origin_z, bin_size;
    uint bin_nx, bin_ny, bin_nz, force_global;  // force_global != 0: tests of the fallback
    float r_max;    // largest inflated radius r + probe, Å
    float rho_max;  // largest arc circle radius, Å
    float d_max;    // the field is clamped to [d_min, d_max] (exact within)
    uint points_z;  // points per invocation along z, 1 to kSesPointsZ (ses_points_z)
    float d_min;
};

// ses_boxes.comp: the grid and sphere bins of SesDistancePush, and the boxes (workgroups of
// ses_distance.comp) per axis.
struct SesBoxesPush {
    float origin_x, origin_y, origin_z, spacing;
    uint nx, ny, nz, pitch;
    float bin_origin_x, bin_origin_y, bin_origin_z, bin_size;
    uint bin_nx, bin_ny, bin_nz, points_z;
    float r_max;
    float d_min;  // the field's lower clamp
    uint boxes_x, boxes_y, boxes_z;
    float slack;  // Å: the margin for float rounding in the box test
};

struct SpectralMaskPush {
    uint nx, ny, nz, cx;      // real grid size; complex values per x row (nx/2+1)
    float fx, fy, fz;         // frequency step per axis: 1 / (n · h), 1/Å
    float cutoff;             // f_c, 1/Å
    float scale;              // 1 / (nx·ny·nz): the inverse FFT's normalisation
    uint shape;               // kFilterIdeal or kFilterGaussian
};

struct McPush {
    float origin_x, origin_y, origin_z, spacing;  // position of buffer point (0,0,0), Å
    uint nx, ny, nz, pitch;  // points in the field buffer; floats per x row
    uint z_begin, z_end;     // points of planes [z_begin, z_end] are processed; cells start on
                             // planes [z_begin, z_end), so the buffer holds planes to z_end
    uint groups_x;           // workgroups along x of this dispatch's 2D grid of workgroups
    float iso;               // iso-level
    uint words;              // segments (32-point words) per x row: ceil(nx / 32)
    uint segments;           // words * ny * (z_end - z_begin + 1)
    float power_sigma2;      // > 0: interpolate the power distance (McParams::power_sigma2)
    float power_t;
};

struct VertexAtomsPush {
    float bin_origin_x, bin_origin_y, bin_origin_z, bin_size;  // cell (0,0,0) corner and edge, Å
    uint bin_nx, bin_ny, bin_nz;  // cells per axis; the grid holds every atom and vertex
    uint vertex_count;
    float r2_max;      // largest r² of the atoms (power distance |p - c|² - r²)
    uint groups_x;     // workgroups along x of the 2D dispatch
    uint attributes;   // uints per atom in `atom_attributes`, copied to the vertex's output
    uint position_stride;  // floats from one vertex's position to the next: 3 for the host's
                           // positions, 6 for a device mesh's interleaved vertex buffer
};

struct CoulombPush {
    float cell_origin_x, cell_origin_y, cell_origin_z, cell_size;  // cell (0,0,0) corner, edge
    uint cell_count;   // target cells (cells holding evaluation points): one workgroup each
    uint site_count;   // charge sites (x, y, z, q)
    float scale;       // 332 / 4: kcal/(mol e) with the distance-dependent dielectric 4 r
    uint groups_x;
    uint color;        // != 0: also write the red-white-blue colour of the potential
    float color_range; // the potential mapped to full red (-) or blue (+), kcal/(mol e)
    uint near_cells;   // sites within this many cells (Chebyshev) are summed exactly
    uint cell_nx, cell_ny, cell_nz;  // cells per axis (site_start has one entry per cell + 1)
};

struct ScanPush {
    uint count;  // number of uvec2 run sums
};

// Rendering (src/render/): the bounding-sphere pass, the scene's vertex shader and the
// compositing pass. render_bounds.comp: flat workgroups of kBoundsGroup, each invocation
// reducing every (groups * kBoundsGroup)-th vertex of its chunk.
FDM_CONST kBoundsGroup = 64;
// Screen-space ambient occlusion: depth samples per pixel (composite.frag).
FDM_CONST kAoSamples = 12;

struct BoundsPush {
    uint vertex_count;  // vertices in this chunk (6 floats each: position, normal)
    uint groups_x;      // workgroups along x of the 2D dispatch
    uint pass;          // 0: the box (ordered-uint min and max), 1: the largest squared
                        // distance from the box's centre
    uint pad0;
};

// The orthographic camera: view = R (p - centre) with R's rows below; clip x = view.x * scale_x,
// clip y = -view.y * scale_y (Vulkan's y points down), depth = 0.5 - view.z * depth_scale
// (0 nearest, 1 farthest over the framed sphere).
struct RenderPush {
    float row0_x, row0_y, row0_z, center_x;
    float row1_x, row1_y, row1_z, center_y;
    float row2_x, row2_y, row2_z, center_z;
    float scale_x, scale_y, depth_scale, pad0;
};

// The compositing pass: the scene's colour and depth in, the lit, shaded picture out.
struct CompositePush {
    float background_r, background_g, background_b, background_a;  // linear, premultiplied
    float depth_range;  // Å between depth 0 and depth 1
    float pixel_size;   // Å per sample of the scene (a pixel over `samples`)
    float ao_strength;  // 0: no ambient occlusion
    float ao_radius;    // Å
    float depth_cue;    // 0: none; else the far side is darkened by this fraction
    float outline;      // 0: no outline; else its width in samples
    float outline_step; // Å: a depth step larger than this between neighbours is outlined
    uint samples;       // scene samples per pixel along x and y (1 or 2): the supersampling
};

#ifdef __cplusplus
}  // namespace fdmsurf::detail::shader
#endif
#undef FDM_CONST

#endif

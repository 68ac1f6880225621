// Shared by density_tiles.comp and density.comp: the bindings, the boxes of grid points (tiles)
// and the float helpers of the density pass.
#ifndef FDMSURF_DENSITY_COMMON_GLSL
#define FDMSURF_DENSITY_COMMON_GLSL

layout(std430, binding = 0) buffer Field { float field[]; };
layout(std430, binding = 1) readonly buffer AtomsBuf { vec4 atoms[]; };  // xyz, r^2
layout(std430, binding = 2) readonly buffer BinStart { uint bin_start[]; };
layout(std430, binding = 3) readonly buffer FirstShell { uint first_shell[]; };
layout(std430, binding = 4) readonly buffer Tiles { uint tiles[]; };  // box index per tile
// The candidate lists: for tile t, words 2t and 2t + 1 hold its candidate count (kDensityOverflow
// when it has more than pc.capacity or the pool ran out) and the first word of its list; word
// 2 * tile_count is the pool's top (0 before the tiles pass), and the pool of pc.pool_words atom
// indices follows it.
layout(std430, binding = 5) buffer Candidates { uint candidates[]; };

layout(push_constant) uniform Push { DensityPush pc; };

uint pool_top_word() { return 2u * pc.tile_count; }
uint pool_first_word() { return 2u * pc.tile_count + 1u; }

// The box of tile `tile`: its first grid point and its corners (grid points), Å.
struct Box {
    uvec3 first;
    vec3 lo, hi;
};

Box tile_box(uint tile) {
    uint id = tiles[tile];
    uvec3 b = uvec3(id % pc.boxes_x, (id / pc.boxes_x) % pc.boxes_y, id / (pc.boxes_x * pc.boxes_y));
    uvec3 size = uvec3(kDensityGroupX, kDensityGroupY, kDensityGroupZ);
    Box box;
    box.first = b * size;
    uvec3 last = min(box.first + size, uvec3(pc.nx, pc.ny, pc.nz)) - 1u;
    vec3 origin = vec3(pc.origin_x, pc.origin_y, pc.origin_z);
    box.lo = origin + pc.spacing * vec3(box.first);
    box.hi = origin + pc.spacing * vec3(last);
    return box;
}

#endif

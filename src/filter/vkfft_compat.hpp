// Includes VkFFT 1.2.26 against glslang 12 (Debian 12), whose C structs grew new fields.
//
// VkFFT fills glslang_resource_t positionally in glslang 11's field order; glslang 12 inserted
// nine max_*_ext fields, so the brace initialiser no longer compiles (../shared/reference/
// NOTES.md). We redirect VkFFT's uses of the struct and of the three functions that take it to
// glslang-11-layout twins with converters, without patching the system header.
#pragma once

#include <glslang/Include/glslang_c_interface.h>

#include <cstddef>
#include <cstring>

namespace fdmsurf::detail::vkfft_compat {

// glslang 11's TBuiltInResource counterpart: glslang 12's without the max_*_ext block.
struct Resource11 {
    int values_before_ext[92];  // max_lights .. max_mesh_view_count_nv: 92 ints in both
    int max_dual_source_draw_buffers_ext;
    glslang_limits_t limits;
};
static_assert(offsetof(glslang_resource_t, max_mesh_output_vertices_ext) ==
                  sizeof(int) * 92,
              "glslang 12 layout: 92 ints precede the max_*_ext fields");

struct Input11 {
    glslang_source_t language;
    glslang_stage_t stage;
    glslang_client_t client;
    glslang_target_client_version_t client_version;
    glslang_target_language_t target_language;
    glslang_target_language_version_t target_language_version;
    const char* code;
    int default_version;
    glslang_profile_t default_profile;
    int force_default_version_and_profile;
    int forward_compatible;
    glslang_messages_t messages;
    const Resource11* resource;
};

// glslang keeps pointers into the input (the address of its code pointer) until the shader is
// parsed, so the converted input must outlive each call. VkFFT compiles one shader at a time
// per thread: create, preprocess, parse, then link.
struct Converted {
    glslang_resource_t resource;
    glslang_input_t input;
};

inline Converted& converted_storage() {
    thread_local Converted storage;
    return storage;
}

inline const glslang_input_t* convert(const Input11* in) {
    Converted& c = converted_storage();
    std::memset(&c.resource, 0, sizeof(c.resource));
    std::memcpy(&c.resource, in->resource->values_before_ext, sizeof(int) * 92);
    c.resource.max_mesh_output_vertices_ext = 256;
    c.resource.max_mesh_output_primitives_ext = 256;
    c.resource.max_mesh_work_group_size_x_ext = 128;
    c.resource.max_mesh_work_group_size_y_ext = 128;
    c.resource.max_mesh_work_group_size_z_ext = 128;
    c.resource.max_task_work_group_size_x_ext = 128;
    c.resource.max_task_work_group_size_y_ext = 128;
    c.resource.max_task_work_group_size_z_ext = 128;
    c.resource.max_mesh_view_count_ext = 4;
    c.resource.max_dual_source_draw_buffers_ext = in->resource->max_dual_source_draw_buffers_ext;
    c.resource.limits = in->resource->limits;
    c.input.language = in->language;
    c.input.stage = in->stage;
    c.input.client = in->client;
    c.input.client_version = in->client_version;
    c.input.target_language = in->target_language;
    c.input.target_language_version = in->target_language_version;
    c.input.code = in->code;
    c.input.default_version = in->default_version;
    c.input.default_profile = in->default_profile;
    c.input.force_default_version_and_profile = in->force_default_version_and_profile;
    c.input.forward_compatible = in->forward_compatible;
    c.input.messages = in->messages;
    c.input.resource = &c.resource;
    return &c.input;
}

inline glslang_shader_t* shader_create(const Input11* in) { return glslang_shader_create(convert(in)); }
inline int shader_preprocess(glslang_shader_t* s, const Input11* in) {
    return glslang_shader_preprocess(s, convert(in));
}
inline int shader_parse(glslang_shader_t* s, const Input11* in) {
    return glslang_shader_parse(s, convert(in));
}

}  // namespace fdmsurf::detail::vkfft_compat

#define glslang_resource_t fdmsurf::detail::vkfft_compat::Resource11
#define glslang_input_t fdmsurf::detail::vkfft_compat::Input11
#define glslang_shader_create fdmsurf::detail::vkfft_compat::shader_create
#define glslang_shader_preprocess fdmsurf::detail::vkfft_compat::shader_preprocess
#define glslang_shader_parse fdmsurf::detail::vkfft_compat::shader_parse

#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wunused-variable"
#pragma GCC diagnostic ignored "-Wunused-but-set-variable"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wformat-truncation"
#pragma GCC diagnostic ignored "-Wunused-function"
#endif
#include <vkFFT.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#undef glslang_resource_t
#undef glslang_input_t
#undef glslang_shader_create
#undef glslang_shader_preprocess
#undef glslang_shader_parse

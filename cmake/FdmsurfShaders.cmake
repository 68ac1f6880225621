# fdmsurf_embed_shaders(TARGET SOURCES ... INCLUDE_DIRS ... DEPENDS ... OUTPUT_DIR dir)
# Compiles each shader to SPIR-V with glslangValidator and writes a C header holding the words,
# so that no shader file is needed at run time: compute shaders (NAME.comp) as
# `static const uint32_t NAME_spv[]` in NAME.spv.h, the renderer's (NAME.vert, NAME.frag) as
# NAME_vert_spv / NAME_frag_spv in NAME_vert.spv.h / NAME_frag.spv.h.
function(fdmsurf_embed_shaders target)
    cmake_parse_arguments(ARG "" "OUTPUT_DIR" "SOURCES;INCLUDE_DIRS;DEPENDS" ${ARGN})
    file(MAKE_DIRECTORY ${ARG_OUTPUT_DIR})
    set(include_flags)
    foreach(dir ${ARG_INCLUDE_DIRS})
        list(APPEND include_flags -I${dir})
    endforeach()
    set(outputs)
    foreach(src ${ARG_SOURCES})
        get_filename_component(name ${src} NAME_WE)
        get_filename_component(ext ${src} LAST_EXT)
        string(SUBSTRING ${ext} 1 -1 ext)
        if(NOT ext STREQUAL "comp")
            set(name ${name}_${ext})
        endif()
        set(out ${ARG_OUTPUT_DIR}/${name}.spv.h)
        add_custom_command(
            OUTPUT ${out}
            COMMAND ${GLSLANG_VALIDATOR} -V --target-env vulkan1.1 ${include_flags}
                    --vn ${name}_spv -o ${out} ${src}
            DEPENDS ${src} ${ARG_DEPENDS}
            COMMENT "Compiling shader ${src}"
            VERBATIM)
        list(APPEND outputs ${out})
    endforeach()
    add_custom_target(${target} DEPENDS ${outputs})
endfunction()

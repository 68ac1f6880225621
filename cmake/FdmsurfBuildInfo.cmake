# What `fdmsurf --version` says about the build: the git commit of the source tree and whether it
# is a release, one made from the tag v${PROJECT_VERSION} with no local changes
# (src/cli/version.hpp). Included by CMakeLists.txt for fdmsurf_add_build_info(); run by the
# build itself in script mode (cmake -P), at every build, so that a commit made after
# configuring is the one the program names. The generated source is written only when its
# text changes, so an unchanged tree recompiles nothing.
#
# A tree without git (an unpacked source archive) reads fdmsurf-source-info.txt at its root
# (lines commit=SHA and release=yes|no, written by python/build_backend's build_sdist); with
# neither, the commit is unknown and the build is not a release.

if(CMAKE_SCRIPT_MODE_FILE)
    # -DSOURCE_DIR= -DVERSION= -DTEMPLATE= -DOUTPUT=
    cmake_minimum_required(VERSION 3.22)  # the policies of the project (IN_LIST)
    set(commit "")
    set(changed FALSE)
    set(release FALSE)
    find_program(GIT_EXECUTABLE git)
    if(GIT_EXECUTABLE AND EXISTS "${SOURCE_DIR}/.git")
        # safe.directory: a tree owned by another user (root building a user's clone) is read,
        # not refused; --no-optional-locks: status does not take the index lock from a commit
        # running beside the build.
        set(git ${GIT_EXECUTABLE} -c safe.directory=* --no-optional-locks -C ${SOURCE_DIR})
        execute_process(COMMAND ${git} rev-parse --short=12 HEAD RESULT_VARIABLE status
            OUTPUT_VARIABLE commit OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
        if(status EQUAL 0)
            execute_process(COMMAND ${git} status --porcelain --untracked-files=no
                OUTPUT_VARIABLE changes ERROR_QUIET)
            if(NOT changes STREQUAL "")
                set(changed TRUE)
            endif()
            execute_process(COMMAND ${git} tag --points-at HEAD
                OUTPUT_VARIABLE tags ERROR_QUIET)
            string(REPLACE "\n" ";" tags "${tags}")
            if("v${VERSION}" IN_LIST tags AND NOT changed)
                set(release TRUE)
            endif()
        else()
            set(commit "")
        endif()
    elseif(EXISTS "${SOURCE_DIR}/fdmsurf-source-info.txt")
        file(STRINGS "${SOURCE_DIR}/fdmsurf-source-info.txt" lines)
        foreach(line IN LISTS lines)
            if(line MATCHES "^commit=([0-9a-f]+)$")
                string(SUBSTRING "${CMAKE_MATCH_1}" 0 12 commit)
            elseif(line MATCHES "^changed=yes$")
                set(changed TRUE)
            elseif(line MATCHES "^release=yes$")
                set(release TRUE)
            endif()
        endforeach()
    endif()
    if(commit STREQUAL "")
        set(FDMSURF_BUILD_LINE "git commit unknown (not built from a git checkout): not a release")
    elseif(release)
        set(FDMSURF_BUILD_LINE "git commit ${commit}, tag v${VERSION}: a release")
    elseif(changed)
        set(FDMSURF_BUILD_LINE
            "git commit ${commit} with local changes: a development build, not a release")
    else()
        set(FDMSURF_BUILD_LINE
            "git commit ${commit}: a development build, not a release (no tag v${VERSION} on it)")
    endif()
    configure_file(${TEMPLATE} ${OUTPUT} @ONLY)  # rewrites OUTPUT only when its text changes
    return()
endif()

# Compiles the build information into TARGET (the fdmsurf program).
function(fdmsurf_add_build_info target)
    set(output ${CMAKE_CURRENT_BINARY_DIR}/generated/build_info.cpp)
    add_custom_target(fdmsurf_build_info
        COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${PROJECT_SOURCE_DIR} -DVERSION=${PROJECT_VERSION}
                -DTEMPLATE=${PROJECT_SOURCE_DIR}/src/cli/version.cpp.in -DOUTPUT=${output}
                -P ${PROJECT_SOURCE_DIR}/cmake/FdmsurfBuildInfo.cmake
        BYPRODUCTS ${output}
        COMMENT "Reading the git commit for --version"
        VERBATIM)
    target_sources(${target} PRIVATE ${output})
    add_dependencies(${target} fdmsurf_build_info)
endfunction()

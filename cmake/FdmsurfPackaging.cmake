# The installs users expect (docs/install.md): the man page fdmsurf(1), made from the program's
# --help by help2man at build time; bash completion; and the Debian package, made by CPack's DEB
# generator (`cpack -G DEB` in a build configured with -DCMAKE_INSTALL_PREFIX=/usr;
# scripts/package-test.sh builds, installs, uses and purges it).

if(FDMSURF_BUILD_CLI)
    # The man page: generated, so it cannot drift from --help; on by default when help2man (the
    # Debian package help2man) is there, except in the sanitizer and fuzzing builds (nobody
    # installs those; their program would run under ASan at build time).
    find_program(HELP2MAN_EXECUTABLE help2man)
    find_program(GZIP_EXECUTABLE gzip)
    if(HELP2MAN_EXECUTABLE AND GZIP_EXECUTABLE AND NOT FDMSURF_SANITIZE AND NOT FDMSURF_FUZZ)
        set(FDMSURF_MAN_DEFAULT ON)
    else()
        set(FDMSURF_MAN_DEFAULT OFF)
    endif()
    option(FDMSURF_MAN "Build the man page fdmsurf(1) with help2man" ${FDMSURF_MAN_DEFAULT})
    if(FDMSURF_MAN)
        if(NOT HELP2MAN_EXECUTABLE OR NOT GZIP_EXECUTABLE)
            message(FATAL_ERROR "FDMSURF_MAN needs help2man and gzip "
                "(Debian: apt-get install help2man gzip)")
        endif()
        set(man_dir ${CMAKE_CURRENT_BINARY_DIR}/man)
        file(MAKE_DIRECTORY ${man_dir})
        add_custom_command(
            OUTPUT ${man_dir}/fdmsurf.1 ${man_dir}/fdmsurf.1.gz
            COMMAND ${CMAKE_COMMAND} -DFDMSURF=$<TARGET_FILE:fdmsurf_cli>
                    -DHELP2MAN=${HELP2MAN_EXECUTABLE} -DGZIP=${GZIP_EXECUTABLE}
                    -DINCLUDE=${PROJECT_SOURCE_DIR}/packaging/fdmsurf.h2m
                    -DVERSION=${PROJECT_VERSION} -DOUTPUT_DIR=${man_dir}
                    -P ${PROJECT_SOURCE_DIR}/cmake/FdmsurfManPage.cmake
            DEPENDS fdmsurf_cli ${PROJECT_SOURCE_DIR}/packaging/fdmsurf.h2m
                    ${PROJECT_SOURCE_DIR}/cmake/FdmsurfManPage.cmake
            COMMENT "Making the man page fdmsurf.1 from fdmsurf --help (help2man)"
            VERBATIM)
        add_custom_target(fdmsurf_man ALL DEPENDS ${man_dir}/fdmsurf.1.gz)
        # `man msms` too: the page has msms's options (COMMANDS) and an example.
        file(CREATE_LINK fdmsurf.1.gz ${man_dir}/msms.1.gz SYMBOLIC)
        install(FILES ${man_dir}/fdmsurf.1.gz ${man_dir}/msms.1.gz
            DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT cli)
    endif()

    # bash completion, for fdmsurf and for msms (a link, so that bash-completion's loader finds
    # the file by either command's name).
    set(FDMSURF_COMPLETIONS_DIR ${CMAKE_INSTALL_DATADIR}/bash-completion/completions CACHE STRING
        "Where bash completion is installed (relative to the prefix)")
    set(completion_dir ${CMAKE_CURRENT_BINARY_DIR}/completions)
    file(MAKE_DIRECTORY ${completion_dir})
    file(CREATE_LINK fdmsurf ${completion_dir}/msms SYMBOLIC)
    install(FILES ${PROJECT_SOURCE_DIR}/packaging/fdmsurf.bash DESTINATION
        ${FDMSURF_COMPLETIONS_DIR} RENAME fdmsurf COMPONENT cli)
    install(FILES ${completion_dir}/msms DESTINATION ${FDMSURF_COMPLETIONS_DIR} COMPONENT cli)
endif()

# The Debian package: the program and msms, the library, headers and CMake package files, the
# Python module for Debian's python3 (python/CMakeLists.txt puts it in lib/python3/dist-packages
# when the prefix is /usr), the man page and bash completion: every component in one package.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME fdmsurf)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "molecular surface meshes (SES, van der Waals, SAS) on Vulkan compute")
set(CPACK_DEBIAN_PACKAGE_DESCRIPTION "${CPACK_PACKAGE_DESCRIPTION_SUMMARY}
 fdmsurf turns a macromolecular structure (PDB, mmCIF, PQR, XYZR) into a closed,
 manifold triangle mesh of its solvent-excluded, van der Waals or solvent-accessible
 surface, with the Filtered Density Map method or the exact SES, on any Vulkan device
 (lavapipe, Mesa's CPU driver, where there is no GPU). It writes PLY, OBJ, GLB, STL, OFF
 and pictures, per-atom and per-residue areas, and MSMS's files through its msms command.
 .
 This package holds the fdmsurf and msms programs, the C++ library with its headers and
 CMake package (find_package(fdmsurf)), and the Python module fdmsurf for python3.")
set(FDMSURF_DEB_MAINTAINER "fdmsurf developers <fdmsurf@invalid>" CACHE STRING
    "The Maintainer field of the Debian package")
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${FDMSURF_DEB_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # fdmsurf_VERSION_ARCH.deb
# Depends: the shared libraries the program and the module link, the Vulkan loader libvulkan1
# among them, as dpkg-shlibdeps finds them with their versions (libc6, libstdc++6, libpng16-16,
# zlib1g, libtinygltf2d, ...).
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# Recommends: a Vulkan driver (lavapipe and the AMD and Intel GPU drivers; an NVIDIA GPU's is
# NVIDIA's), and what the Python module needs: the python3 it was built for, numpy.
set(recommends "mesa-vulkan-drivers")
if(FDMSURF_PYTHON)
    math(EXPR next_minor "${Python3_VERSION_MINOR} + 1")
    string(APPEND recommends ", python3 (>= ${Python3_VERSION_MAJOR}.${Python3_VERSION_MINOR}~)"
        ", python3 (<< ${Python3_VERSION_MAJOR}.${next_minor}), python3-numpy")
endif()
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "${recommends}")
# Suggests: fdmsurf.batch's Dask, bash-completion, and the development packages that
# find_package(fdmsurf) needs (cmake/fdmsurfConfig.cmake.in finds these dependencies).
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "python3-distributed, bash-completion, cmake, g++, \
libvulkan-dev, glslang-dev, spirv-tools, libtinygltf-dev, libmeshoptimizer-dev, libpng-dev, \
zlib1g-dev")
# prerm removes the bytecode python3 leaves beside the module, so that a purge leaves nothing.
set(FDMSURF_DEB_PYTHON_PACKAGE "")
if(FDMSURF_PYTHON)
    set(FDMSURF_DEB_PYTHON_PACKAGE /usr/${FDMSURF_PYTHON_INSTALL_DIR}/fdmsurf)
endif()
configure_file(${PROJECT_SOURCE_DIR}/packaging/deb/prerm.in ${CMAKE_CURRENT_BINARY_DIR}/deb/prerm
    @ONLY FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE
    WORLD_READ WORLD_EXECUTE)
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA ${CMAKE_CURRENT_BINARY_DIR}/deb/prerm)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION TRUE)
set(CPACK_STRIP_FILES TRUE)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_OUTPUT_FILE_PREFIX ${CMAKE_CURRENT_BINARY_DIR}/packages)
include(CPack)

# The tests of these installs that need no install (tests/packaging/): the completion and the man
# page against the program, the backend's metadata and messages, the module's import error.
# scripts/pip-test.sh and scripts/package-test.sh install for real.
if(FDMSURF_BUILD_TESTS AND FDMSURF_BUILD_CLI AND Python3_EXECUTABLE)
    set(tests completion backend import_error)
    if(FDMSURF_MAN)
        list(APPEND tests man_page)
    endif()
    foreach(test ${tests})
        add_test(NAME packaging.${test}
            COMMAND ${Python3_EXECUTABLE} -m pytest -q -p no:cacheprovider
                ${PROJECT_SOURCE_DIR}/tests/packaging/test_${test}.py
            WORKING_DIRECTORY ${PROJECT_BINARY_DIR})
        set_tests_properties(packaging.${test} PROPERTIES TIMEOUT 300 ENVIRONMENT
            "FDMSURF_CLI=$<TARGET_FILE:fdmsurf_cli>;FDMSURF_VERSION=${PROJECT_VERSION};\
FDMSURF_MAN_PAGE=${PROJECT_BINARY_DIR}/man/fdmsurf.1;PYTHONDONTWRITEBYTECODE=1")
    endforeach()
endif()

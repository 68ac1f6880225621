# The installs users expect (docs/install.md): the man page fdmsurf(1), made from the program's
# --help by help2man at build time, and bash completion.

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
        install(FILES ${man_dir}/fdmsurf.1.gz DESTINATION ${CMAKE_INSTALL_MANDIR}/man1
            COMPONENT cli)
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

# The tests of these installs that need no install (tests/packaging/): the completion and the man
# page against the program, the backend's metadata and messages, the module's import error.
# scripts/pip-test.sh installs for real.
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

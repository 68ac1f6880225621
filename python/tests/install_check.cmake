# ctest python.install: `cmake --install BUILD --component python` into a scratch prefix, then
# `import fdmsurf` from there with the interpreter the module was built for.
file(REMOVE_RECURSE ${PREFIX})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --component python
                        --prefix ${PREFIX}
                RESULT_VARIABLE status OUTPUT_VARIABLE output ERROR_VARIABLE output)
if(NOT status EQUAL 0)
    message(FATAL_ERROR "cmake --install --component python failed:\n${output}")
endif()
set(site ${PREFIX}/${INSTALL_DIR})
execute_process(
    COMMAND ${CMAKE_COMMAND} -E env PYTHONPATH=${site} ${PYTHON} -c
            "import fdmsurf, fdmsurf.batch, os; assert os.path.dirname(fdmsurf.__file__) == os.path.join('${site}', 'fdmsurf'), fdmsurf.__file__; print(fdmsurf.__version__)"
    WORKING_DIRECTORY ${PREFIX}  # not the build tree's python/, which holds a package too
    RESULT_VARIABLE status OUTPUT_VARIABLE output ERROR_VARIABLE output)
if(NOT status EQUAL 0)
    message(FATAL_ERROR "the installed package does not import:\n${output}")
endif()
file(GLOB installed RELATIVE ${site}/fdmsurf ${site}/fdmsurf/*)
message(STATUS "installed and imported: ${installed}")
file(REMOVE_RECURSE ${PREFIX})

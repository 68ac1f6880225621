# Makes the man page fdmsurf(1) from the program's own help, run at build time (cmake -P) by
# cmake/FdmsurfPackaging.cmake: help2man turns `fdmsurf --help` into the NAME, SYNOPSIS,
# DESCRIPTION and option sections (every option, the exit codes); the help of each subcommand
# (compare, msms, prepare) becomes a COMMANDS section; packaging/fdmsurf.h2m adds EXAMPLES,
# ENVIRONMENT, FILES and SEE ALSO (tests/packaging/check_man_page.py checks its options against
# --help). Writes OUTPUT_DIR/fdmsurf.1 and its gzipped copy fdmsurf.1.gz (what is installed).
#
# -DFDMSURF= -DHELP2MAN= -DGZIP= -DINCLUDE= -DVERSION= -DOUTPUT_DIR=

set(env ${CMAKE_COMMAND} -E env FDMSURF_HUGE_PAGES=0)  # no restart: plain help text
set(commands "[COMMANDS]\n")
foreach(command compare msms prepare)
    execute_process(COMMAND ${env} ${FDMSURF} ${command} --help
        RESULT_VARIABLE status OUTPUT_VARIABLE text ERROR_VARIABLE error)
    if(NOT status EQUAL 0)
        message(FATAL_ERROR "fdmsurf ${command} --help failed (${status}): ${error}")
    endif()
    # As preformatted roff: backslashes and minus signs escaped, no line taken as a request.
    string(REPLACE "\\" "\\e" text "${text}")
    string(REPLACE "-" "\\-" text "${text}")
    string(REGEX REPLACE "(^|\n)([.'])" "\\1\\\\&\\2" text "${text}")
    string(APPEND commands ".SS \"fdmsurf ${command}\"\n.nf\n${text}.fi\n")
endforeach()
file(WRITE ${OUTPUT_DIR}/commands.h2m "${commands}")

# help2man reads the usage lines after the first as the SYNOPSIS's only when they start with
# "or:": a program of that name in front of fdmsurf turns the help's "       fdmsurf ..." into
# "   or: fdmsurf ...", and changes nothing else.
file(MAKE_DIRECTORY ${OUTPUT_DIR}/bin)
file(WRITE ${OUTPUT_DIR}/bin/fdmsurf "#!/bin/sh\n\"${FDMSURF}\" \"$@\" | sed 's/^       fdmsurf /   or: fdmsurf /'\n")
file(CHMOD ${OUTPUT_DIR}/bin/fdmsurf PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE
    GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
# --locale: the help's Å, σ and ³ as they are (UTF-8), not as '?'.
execute_process(
    COMMAND ${env} ${HELP2MAN} --no-info --locale=C.UTF-8 --section 1 --version-string ${VERSION}
            --include ${INCLUDE} --include ${OUTPUT_DIR}/commands.h2m
            --output ${OUTPUT_DIR}/fdmsurf.1 ${OUTPUT_DIR}/bin/fdmsurf
    RESULT_VARIABLE status ERROR_VARIABLE error)
if(NOT status EQUAL 0)
    message(FATAL_ERROR "help2man failed (${status}): ${error}")
endif()
# -n: no name or time stamp in the gzip header, so that the same page gives the same bytes.
execute_process(COMMAND ${GZIP} -9 -n -c ${OUTPUT_DIR}/fdmsurf.1
    OUTPUT_FILE ${OUTPUT_DIR}/fdmsurf.1.gz RESULT_VARIABLE status)
if(NOT status EQUAL 0)
    message(FATAL_ERROR "gzip of the man page failed (${status})")
endif()

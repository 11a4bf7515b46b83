# Writes the man page vsculpt.1 from the built executable's --help (run at build time by
# packaging/Packaging.cmake, so the page never drifts from the options):
#   cmake -DVSCULPT=<exe> -DHELP2MAN=<help2man or empty> -DEXTRA=vsculpt.h2m -DOUT=vsculpt.1
#         -P make-man.cmake
# The main --help becomes NAME, SYNOPSIS, DESCRIPTION and OPTIONS (help2man); every
# subcommand's --help is added as COMMANDS; EXTRA adds ENVIRONMENT, FILES, EXIT STATUS,
# EXAMPLES and SEE ALSO. Without help2man a plainer page is written from the same text.
cmake_minimum_required(VERSION 3.25)
foreach(var VSCULPT EXTRA OUT)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "make-man.cmake: -D${var}=... is required")
  endif()
endforeach()

# Runs vsculpt with ARGN under the name "vsculpt" (so usage lines do not show the build path)
# and a fixed environment; the text lands in the variable named by `out`.
function(vsculpt_text out)
  get_filename_component(dir "${VSCULPT}" DIRECTORY)
  get_filename_component(name "${VSCULPT}" NAME)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env LC_ALL=C COLUMNS=100 "PATH=${dir}:$ENV{PATH}"
                          ${name} ${ARGN}
                  OUTPUT_VARIABLE text ERROR_VARIABLE err RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "make-man.cmake: vsculpt ${ARGN} failed (${rc}): ${err}")
  endif()
  set(${out} "${text}" PARENT_SCOPE)
endfunction()

# Plain text -> roff lines shown as they are (.nf/.fi blocks).
function(roff_escape out text)
  string(REPLACE "\\" "\\e" text "${text}")
  string(REPLACE "-" "\\-" text "${text}")
  string(REGEX REPLACE "(^|\n)([.'])" "\\1\\\\&\\2" text "${text}")
  set(${out} "${text}" PARENT_SCOPE)
endfunction()

vsculpt_text(help --help)
vsculpt_text(version --version)
string(STRIP "${version}" version)

# The subcommands, from the "Subcommands:" list of the main help.
set(commands "")
string(REGEX REPLACE ".*\nSubcommands:\n" "" list "${help}")
string(REPLACE "\n" ";" list "${list}")
foreach(line IN LISTS list)
  if(line MATCHES "^  ([a-z][a-z0-9-]*) ")
    list(APPEND commands "${CMAKE_MATCH_1}")
  endif()
endforeach()
if(NOT commands)
  message(FATAL_ERROR "make-man.cmake: no subcommands found in vsculpt --help")
endif()

set(section "[COMMANDS]\n")
foreach(cmd IN LISTS commands)
  vsculpt_text(sub ${cmd} --help)
  roff_escape(sub "${sub}")
  string(APPEND section ".SS \"vsculpt ${cmd}\"\n.nf\n${sub}.fi\n")
endforeach()
file(READ "${EXTRA}" extra)
get_filename_component(outDir "${OUT}" DIRECTORY)
set(include "${outDir}/vsculpt-man-include.h2m")
file(WRITE "${include}" "${section}\n${extra}")

get_filename_component(exeDir "${VSCULPT}" DIRECTORY)
get_filename_component(exeName "${VSCULPT}" NAME)
if(HELP2MAN)
  execute_process(
    COMMAND ${CMAKE_COMMAND} -E env LC_ALL=C COLUMNS=100 "PATH=${exeDir}:$ENV{PATH}"
            ${HELP2MAN} --no-info --section=1 "--name=immersive virtual-sculpting modeler"
            "--include=${include}" "--output=${OUT}" ${exeName}
    RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "make-man.cmake: help2man failed (${rc}): ${err}")
  endif()
  return()
endif()

# Without help2man: the same sections, the help text shown as it is.
roff_escape(body "${help}")
file(READ "${include}" sections)
# help2man's "[NAME]" headers become .SH lines; everything else in them is roff already.
string(REGEX REPLACE "(^|\n)\\[([A-Z ]+)\\]\n" "\\1.SH \"\\2\"\n" sections "${sections}")
file(WRITE "${OUT}"
  ".TH VSCULPT \"1\" \"\" \"${version}\" \"User Commands\"\n"
  ".SH NAME\nvsculpt \\- immersive virtual\\-sculpting modeler\n"
  ".SH SYNOPSIS\n.B vsculpt\n[\\fIOPTIONS\\fR] [\\fISUBCOMMAND\\fR]\n"
  ".SH DESCRIPTION\n.nf\n${body}.fi\n"
  "${sections}")

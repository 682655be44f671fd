# cmake -P script: docs/cli.md from the program's own help, so that the command reference cannot
# drift from the flags. Runs `LEANFADE --help` and `LEANFADE <subcommand> --help` for every
# subcommand that --help lists, and writes OUTPUT (Markdown: one section per subcommand, its help
# verbatim). Used by the build (target cli_doc) and checked by the test docs.CliReferenceIsCurrent.
foreach(var LEANFADE OUTPUT)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "GenerateCliDoc.cmake needs -D${var}=...")
  endif()
endforeach()

function(help_of out)
  execute_process(COMMAND ${LEANFADE} ${ARGN} --help RESULT_VARIABLE rc OUTPUT_VARIABLE text
                  ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "leanfade ${ARGN} --help failed (${rc}): ${err}")
  endif()
  string(REGEX REPLACE "\n+$" "" text "${text}")
  set(${out} "${text}" PARENT_SCOPE)
endfunction()

help_of(top)
# The subcommands: the lines of the "Subcommands:" section, two-space indented names.
string(REGEX MATCH "Subcommands:\n.*" section "${top}")
string(REPLACE "\n" ";" lines "${section}")
set(subcommands "")
foreach(line IN LISTS lines)
  if(line MATCHES "^  ([a-z][a-z0-9-]*)  ")
    list(APPEND subcommands ${CMAKE_MATCH_1})
  endif()
endforeach()
if(NOT subcommands)
  message(FATAL_ERROR "leanfade --help lists no subcommand")
endif()

set(doc "# Command-line reference\n\n")
string(APPEND doc "Generated from `leanfade --help` and `leanfade COMMAND --help` by the build ")
string(APPEND doc "(`cmake/GenerateCliDoc.cmake`, `make cli-doc`); the test ")
string(APPEND doc "`docs.CliReferenceIsCurrent` fails when this file and the program differ. ")
string(APPEND doc "What the commands are for, with examples: [commands.md](commands.md).\n\n")
foreach(command IN LISTS subcommands)
  string(APPEND doc "- [`${command}`](#leanfade-${command})\n")
endforeach()
string(APPEND doc "\n```text\n${top}\n```\n")
foreach(command IN LISTS subcommands)
  help_of(text ${command})
  string(APPEND doc "\n## leanfade ${command}\n\n```text\n${text}\n```\n")
endforeach()
file(WRITE ${OUTPUT} "${doc}")

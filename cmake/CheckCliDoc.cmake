# cmake -P script of the test docs.CliReferenceIsCurrent: docs/cli.md (EXPECTED) must be what
# GenerateCliDoc.cmake writes from the program now (OUTPUT, in the build tree), so that every flag
# of every subcommand is in it as the program prints it. On a difference: `make cli-doc`.
include(${CMAKE_CURRENT_LIST_DIR}/GenerateCliDoc.cmake)
file(READ ${OUTPUT} generated)
if(NOT EXISTS ${EXPECTED})
  message(FATAL_ERROR "${EXPECTED} is missing: run `make cli-doc`")
endif()
file(READ ${EXPECTED} committed)
if(NOT generated STREQUAL committed)
  message(FATAL_ERROR "${EXPECTED} differs from the program's --help (generated: ${OUTPUT}); "
                      "run `make cli-doc` and commit docs/cli.md")
endif()
# Every --flag the program prints for a subcommand is in the file (what the equality implies,
# said explicitly).
string(REGEX MATCHALL "--[a-z][a-z0-9-]*" flags "${generated}")
list(REMOVE_DUPLICATES flags)
list(LENGTH flags count)
foreach(flag IN LISTS flags)
  string(FIND "${committed}" "${flag}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "docs/cli.md does not mention ${flag}")
  endif()
endforeach()
message(STATUS "docs/cli.md is current: ${count} flags")

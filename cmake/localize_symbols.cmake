# cmake -P script that finishes each static library of LIBRARIES (comma-separated target names)
# after `ar` and ranlib (cmake/LeanfadeLibraries.cmake; other archives are left as they are):
# links ARCHIVE's objects into one relocatable object, COMDAT groups resolved and dissolved
# (ld -r --force-group-allocation), makes every defined symbol local except those matching the
# patterns of KEEP (objcopy --wildcard --keep-global-symbols), and replaces the archive's members
# with that object. Undefined symbols (those of the other libraries and the system) stay as they
# are.
cmake_minimum_required(VERSION 3.25)
foreach(var ARCHIVE LIBRARIES LINKER OBJCOPY AR KEEP)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "localize_symbols.cmake needs -D${var}=...")
  endif()
endforeach()

get_filename_component(file_name ${ARCHIVE} NAME)
string(REGEX REPLACE "^lib(.*)\\.a$" "\\1" NAME "${file_name}")
string(REPLACE "," ";" LIBRARIES "${LIBRARIES}")
if(NOT NAME IN_LIST LIBRARIES)
  return()
endif()
get_filename_component(folder ${ARCHIVE} DIRECTORY)
set(object ${folder}/${NAME}.o)

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${ARGN} failed (${rc}):\n${out}${err}")
  endif()
endfunction()

run(${LINKER} -r --force-group-allocation -o ${object}
    --whole-archive ${ARCHIVE} --no-whole-archive)
run(${OBJCOPY} --wildcard --keep-global-symbols=${KEEP} ${object})
file(REMOVE ${ARCHIVE})
run(${AR} qcs ${ARCHIVE} ${object})
file(REMOVE ${object})

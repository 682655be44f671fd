# How the installed libraries (leanfade_core, leanfade_io, leanfade_scene, leanfade_gl) are built
# so that they link into any program or shared object (docs/integration.md, "Linking"):
#   - position-independent code, static or shared alike (-fPIC; -fno-semantic-interposition keeps
#     the calls inside a library as direct as without it);
#   - only the symbols of namespace leanfade global. Static libraries (the default): after `ar`,
#     each archive is linked into one relocatable object (ld -r --force-group-allocation: every
#     COMDAT group resolved inside the library and dissolved) whose other symbols objcopy makes
#     local (cmake/localize_symbols.cmake): bundled code (tinygltf, and nlohmann::json's, glm's
#     and the standard library's template instances) can no longer clash with an engine's own.
#     Shared libraries (LEANFADE_SHARED_LIBS): a version script exports the same patterns only.
# Included by the top-level CMakeLists.txt before the libraries' folders: archives made there are
# finished by cmake/localize_symbols.cmake (CMAKE_CXX_ARCHIVE_FINISH, reset by
# leanfade_configure_libraries()); leanfade_configure_libraries(), called after them, sets their
# properties.

set(LEANFADE_INSTALLED_LIBRARIES leanfade_core leanfade_io leanfade_scene leanfade_gl)

# The mangled names of namespace leanfade: functions and variables (member functions with their
# cv- and ref-qualifiers), vtables, VTTs, typeinfo objects and names, thunks, guard variables,
# function-local statics, reference temporaries and the thread_local wrappers.
set(LEANFADE_EXPORTED_SYMBOL_PATTERNS
  _ZN8leanfade* _ZNK8leanfade* _ZNR8leanfade* _ZNO8leanfade* _ZNKR8leanfade* _ZNKO8leanfade*
  _ZNV8leanfade* _ZNVK8leanfade*
  _ZTVN8leanfade* _ZTTN8leanfade* _ZTIN8leanfade* _ZTSN8leanfade*
  _ZTh*_N8leanfade* _ZTh*_NK8leanfade* _ZTv*_N8leanfade* _ZTv*_NK8leanfade*
  _ZTc*_N8leanfade* _ZTc*_NK8leanfade*
  _ZGVN8leanfade* _ZGVZN8leanfade* _ZGVZNK8leanfade* _ZZN8leanfade* _ZZNK8leanfade*
  _ZGRN8leanfade* _ZGRZN8leanfade* _ZGRZNK8leanfade* _ZTHN8leanfade* _ZTWN8leanfade*)

# The same list as objcopy's --keep-global-symbols file and as a linker version script.
list(JOIN LEANFADE_EXPORTED_SYMBOL_PATTERNS "\n" _leanfade_keep)
file(WRITE ${PROJECT_BINARY_DIR}/symbols/leanfade-exported.txt "${_leanfade_keep}\n")
list(JOIN LEANFADE_EXPORTED_SYMBOL_PATTERNS ";\n    " _leanfade_global)
file(WRITE ${PROJECT_BINARY_DIR}/symbols/leanfade.map
     "{\n  global:\n    ${_leanfade_global};\n  local:\n    *;\n};\n")

# Symbols are localized where the tools for it are there: ELF, GNU ld and objcopy (binutils).
set(LEANFADE_CAN_LOCALIZE OFF)
if(CMAKE_EXECUTABLE_FORMAT STREQUAL "ELF" AND CMAKE_LINKER AND CMAKE_OBJCOPY AND CMAKE_AR)
  execute_process(COMMAND ${CMAKE_LINKER} --help OUTPUT_VARIABLE _leanfade_ld_help
                  ERROR_QUIET RESULT_VARIABLE _leanfade_ld_rc)
  if(_leanfade_ld_rc EQUAL 0 AND _leanfade_ld_help MATCHES "--force-group-allocation")
    set(LEANFADE_CAN_LOCALIZE ON)
  endif()
endif()
if(LEANFADE_LOCALIZE_SYMBOLS AND NOT LEANFADE_CAN_LOCALIZE AND NOT LEANFADE_SHARED_LIBS)
  message(WARNING "LEANFADE_LOCALIZE_SYMBOLS needs ELF, GNU ld 2.30 or later and objcopy: the "
                  "static libraries keep the symbols of their bundled code global")
endif()

# Whether package.InstallAndConsume checks the installed libraries' symbols (tests/package).
set(LEANFADE_PACKAGE_SYMBOLS_CHECKED OFF)
if(CMAKE_EXECUTABLE_FORMAT STREQUAL "ELF" AND
   (LEANFADE_SHARED_LIBS OR (LEANFADE_LOCALIZE_SYMBOLS AND LEANFADE_CAN_LOCALIZE)))
  set(LEANFADE_PACKAGE_SYMBOLS_CHECKED ON)
endif()

if(LEANFADE_LOCALIZE_SYMBOLS AND LEANFADE_CAN_LOCALIZE AND NOT LEANFADE_SHARED_LIBS)
  set(LEANFADE_SAVED_ARCHIVE_FINISH "${CMAKE_CXX_ARCHIVE_FINISH}")
  list(JOIN LEANFADE_INSTALLED_LIBRARIES "," _leanfade_names)
  set(CMAKE_CXX_ARCHIVE_FINISH
      "${CMAKE_CXX_ARCHIVE_FINISH}"
      "\"${CMAKE_COMMAND}\" -DARCHIVE=<TARGET> -DLIBRARIES=${_leanfade_names} \
-DLINKER=\"${CMAKE_LINKER}\" -DOBJCOPY=\"${CMAKE_OBJCOPY}\" -DAR=\"${CMAKE_AR}\" \
-DKEEP=\"${PROJECT_BINARY_DIR}/symbols/leanfade-exported.txt\" \
-P \"${PROJECT_SOURCE_DIR}/cmake/localize_symbols.cmake\"")
endif()

macro(leanfade_configure_libraries)
  if(DEFINED LEANFADE_SAVED_ARCHIVE_FINISH)
    set(CMAKE_CXX_ARCHIVE_FINISH "${LEANFADE_SAVED_ARCHIVE_FINISH}")
  endif()
  foreach(target IN LISTS LEANFADE_INSTALLED_LIBRARIES)
    set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
    if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
      target_compile_options(${target} PRIVATE -fno-semantic-interposition)
    endif()
    # Static data of inline functions and templates weak instead of STB_GNU_UNIQUE, which
    # objcopy cannot make local (the same objects, static or shared).
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
      target_compile_options(${target} PRIVATE -fno-gnu-unique)
    endif()
    # C++20 is a usage requirement: a consumer that sets no standard compiles the headers with it.
    target_compile_features(${target} PUBLIC cxx_std_20)
    get_target_property(_leanfade_type ${target} TYPE)
    if(NOT _leanfade_type STREQUAL "SHARED_LIBRARY")
      # Static: the library's own symbols are hidden, so that a shared object linking it (an
      # engine plugin) does not export them; within the program or plugin they link as usual.
      set_target_properties(${target} PROPERTIES CXX_VISIBILITY_PRESET hidden
                            VISIBILITY_INLINES_HIDDEN ON)
    endif()
    if(_leanfade_type STREQUAL "SHARED_LIBRARY")
      if(CMAKE_EXECUTABLE_FORMAT STREQUAL "ELF")
        target_link_options(${target} PRIVATE
          "LINKER:--version-script=${PROJECT_BINARY_DIR}/symbols/leanfade.map")
        set_property(TARGET ${target} APPEND PROPERTY
                     LINK_DEPENDS ${PROJECT_BINARY_DIR}/symbols/leanfade.map)
      endif()
      set_target_properties(${target} PROPERTIES VERSION ${PROJECT_VERSION}
                            SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
    endif()
  endforeach()
endmacro()

# Install rules and the package files of leanfade (docs/integration.md): `cmake --install`
# puts the libraries (static, or shared with LEANFADE_SHARED_LIBS), their headers, the shaders,
# the `leanfade` executable, a CMake package config (find_package(leanfade): leanfade::leanfade,
# and leanfade::gl with COMPONENTS gl) and a pkg-config file (leanfade.pc) under the prefix.
#
# Included at the end of the top-level CMakeLists.txt, after every target is defined: the
# dependencies the package config looks for are read from the exported targets' link interfaces
# here, so a library that gains a dependency (target_link_libraries(... PRIVATE Foo::Foo)) needs no
# edit of this file when the package's name is the imported target's namespace (Foo).
# GNUInstallDirs and LEANFADE_INSTALL_SHADER_DIR come from the top-level CMakeLists.txt (the
# libraries' install() lines use them).
include(CMakePackageConfigHelpers)

set(LEANFADE_INSTALL_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/leanfade)

# leanfade::leanfade: what an engine links to bake LEAN maps in memory and read and write KTX2
# files (#include <leanfade/leanfade.hpp>); GL-free.
add_library(leanfade_package INTERFACE)
target_link_libraries(leanfade_package INTERFACE leanfade_core leanfade_io)
set_target_properties(leanfade_package PROPERTIES EXPORT_NAME leanfade)
add_library(leanfade::leanfade ALIAS leanfade_package)

# The two export sets: the GL-free libraries, and the OpenGL renderer with the meshes it draws.
# Each library is exported under its short name (leanfade_core -> leanfade::core).
set(LEANFADE_EXPORTED_CORE leanfade_warnings leanfade_core leanfade_io leanfade_package)
set(LEANFADE_EXPORTED_GL leanfade_scene leanfade_gl)
set_target_properties(leanfade_warnings PROPERTIES EXPORT_NAME warnings)
set_target_properties(leanfade_core PROPERTIES EXPORT_NAME core)
set_target_properties(leanfade_io PROPERTIES EXPORT_NAME io)
set_target_properties(leanfade_scene PROPERTIES EXPORT_NAME scene)
set_target_properties(leanfade_gl PROPERTIES EXPORT_NAME gl)

# Include folders: the source folders in the build tree, <prefix>/include once installed (core
# also has the shader folder: leanfade/core/shading.hpp includes lean_shading.glsl).
function(leanfade_installable_includes target)
  get_target_property(dirs ${target} INTERFACE_INCLUDE_DIRECTORIES)
  set(fixed "")
  if(dirs)
    foreach(dir IN LISTS dirs)
      if(dir MATCHES "^\\$<")
        list(APPEND fixed "${dir}")
      else()
        list(APPEND fixed "$<BUILD_INTERFACE:${dir}>")
      endif()
    endforeach()
  endif()
  list(APPEND fixed "$<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>" ${ARGN})
  set_target_properties(${target} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${fixed}")
endfunction()
leanfade_installable_includes(leanfade_core "$<INSTALL_INTERFACE:${LEANFADE_INSTALL_SHADER_DIR}>")
foreach(target leanfade_io leanfade_scene leanfade_gl)
  leanfade_installable_includes(${target})
endforeach()

# Every imported target the exported targets link (directly or through each other), as the
# list variable `out`, and the plain library names and flags they link (dl, -pthread) as
# `out`_PLAIN. A link item that is a target of this project but not exported is an error (it
# could not be found by a consumer).
function(leanfade_imported_dependencies out)
  set(exported ${LEANFADE_EXPORTED_CORE} ${LEANFADE_EXPORTED_GL})
  set(queue ${ARGN})
  set(seen "")
  set(found "")
  set(plain "")
  while(queue)
    list(POP_FRONT queue target)
    if(target IN_LIST seen)
      continue()
    endif()
    list(APPEND seen ${target})
    get_target_property(items ${target} INTERFACE_LINK_LIBRARIES)
    if(NOT items)
      continue()
    endif()
    foreach(item IN LISTS items)
      string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" item "${item}")
      if(NOT TARGET ${item})
        if(NOT item MATCHES "^\\$<")
          list(APPEND plain ${item})  # a plain library name (dl) or flag: the linker finds it
        endif()
        continue()
      endif()
      get_target_property(aliased ${item} ALIASED_TARGET)
      if(aliased)
        set(item ${aliased})
      endif()
      get_target_property(imported ${item} IMPORTED)
      if(imported)
        list(APPEND found ${item})
      elseif(item IN_LIST exported)
        list(APPEND queue ${item})
      else()
        message(FATAL_ERROR "${target} links ${item}, which is neither exported by "
                            "cmake/LeanfadeInstall.cmake nor an imported target")
      endif()
    endforeach()
  endwhile()
  list(REMOVE_DUPLICATES found)
  list(REMOVE_DUPLICATES plain)
  set(${out} ${found} PARENT_SCOPE)
  set(${out}_PLAIN ${plain} PARENT_SCOPE)
endfunction()

# The find_dependency() lines (package config) for imported targets: the package is the target's
# namespace (glm::glm -> glm, PNG::PNG -> PNG); PkgConfig::NAME targets are found again with
# pkg_check_modules and the module name they were found with.
function(leanfade_find_dependency_lines out)
  set(blocks "")
  foreach(target IN LISTS ARGN)
    string(REGEX MATCH "^([A-Za-z0-9_]+)::(.+)$" match "${target}")
    if(NOT match)
      message(FATAL_ERROR "cannot tell the package of the imported target ${target}: "
                          "name it Package::Target or add a rule to cmake/LeanfadeInstall.cmake")
    endif()
    set(package ${CMAKE_MATCH_1})
    set(name ${CMAKE_MATCH_2})
    if(package STREQUAL "PkgConfig")
      if(NOT ${name}_MODULE_NAME)
        message(FATAL_ERROR "no pkg-config module name for ${target}")
      endif()
      set(module ${${name}_MODULE_NAME})
      string(CONCAT block "if(NOT TARGET ${target})\n"
             "  pkg_check_modules(${name} QUIET IMPORTED_TARGET ${module})\n"
             "  if(NOT ${name}_FOUND)\n"
             "    set(leanfade_FOUND FALSE)\n"
             "    set(leanfade_NOT_FOUND_MESSAGE \"pkg-config module ${module} not found\")\n"
             "    return()\n"
             "  endif()\n"
             "endif()")
      list(APPEND blocks "find_dependency(PkgConfig)" "${block}")
    else()
      list(APPEND blocks "find_dependency(${package})")
    endif()
  endforeach()
  list(REMOVE_DUPLICATES blocks)
  list(JOIN blocks "\n" text)
  set(${out} "${text}" PARENT_SCOPE)
endfunction()

# The pkg-config Requires and Libs of imported targets: their pkg-config module where one is
# known, else -l<name> for the library file (with -L<folder> only where the folder is not one
# the compiler searches anyway); threads as -pthread (also where the C library has them built in:
# the file is for any compiler and C library). Nothing names a file by its absolute path.
set(LEANFADE_PC_MODULE_glm glm)
set(LEANFADE_PC_MODULE_PNG libpng)
set(LEANFADE_PC_MODULE_nlohmann_json nlohmann_json)
set(LEANFADE_PC_MODULE_OpenSSL libcrypto)
set(LEANFADE_PC_MODULE_OpenImageIO OpenImageIO)
set(LEANFADE_PC_MODULE_TinyGLTF tinygltf)
set(LEANFADE_PC_MODULE_tinyobjloader tinyobjloader)
function(leanfade_pc_library_flags file out)
  get_filename_component(folder ${file} DIRECTORY)
  get_filename_component(name ${file} NAME)
  if(NOT name MATCHES "^lib(.+)\\.(so|a|dylib)(\\.[0-9.]+)?$")
    message(FATAL_ERROR "leanfade.pc cannot name ${file} with -l: add its pkg-config module to "
                        "cmake/LeanfadeInstall.cmake")
  endif()
  set(flags "")
  if(NOT folder IN_LIST CMAKE_CXX_IMPLICIT_LINK_DIRECTORIES)
    list(APPEND flags "-L${folder}")
  endif()
  list(APPEND flags "-l${CMAKE_MATCH_1}")
  set(${out} ${flags} PARENT_SCOPE)
endfunction()
function(leanfade_pkg_config_fields requires_out libs_out)
  cmake_parse_arguments(PC "" "" "TARGETS;PLAIN" ${ARGN})
  set(requires "")
  set(libs "")
  foreach(target IN LISTS PC_TARGETS)
    string(REGEX MATCH "^([A-Za-z0-9_]+)::(.+)$" match "${target}")
    set(package ${CMAKE_MATCH_1})
    set(name ${CMAKE_MATCH_2})
    if(target STREQUAL "Threads::Threads")
      list(APPEND libs -pthread)
    elseif(package STREQUAL "PkgConfig")
      list(APPEND requires ${${name}_MODULE_NAME})
    elseif(DEFINED LEANFADE_PC_MODULE_${package})
      list(APPEND requires ${LEANFADE_PC_MODULE_${package}})
    else()
      get_target_property(type ${target} TYPE)
      if(type STREQUAL "INTERFACE_LIBRARY")
        continue()
      endif()
      set(location "")
      foreach(property IMPORTED_LOCATION_RELEASE IMPORTED_LOCATION_NONE IMPORTED_LOCATION
                       IMPORTED_LOCATION_RELWITHDEBINFO IMPORTED_LOCATION_DEBUG)
        get_target_property(location ${target} ${property})
        if(location)
          break()
        endif()
      endforeach()
      if(NOT location)
        message(FATAL_ERROR "no library file for ${target} in leanfade.pc: add its pkg-config "
                            "module to cmake/LeanfadeInstall.cmake")
      endif()
      leanfade_pc_library_flags(${location} flags)
      list(APPEND libs ${flags})
    endif()
  endforeach()
  foreach(item IN LISTS PC_PLAIN)
    if(item MATCHES "^-")
      list(APPEND libs ${item})
    elseif(IS_ABSOLUTE ${item})
      leanfade_pc_library_flags(${item} flags)
      list(APPEND libs ${flags})
    else()
      list(APPEND libs -l${item})
    endif()
  endforeach()
  list(REMOVE_DUPLICATES requires)
  list(REMOVE_DUPLICATES libs)
  string(REPLACE ";" ", " requires "${requires}")
  string(REPLACE ";" " " libs "${libs}")
  set(${requires_out} "${requires}" PARENT_SCOPE)
  set(${libs_out} "${libs}" PARENT_SCOPE)
endfunction()

leanfade_imported_dependencies(LEANFADE_CORE_DEPENDENCIES ${LEANFADE_EXPORTED_CORE})
leanfade_imported_dependencies(LEANFADE_ALL_DEPENDENCIES ${LEANFADE_EXPORTED_GL})
set(LEANFADE_GL_DEPENDENCIES ${LEANFADE_ALL_DEPENDENCIES})
list(REMOVE_ITEM LEANFADE_GL_DEPENDENCIES ${LEANFADE_CORE_DEPENDENCIES})
leanfade_find_dependency_lines(LEANFADE_CORE_FIND_DEPENDENCIES ${LEANFADE_CORE_DEPENDENCIES})
leanfade_find_dependency_lines(LEANFADE_GL_FIND_DEPENDENCIES ${LEANFADE_GL_DEPENDENCIES})
leanfade_pkg_config_fields(LEANFADE_PC_REQUIRES LEANFADE_PC_DEPENDENCY_LIBS
  TARGETS ${LEANFADE_CORE_DEPENDENCIES} PLAIN ${LEANFADE_CORE_DEPENDENCIES_PLAIN})
# Static libraries: a program links their dependencies too (Libs); shared ones link them
# themselves (Libs.private, for `pkg-config --static`).
if(LEANFADE_SHARED_LIBS)
  set(LEANFADE_PC_LIBS "")
  set(LEANFADE_PC_LIBS_PRIVATE "${LEANFADE_PC_DEPENDENCY_LIBS}")
else()
  set(LEANFADE_PC_LIBS "${LEANFADE_PC_DEPENDENCY_LIBS}")
  set(LEANFADE_PC_LIBS_PRIVATE "")
endif()

install(TARGETS ${LEANFADE_EXPORTED_CORE} EXPORT leanfadeTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS ${LEANFADE_EXPORTED_GL} EXPORT leanfadeGlTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
# The OpenImageIO module libs/io loads with dlopen (JPEG, TGA, TIFF, ...), in <prefix>/lib/leanfade:
# found beside the code that loads it, or by name on the run path that the package gives the
# programs linking it (leanfade::io's INTERFACE_LINK_OPTIONS; leanfade.pc's Libs).
set(LEANFADE_PC_MODULE_RPATH "")
if(TARGET leanfade_io_oiio)
  install(TARGETS leanfade_io_oiio LIBRARY DESTINATION lib/leanfade)
  if(CMAKE_EXECUTABLE_FORMAT STREQUAL "ELF")
    set(LEANFADE_PC_MODULE_RPATH "-Wl,-rpath,\${prefix}/lib/leanfade")
  endif()
endif()
install(EXPORT leanfadeTargets NAMESPACE leanfade:: DESTINATION ${LEANFADE_INSTALL_CMAKE_DIR})
install(EXPORT leanfadeGlTargets NAMESPACE leanfade:: DESTINATION ${LEANFADE_INSTALL_CMAKE_DIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/leanfadeConfig.cmake.in
  ${PROJECT_BINARY_DIR}/package/leanfadeConfig.cmake
  INSTALL_DESTINATION ${LEANFADE_INSTALL_CMAKE_DIR}
  PATH_VARS LEANFADE_INSTALL_SHADER_DIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/package/leanfadeConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/package/leanfadeConfig.cmake
              ${PROJECT_BINARY_DIR}/package/leanfadeConfigVersion.cmake
        DESTINATION ${LEANFADE_INSTALL_CMAKE_DIR})

# leanfade.pc, relocatable: the prefix is found from the file's own folder.
file(RELATIVE_PATH LEANFADE_PC_TO_PREFIX
     ${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR}/pkgconfig ${CMAKE_INSTALL_PREFIX})
string(REGEX REPLACE "/$" "" LEANFADE_PC_TO_PREFIX "${LEANFADE_PC_TO_PREFIX}")
configure_file(${PROJECT_SOURCE_DIR}/cmake/leanfade.pc.in ${PROJECT_BINARY_DIR}/package/leanfade.pc
               @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/package/leanfade.pc
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# The test that installs this build and builds a consumer against it (tests/package).
if(LEANFADE_BUILD_TESTS)
  add_subdirectory(${PROJECT_SOURCE_DIR}/tests/package ${PROJECT_BINARY_DIR}/tests/package)
endif()

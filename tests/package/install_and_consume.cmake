# cmake -P script of the test package.InstallAndConsume (tests/package/CMakeLists.txt).
# Installs BUILD_DIR into WORK_DIR/prefix; checks that the installed libraries define no global
# symbol outside namespace leanfade (SYMBOLS=ON: bundled code made local, cmake/LeanfadeLibraries
# .cmake); builds examples/consumer against that prefix with CMake (find_package(leanfade
# COMPONENTS gl), a program with its own tinygltf among them) and with pkg-config (its Makefile),
# and examples/plugin (a shared object linking the package, loaded by a host program) with both;
# runs the programs, and fails on the first step that fails. Nothing is downloaded; the package
# is found in the prefix only (no user package registry, the prefix first on every search path).
cmake_policy(SET CMP0057 NEW)  # if(... IN_LIST ...)
foreach(var BUILD_DIR SOURCE_DIR WORK_DIR CONSUMER_DIR PLUGIN_DIR LIBDIR GENERATOR CXX MAKE
            PKG_CONFIG NM OBJCOPY SYMBOLS)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "install_and_consume.cmake needs -D${var}=...")
  endif()
endforeach()

function(step name)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${name} failed (${rc}):\n${out}\n${err}")
  endif()
  message(STATUS "${name}: ok")
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

set(prefix ${WORK_DIR}/prefix)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR}/out)

step("install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
set(expected include/leanfade/leanfade.hpp share/leanfade/shaders/lean_shading.glsl bin/leanfade
    ${LIBDIR}/cmake/leanfade/leanfadeConfig.cmake ${LIBDIR}/pkgconfig/leanfade.pc)
if(EXISTS ${BUILD_DIR}/libs/io/libleanfade_io_oiio.so)
  list(APPEND expected lib/leanfade/libleanfade_io_oiio.so)  # OpenImageIO formats (dlopen)
endif()
foreach(file IN LISTS expected)
  if(NOT EXISTS ${prefix}/${file})
    message(FATAL_ERROR "the install has no ${file}")
  endif()
endforeach()

# The public API is at most 16 headers: every other installed header lies in a detail/ folder
# (installed because the public ones include them, not a promise). The consumers and plugins
# below include public headers only, so each of them compiles against those alone.
set(max_public_headers 16)
file(GLOB_RECURSE headers LIST_DIRECTORIES false RELATIVE ${prefix}/include
     ${prefix}/include/leanfade/*.hpp)
set(public_headers "")
foreach(header IN LISTS headers)
  if(NOT header MATCHES "/detail/")
    list(APPEND public_headers ${header})
  endif()
endforeach()
list(LENGTH public_headers public_count)
list(JOIN public_headers "\n  " shown)
if(public_count GREATER max_public_headers OR public_count EQUAL 0)
  message(FATAL_ERROR "${public_count} public headers installed (at most ${max_public_headers}):"
                      "\n  ${shown}")
endif()
message(STATUS "${public_count} public headers:\n  ${shown}")
file(GLOB example_sources ${CONSUMER_DIR}/*.cpp ${PLUGIN_DIR}/*.cpp)
foreach(source IN LISTS example_sources)
  file(STRINGS ${source} includes REGEX "^#include [<\"]leanfade/")
  foreach(line IN LISTS includes)
    string(REGEX REPLACE "^#include [<\"]([^>\"]+)[>\"].*$" "\\1" header "${line}")
    if(NOT header IN_LIST public_headers)
      message(FATAL_ERROR "${source} includes ${header}, which is not a public header")
    endif()
  endforeach()
endforeach()

# Relocatable: no installed file names the build or the source tree (a compiled-in path, a run
# path, a package file), so the prefix can be moved or packaged. Debug information may name them
# (a debugger's business): ELF files are compared without it (objcopy --strip-debug).
set(stripped ${WORK_DIR}/stripped)
file(MAKE_DIRECTORY ${stripped})
file(GLOB_RECURSE installed LIST_DIRECTORIES false ${prefix}/*)
list(LENGTH installed installed_count)
set(tree_paths "")
foreach(file IN LISTS installed)
  if(IS_SYMLINK ${file})
    continue()
  endif()
  set(scanned ${file})
  file(READ ${file} magic LIMIT 4 HEX)
  if(magic STREQUAL "7f454c46" OR file MATCHES "\\.a$")  # ELF, or an archive of ELF objects
    string(MD5 name "${file}")
    set(scanned ${stripped}/${name})
    execute_process(COMMAND ${OBJCOPY} --strip-debug ${file} ${scanned} RESULT_VARIABLE rc
                    ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "objcopy --strip-debug ${file} failed: ${err}")
    endif()
  endif()
  foreach(tree ${BUILD_DIR} ${SOURCE_DIR})
    string(REGEX REPLACE "([][+.*()^$?|\\])" "\\\\\\1" tree_regex "${tree}")
    file(STRINGS ${scanned} hits LIMIT_COUNT 1 REGEX "${tree_regex}")
    if(hits)
      string(REPLACE "${prefix}/" "" shown "${file}")
      list(APPEND tree_paths "${shown} names ${tree}")
    endif()
  endforeach()
endforeach()
file(REMOVE_RECURSE ${stripped})
if(tree_paths)
  list(JOIN tree_paths "\n  " shown)
  message(FATAL_ERROR "installed files name the build or source tree:\n  ${shown}")
endif()
message(STATUS "${installed_count} installed files: none names the build or source tree")

# The installed program finds its Node.js scripts in share/leanfade/node (the npm packages are
# installed with them when the source tree has them: scripts/install-deps.sh runs npm ci there).
if(EXISTS ${SOURCE_DIR}/tools/node/node_modules/naga-wasm/package.json)
  if(NOT EXISTS ${prefix}/share/leanfade/node/node_modules/naga-wasm/package.json)
    message(FATAL_ERROR "the install has no share/leanfade/node/node_modules/naga-wasm")
  endif()
  step("installed leanfade shaders --lang wgsl"
       ${prefix}/bin/leanfade shaders --lang wgsl -o ${WORK_DIR}/out/wgsl)
  if(NOT EXISTS ${WORK_DIR}/out/wgsl/scene_lean_plain.frag.wgsl)
    message(FATAL_ERROR "the installed leanfade wrote no WGSL: ${step_output}")
  endif()
  step("installed leanfade bake --compress basis"
       ${prefix}/bin/leanfade bake --builtin bumps --size 32 --roughness-out
       ${WORK_DIR}/out/basis.ktx2 --compress basis)
  if(NOT EXISTS ${WORK_DIR}/out/basis.normal.ktx2)
    message(FATAL_ERROR "the installed leanfade wrote no Basis Universal texture: ${step_output}")
  endif()
endif()

# Defined global symbols of the installed libraries: only those of namespace leanfade (functions,
# variables, vtables, typeinfo, thunks, guard variables, function-local statics, as mangled).
set(leanfade_symbol "^_Z(N[rVK]*[RO]?8leanfade|T[VTIS]N8leanfade|T[hvc].*_N[rVK]*[RO]?8leanfade")
string(APPEND leanfade_symbol "|G[VR]Z?N[rVK]*8leanfade|ZN[rVK]*[RO]?8leanfade|T[HW]N8leanfade)")
if(SYMBOLS)
  foreach(library leanfade_core leanfade_io leanfade_scene leanfade_gl)
    set(file ${prefix}/${LIBDIR}/lib${library}.a)
    set(nm_flags -g --defined-only)
    if(NOT EXISTS ${file})
      set(file ${prefix}/${LIBDIR}/lib${library}.so)
      set(nm_flags -D --defined-only)
    endif()
    step("nm ${library}" ${NM} ${nm_flags} ${file})
    string(REPLACE "\n" ";" lines "${step_output}")
    set(kept 0)
    set(foreign "")
    foreach(line IN LISTS lines)
      if(NOT line MATCHES "^[0-9a-fA-F]* [A-Za-z] (.+)$")
        continue()
      endif()
      set(symbol ${CMAKE_MATCH_1})
      string(REGEX REPLACE "@.*$" "" symbol "${symbol}")  # a shared library's version
      if(symbol MATCHES "${leanfade_symbol}")
        math(EXPR kept "${kept} + 1")
      elseif(NOT symbol STREQUAL "")
        list(APPEND foreign "${symbol}")
      endif()
    endforeach()
    list(LENGTH foreign foreign_count)
    if(foreign_count GREATER 0)
      list(SUBLIST foreign 0 20 shown)
      list(JOIN shown "\n  " shown)
      message(FATAL_ERROR "${file} defines ${foreign_count} global symbols outside namespace "
                          "leanfade (bundled code not made local), e.g.\n  ${shown}")
    endif()
    message(STATUS "${library}: ${kept} global symbols, all of namespace leanfade")
  endforeach()
endif()

# find_package(leanfade COMPONENTS gl)
step("configure the CMake consumer" ${CMAKE_COMMAND} -S ${CONSUMER_DIR} -B ${WORK_DIR}/cmake
     -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CXX}
     -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
file(STRINGS ${WORK_DIR}/cmake/CMakeCache.txt found_dir REGEX "^leanfade_DIR:")
if(NOT found_dir STREQUAL "leanfade_DIR:PATH=${prefix}/${LIBDIR}/cmake/leanfade")
  message(FATAL_ERROR "the consumer found another leanfade package: ${found_dir}")
endif()
step("build the CMake consumer" ${CMAKE_COMMAND} --build ${WORK_DIR}/cmake -j 2)
# The DDS is decoded by the package's OpenImageIO module: found from the consumer's run path.
set(dds ${SOURCE_DIR}/tests/io/data/nvtt-bc5.dds)
step("run consumer" ${WORK_DIR}/cmake/consumer ${WORK_DIR}/out ${dds})
message(STATUS "${step_output}")
# The installed Python module (python/), from the prefix alone: it bakes the DDS through the same
# OpenImageIO module, found from the extension's run path.
if(PYTHON)
  step("import the installed Python module" ${CMAKE_COMMAND} -E env
       PYTHONPATH=${prefix}/${PYTHON_DIR} PYTHONDONTWRITEBYTECODE=1
       ${PYTHON} -c [[
import sys
import leanfade
lean = leanfade.bake(sys.argv[1])
print(leanfade.__file__, lean.width, lean.height, lean.source, lean.storage)
]] ${dds})
  if(NOT step_output MATCHES "^${prefix}/${PYTHON_DIR}/leanfade/__init__.py 32 32 normal 16")
    message(FATAL_ERROR "the installed Python module: ${step_output}")
  endif()
  message(STATUS "${step_output}")
endif()
step("run consumer_gl" ${WORK_DIR}/cmake/consumer_gl ${prefix}/share/leanfade/shaders)
message(STATUS "${step_output}")
if(NOT EXISTS ${WORK_DIR}/cmake/consumer_tinygltf)
  message(FATAL_ERROR "consumer_tinygltf was not built (tiny_gltf.h or nlohmann_json not found)")
endif()
step("run consumer_tinygltf" ${WORK_DIR}/cmake/consumer_tinygltf ${WORK_DIR}/out)
message(STATUS "${step_output}")
# Two copies of tinygltf in it: the program's (global) and leanfade's (local). With leanfade's
# global, the linker would take the program's for leanfade's calls too and leave leanfade's out.
if(SYMBOLS)
  step("nm consumer_tinygltf" ${NM} ${WORK_DIR}/cmake/consumer_tinygltf)
  set(load_from_string "_ZN8tinygltf8TinyGLTF14LoadFromString[A-Za-z0-9_]*")
  foreach(binding T t)
    if(NOT step_output MATCHES " ${binding} ${load_from_string}\n")
      message(FATAL_ERROR "consumer_tinygltf has no ${binding} tinygltf::TinyGLTF::LoadFromString: "
                          "the program's (T) and leanfade's (t) tinygltf should both be in it")
    endif()
  endforeach()
  message(STATUS "consumer_tinygltf: its own tinygltf (global) and leanfade's (local)")
endif()

# A shared object linking the package: find_package(leanfade)
step("configure the CMake plugin" ${CMAKE_COMMAND} -S ${PLUGIN_DIR} -B ${WORK_DIR}/plugin
     -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CXX}
     -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
step("build the CMake plugin" ${CMAKE_COMMAND} --build ${WORK_DIR}/plugin -j 2)
step("run plugin_host" ${WORK_DIR}/plugin/plugin_host ${WORK_DIR}/plugin/libleanfade_plugin.so)
message(STATUS "${step_output}")

# A plugin exports its own entry point and no symbol of leanfade's (the static libraries' symbols
# are hidden; the plugin hides the headers' inline functions, as docs/integration.md says).
function(check_plugin_exports plugin)
  if(NOT SYMBOLS)
    return()
  endif()
  step("nm -D ${plugin}" ${NM} -D --defined-only ${plugin})
  if(NOT step_output MATCHES "leanfade_plugin_bake")
    message(FATAL_ERROR "${plugin} does not export leanfade_plugin_bake:\n${step_output}")
  endif()
  string(REGEX MATCHALL "[^\n]*8leanfade[^\n]*" exported "${step_output}")
  list(LENGTH exported count)
  if(count GREATER 0)
    list(SUBLIST exported 0 10 shown)
    list(JOIN shown "\n  " shown)
    message(FATAL_ERROR "${plugin} exports ${count} symbols of leanfade, e.g.\n  ${shown}")
  endif()
  message(STATUS "${plugin}: exports no symbol of leanfade")
endfunction()
check_plugin_exports(${WORK_DIR}/plugin/libleanfade_plugin.so)

# pkg-config leanfade
file(MAKE_DIRECTORY ${WORK_DIR}/pkg-config)
step("build the pkg-config consumer" ${CMAKE_COMMAND} -E env
     PKG_CONFIG_PATH=${prefix}/${LIBDIR}/pkgconfig
     ${MAKE} -f ${CONSUMER_DIR}/Makefile BUILD=${WORK_DIR}/pkg-config CXX=${CXX}
     PKG_CONFIG=${PKG_CONFIG})
step("run consumer_pc" ${WORK_DIR}/pkg-config/consumer_pc ${WORK_DIR}/out ${dds})
message(STATUS "${step_output}")

# A shared object linking the package: g++ -shared -fPIC plugin.cpp $(pkg-config --cflags --libs
# leanfade)
file(MAKE_DIRECTORY ${WORK_DIR}/plugin-pc)
step("build the pkg-config plugin" ${CMAKE_COMMAND} -E env
     PKG_CONFIG_PATH=${prefix}/${LIBDIR}/pkgconfig
     ${MAKE} -f ${PLUGIN_DIR}/Makefile BUILD=${WORK_DIR}/plugin-pc CXX=${CXX}
     PKG_CONFIG=${PKG_CONFIG})
step("run plugin_host on the pkg-config plugin" ${WORK_DIR}/plugin-pc/plugin_host
     ${WORK_DIR}/plugin-pc/libleanfade_plugin_pc.so)
message(STATUS "${step_output}")
check_plugin_exports(${WORK_DIR}/plugin-pc/libleanfade_plugin_pc.so)

# cmake -P script of the test package.InstallAndConsume (tests/package/CMakeLists.txt).
# Installs BUILD_DIR into WORK_DIR/prefix, builds examples/consumer against that prefix with CMake
# (find_package(leanfade COMPONENTS gl)) and with pkg-config (its Makefile), runs the programs, and
# fails on the first step that fails. Nothing is downloaded; the package is found in the prefix
# only (no user package registry, the prefix first on every search path).
foreach(var BUILD_DIR WORK_DIR CONSUMER_DIR LIBDIR GENERATOR CXX MAKE PKG_CONFIG)
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

# find_package(leanfade COMPONENTS gl)
step("configure the CMake consumer" ${CMAKE_COMMAND} -S ${CONSUMER_DIR} -B ${WORK_DIR}/cmake
     -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CXX}
     -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
file(STRINGS ${WORK_DIR}/cmake/CMakeCache.txt found_dir REGEX "^leanfade_DIR:")
if(NOT found_dir STREQUAL "leanfade_DIR:PATH=${prefix}/${LIBDIR}/cmake/leanfade")
  message(FATAL_ERROR "the consumer found another leanfade package: ${found_dir}")
endif()
step("build the CMake consumer" ${CMAKE_COMMAND} --build ${WORK_DIR}/cmake -j 2)
step("run consumer" ${WORK_DIR}/cmake/consumer ${WORK_DIR}/out)
message(STATUS "${step_output}")
step("run consumer_gl" ${WORK_DIR}/cmake/consumer_gl ${prefix}/share/leanfade/shaders)
message(STATUS "${step_output}")

# pkg-config leanfade
file(MAKE_DIRECTORY ${WORK_DIR}/pkg-config)
step("build the pkg-config consumer" ${CMAKE_COMMAND} -E env
     PKG_CONFIG_PATH=${prefix}/${LIBDIR}/pkgconfig
     ${MAKE} -f ${CONSUMER_DIR}/Makefile BUILD=${WORK_DIR}/pkg-config CXX=${CXX}
     PKG_CONFIG=${PKG_CONFIG})
step("run consumer_pc" ${WORK_DIR}/pkg-config/consumer_pc ${WORK_DIR}/out)
message(STATUS "${step_output}")

# leanfade_embed_files(TARGET target NAMESPACE ns FILES a b ... BASE dir)
# Generates a C++ source holding each file's text, looked up by its path relative to BASE, so
# the binary runs from any folder. Re-generated when any listed file changes.
function(leanfade_embed_files)
  cmake_parse_arguments(E "" "TARGET;BASE;NAME" "FILES" ${ARGN})
  set(out ${CMAKE_CURRENT_BINARY_DIR}/${E_NAME}.cpp)
  set(script ${PROJECT_SOURCE_DIR}/cmake/embed_files_script.cmake)
  add_custom_command(OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out} -DBASE=${E_BASE} -DNAME=${E_NAME}
            "-DFILES=${E_FILES}" -P ${script}
    DEPENDS ${E_FILES} ${script}
    COMMENT "Embedding ${E_NAME}"
    VERBATIM)
  target_sources(${E_TARGET} PRIVATE ${out})
endfunction()

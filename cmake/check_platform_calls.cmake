# cmake -P script of the test platform.PortableCallsNoLinuxFunction (top-level CMakeLists.txt, the
# portable build only): fails when LIBRARIES (a list of static libraries or objects) call a
# function that the portable platform layer replaces (leanfade/core/detail/platform.hpp).
cmake_minimum_required(VERSION 3.25)
foreach(var NM LIBRARIES)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "check_platform_calls.cmake needs -D${var}=...")
  endif()
endforeach()
set(linux_only madvise mmap mmap64 munmap posix_fallocate posix_fallocate64 syscall copy_file_range
    ioctl)
foreach(library IN LISTS LIBRARIES)
  execute_process(COMMAND ${NM} -u ${library} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${NM} -u ${library} failed (${rc}): ${err}")
  endif()
  foreach(function IN LISTS linux_only)
    if(out MATCHES "U ${function}(@[^\n]*)?\n")
      message(FATAL_ERROR "${library} calls ${function}, which the portable build replaces")
    endif()
  endforeach()
  message(STATUS "${library}: none of ${linux_only}")
endforeach()

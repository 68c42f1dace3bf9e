# ctest -R Install: install the build tree into a scratch prefix, build and run the consumer.
file(REMOVE_RECURSE "${WORK}")
execute_process(COMMAND "${CMAKE_COMMAND}" --install "${BUILD}" --prefix "${WORK}/prefix"
                RESULT_VARIABLE r OUTPUT_QUIET)
if(r)
  message(FATAL_ERROR "install failed")
endif()
# Ceres and nanoflann stay inside the libraries: no installed header includes them (a header
# that needs one is the library's own, not installed), so a consumer compiles without them.
file(GLOB_RECURSE installed_headers "${WORK}/prefix/include/loopscan/*.hpp")
foreach(h IN LISTS installed_headers)
  file(STRINGS "${h}" includes REGEX "^#include <(ceres|nanoflann)")
  if(includes)
    message(FATAL_ERROR "installed header ${h} includes a private dependency: ${includes}")
  endif()
endforeach()
execute_process(COMMAND "${CMAKE_COMMAND}" -S "${SOURCE}" -B "${WORK}/build" -G Ninja
                "-DCMAKE_PREFIX_PATH=${WORK}/prefix" -DCMAKE_BUILD_TYPE=Release
                RESULT_VARIABLE r)
if(r)
  message(FATAL_ERROR "configuring the consumer failed")
endif()
execute_process(COMMAND "${CMAKE_COMMAND}" --build "${WORK}/build" RESULT_VARIABLE r)
if(r)
  message(FATAL_ERROR "building the consumer failed")
endif()
execute_process(COMMAND "${WORK}/build/consumer" RESULT_VARIABLE r)
if(r)
  message(FATAL_ERROR "the consumer failed")
endif()

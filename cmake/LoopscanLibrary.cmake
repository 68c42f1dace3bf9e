# loopscan_library(<name> SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Builds loopscan_<name>, aliased loopscan::<name>, headers under cpp/ as <loopscan/<name>/...>.
function(loopscan_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(loopscan_${name} ${ARG_SOURCES})
  add_library(loopscan::${name} ALIAS loopscan_${name})
  set_target_properties(loopscan_${name} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(loopscan_${name} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/cpp>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(loopscan_${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  target_compile_options(loopscan_${name} PRIVATE ${LOOPSCAN_WARNINGS})
  install(TARGETS loopscan_${name} EXPORT loopscanTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/loopscan/${name}
    FILES_MATCHING PATTERN "*.hpp")
endfunction()

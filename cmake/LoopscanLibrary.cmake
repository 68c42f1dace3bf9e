# loopscan_library(<name> SOURCES ... [HEADER_DIR dir] [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Builds loopscan_<name>, aliased loopscan::<name>. Headers are included as
# <loopscan/<HEADER_DIR>/...> (HEADER_DIR defaults to <name>) from the source tree and from an
# installed package alike; only this folder's own headers are installed (not its subfolders').
function(loopscan_library name)
  cmake_parse_arguments(ARG "" "HEADER_DIR" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  if(NOT ARG_HEADER_DIR)
    set(ARG_HEADER_DIR ${name})
  endif()
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
  file(GLOB headers CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.hpp)
  install(FILES ${headers} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/loopscan/${ARG_HEADER_DIR})
endfunction()

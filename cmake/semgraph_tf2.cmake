# semgraph_find_tf2(): finds ROS 1 tf2 (Debian's libtf2-dev) and, when found, defines the
# INTERFACE target semgraph_tf2 that links it. Used by the benchmarks (the tf2 comparison) and
# the examples (coming_from_tf2). tf2's CMake config needs catkin, which Debian does not package,
# so tf2 is found through pkg-config, or else by its header and libraries. Calling it again is a
# no-op; test for the result with `if(TARGET semgraph_tf2)`.
function(semgraph_find_tf2)
  if(TARGET semgraph_tf2)
    return()
  endif()
  find_package(PkgConfig QUIET)
  if(PkgConfig_FOUND)
    pkg_check_modules(SEMGRAPH_TF2 QUIET IMPORTED_TARGET GLOBAL tf2)
  endif()
  if(SEMGRAPH_TF2_FOUND)
    add_library(semgraph_tf2 INTERFACE)
    target_link_libraries(semgraph_tf2 INTERFACE PkgConfig::SEMGRAPH_TF2)
    return()
  endif()
  find_path(SEMGRAPH_TF2_INCLUDE_DIR tf2/buffer_core.h)
  find_library(SEMGRAPH_TF2_LIBRARY tf2)
  find_library(SEMGRAPH_ROSTIME_LIBRARY rostime)
  find_library(SEMGRAPH_CONSOLE_BRIDGE_LIBRARY console_bridge)
  find_library(SEMGRAPH_CPP_COMMON_LIBRARY cpp_common)
  find_library(SEMGRAPH_ROSCPP_SERIALIZATION_LIBRARY roscpp_serialization)
  if(SEMGRAPH_TF2_INCLUDE_DIR AND SEMGRAPH_TF2_LIBRARY AND SEMGRAPH_ROSTIME_LIBRARY
     AND SEMGRAPH_CONSOLE_BRIDGE_LIBRARY AND SEMGRAPH_CPP_COMMON_LIBRARY)
    add_library(semgraph_tf2 INTERFACE)
    target_include_directories(semgraph_tf2 SYSTEM INTERFACE ${SEMGRAPH_TF2_INCLUDE_DIR})
    target_link_libraries(semgraph_tf2 INTERFACE
        ${SEMGRAPH_TF2_LIBRARY} ${SEMGRAPH_CONSOLE_BRIDGE_LIBRARY}
        $<$<BOOL:${SEMGRAPH_ROSCPP_SERIALIZATION_LIBRARY}>:${SEMGRAPH_ROSCPP_SERIALIZATION_LIBRARY}>
        ${SEMGRAPH_ROSTIME_LIBRARY} ${SEMGRAPH_CPP_COMMON_LIBRARY})
  endif()
endfunction()

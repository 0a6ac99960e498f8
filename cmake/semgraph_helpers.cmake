# Helpers that keep the folder CMakeLists.txt files declarative.

# Warnings as errors, for our own targets only: linked PRIVATE, never exported to consumers.
add_library(semgraph_warnings INTERFACE)
target_compile_options(semgraph_warnings INTERFACE -Wall -Wextra -Werror -Wpedantic)
# GCC 12 at -O3 reports a false -Wrestrict on "literal" + std::string (GCC PR 105329).
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  target_compile_options(semgraph_warnings INTERFACE -Wno-restrict)
endif()

# semgraph_add_layer(NAME <layer> SOURCES ... DEPS ...): one static library per layer,
# target semgraph_<layer>, alias semgraph::<layer>, headers under <layer>/include.
function(semgraph_add_layer)
  cmake_parse_arguments(A "" "NAME" "SOURCES;DEPS" ${ARGN})
  set(t semgraph_${A_NAME})
  add_library(${t} STATIC ${A_SOURCES})
  add_library(semgraph::${A_NAME} ALIAS ${t})
  set_target_properties(${t} PROPERTIES EXPORT_NAME ${A_NAME} POSITION_INDEPENDENT_CODE ON)
  target_include_directories(${t} PUBLIC
      $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
      $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_compile_features(${t} PUBLIC cxx_std_20)
  target_link_libraries(${t} PUBLIC ${A_DEPS} PRIVATE $<BUILD_INTERFACE:semgraph_warnings>)
  if(SEMGRAPH_EXPENSIVE_CHECKS)
    target_compile_definitions(${t} PUBLIC SEMGRAPH_EXPENSIVE_CHECKS=1)
  endif()
endfunction()

# semgraph_add_test(NAME <name> SOURCES ... [DEPS ...]): a GoogleTest binary registered with ctest.
function(semgraph_add_test)
  cmake_parse_arguments(A "" "NAME" "SOURCES;DEPS" ${ARGN})
  add_executable(${A_NAME} ${A_SOURCES})
  target_link_libraries(${A_NAME} PRIVATE ${A_DEPS} semgraph_test_support GTest::gtest GTest::gtest_main
                        semgraph_warnings)
  # Allocation-counting tests replace the global operator new/delete with malloc/free; GCC 12
  # at -O3 inlines them and reports a false -Wmismatched-new-delete on that pairing.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${A_NAME} PRIVATE -Wno-mismatched-new-delete)
  endif()
  include(GoogleTest)
  gtest_discover_tests(${A_NAME} TEST_PREFIX "${A_NAME}." DISCOVERY_TIMEOUT 60 PROPERTIES TIMEOUT 600)
endfunction()

# semgraph_add_bench(NAME <name> SOURCES ... [DEPS ...])
function(semgraph_add_bench)
  cmake_parse_arguments(A "" "NAME" "SOURCES;DEPS" ${ARGN})
  add_executable(${A_NAME} ${A_SOURCES})
  target_link_libraries(${A_NAME} PRIVATE ${A_DEPS} benchmark::benchmark semgraph_warnings)
endfunction()

# semgraph_add_tests_in_dir(PREFIX <p> DEPS ...): one GoogleTest binary per *_test.cc in the
# current folder, named <p>_<file stem>, so adding a test file needs no CMake edit.
function(semgraph_add_tests_in_dir)
  cmake_parse_arguments(A "" "PREFIX" "DEPS" ${ARGN})
  file(GLOB tests CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*_test.cc)
  foreach(src ${tests})
    get_filename_component(stem ${src} NAME_WE)
    semgraph_add_test(NAME ${A_PREFIX}_${stem} SOURCES ${src} DEPS ${A_DEPS})
  endforeach()
endfunction()

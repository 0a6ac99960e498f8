# Helpers that keep the folder CMakeLists.txt files declarative.

# Warnings as errors, for our own targets only: linked PRIVATE, never exported to consumers.
add_library(semgraph_warnings INTERFACE)
target_compile_options(semgraph_warnings INTERFACE -Wall -Wextra -Werror -Wpedantic)
# GCC 12 at -O3 reports a false -Wrestrict on "literal" + std::string (GCC PR 105329).
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  target_compile_options(semgraph_warnings INTERFACE -Wno-restrict)
endif()

include(GenerateExportHeader)

# semgraph_library_properties(<target> <layer>): what every installed library of semgraph gets.
#  - Static or shared as BUILD_SHARED_LIBS says (shared: VERSION = the project version and
#    SOVERSION = MAJOR.MINOR, since compatibility is promised within a minor version, as the
#    package's config-version file says).
#  - Symbols hidden unless exported: the headers mark the API with SEMGRAPH_<LAYER>_EXPORT, from
#    semgraph/<layer>/export.h, generated here (GenerateExportHeader) into the build tree and
#    installed with the other headers. A static build defines SEMGRAPH_<LAYER>_STATIC_DEFINE for
#    itself and its users (the macros are then empty).
function(semgraph_library_properties t layer)
  string(TOUPPER ${layer} LAYER)
  set_target_properties(${t} PROPERTIES
      POSITION_INDEPENDENT_CODE ON
      CXX_VISIBILITY_PRESET hidden
      VISIBILITY_INLINES_HIDDEN ON
      VERSION ${PROJECT_VERSION}
      SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR}
      INSTALL_RPATH "$ORIGIN")  # shared: each library finds the layers below it beside itself
  set(dir ${CMAKE_CURRENT_BINARY_DIR}/export_include)
  generate_export_header(${t}
      BASE_NAME SEMGRAPH_${LAYER}
      EXPORT_FILE_NAME ${dir}/semgraph/${layer}/export.h)
  target_include_directories(${t} PUBLIC $<BUILD_INTERFACE:${dir}>)
  get_target_property(type ${t} TYPE)
  if(NOT type STREQUAL "SHARED_LIBRARY")
    target_compile_definitions(${t} PUBLIC SEMGRAPH_${LAYER}_STATIC_DEFINE)
  endif()
  set_property(GLOBAL APPEND PROPERTY SEMGRAPH_EXPORT_HEADER_DIRS ${dir})
endfunction()

# semgraph_add_layer(NAME <layer> SOURCES ... DEPS ...): one library per layer (static, or
# shared with BUILD_SHARED_LIBS), target semgraph_<layer>, alias semgraph::<layer>, headers
# under <layer>/include plus the generated semgraph/<layer>/export.h.
function(semgraph_add_layer)
  cmake_parse_arguments(A "" "NAME" "SOURCES;DEPS" ${ARGN})
  set(t semgraph_${A_NAME})
  add_library(${t} ${A_SOURCES})
  add_library(semgraph::${A_NAME} ALIAS ${t})
  set_target_properties(${t} PROPERTIES EXPORT_NAME ${A_NAME})
  semgraph_library_properties(${t} ${A_NAME})
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

# semgraph_add_tests_in_dir(PREFIX <p> DEPS ... [EXCLUDE <file> ...]): one GoogleTest binary per
# *_test.cc in the current folder, named <p>_<file stem>, so adding a test file needs no CMake
# edit. EXCLUDE names files (e.g. peer-library tests) that the folder adds on its own.
function(semgraph_add_tests_in_dir)
  cmake_parse_arguments(A "" "PREFIX" "DEPS;EXCLUDE" ${ARGN})
  file(GLOB tests CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*_test.cc)
  foreach(src ${tests})
    get_filename_component(name ${src} NAME)
    if(name IN_LIST A_EXCLUDE)
      continue()
    endif()
    get_filename_component(stem ${src} NAME_WE)
    semgraph_add_test(NAME ${A_PREFIX}_${stem} SOURCES ${src} DEPS ${A_DEPS})
  endforeach()
endfunction()

# semgraph_unity(<target> <batch>): compile the target's sources as unity batches of <batch>
# files. The big libraries instantiate the same Eigen and evaluator templates in every file, and
# CI compiles them four times (Release, shared, ASan, TSan): batched, they compile about three
# times faster. A name clash between two files of a batch (their anonymous namespaces merge) is
# a compile error. -DSEMGRAPH_NO_UNITY=ON compiles every file on its own (e.g. to debug one).
option(SEMGRAPH_NO_UNITY "Compile every file on its own (no unity batches)" OFF)
function(semgraph_unity target batch)
  if(NOT SEMGRAPH_NO_UNITY)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE ${batch})
  endif()
endfunction()

# The ROS 1 bag and rosbag2 sqlite3 readers, against bags written at test time by independent
# writers: tests/ros/fixtures/write_ros1_bags.py (Debian's python3-rosbag with genpy messages;
# Python's sqlite3). The script needs Debian's own python3 (the ROS 1 Python packages live in its
# dist-packages), so it is looked up in /usr/bin first. A missing package fails the fixture, and
# with it the tests: scripts/setup.sh --ros installs them.
find_program(SEMGRAPH_DEBIAN_PYTHON3 NAMES python3 PATHS /usr/bin NO_DEFAULT_PATH)
if(NOT SEMGRAPH_DEBIAN_PYTHON3)
  find_program(SEMGRAPH_DEBIAN_PYTHON3 NAMES python3 REQUIRED)
endif()
find_package(BZip2 REQUIRED)
find_package(SQLite3 REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(SEMGRAPH_TEST_LZ4 REQUIRED IMPORTED_TARGET liblz4)

# With Foxglove's samples (ros.fixtures, CMakeLists.txt) the script cross-checks its writers
# against them and writes a sqlite3 bag of Foxglove's CDR bytes.
set(SEMGRAPH_ROS_BAG_FIXTURES ${CMAKE_CURRENT_BINARY_DIR}/bag_fixtures)
add_test(NAME ros_bag_fixtures
         COMMAND ${SEMGRAPH_DEBIAN_PYTHON3} ${CMAKE_CURRENT_SOURCE_DIR}/fixtures/write_ros1_bags.py
                 ${SEMGRAPH_ROS_BAG_FIXTURES} --foxglove ${SEMGRAPH_ROS_FIXTURES})
set_tests_properties(ros_bag_fixtures PROPERTIES FIXTURES_SETUP ros_bag_fixtures
                     FIXTURES_REQUIRED ros_fixtures TIMEOUT 300 LABELS ros)

include(GoogleTest)
# open_bag_test reads the MCAP bags of ros.fixtures too (and skips those cases without them).
foreach(name ros1_bag_reader sqlite3_bag_reader open_bag)
  set(t ros_${name}_test)
  add_executable(${t} ${name}_test.cc)
  target_link_libraries(${t} PRIVATE semgraph::ros semgraph_test_support GTest::gtest
                        GTest::gtest_main semgraph_warnings yaml-cpp BZip2::BZip2
                        SQLite::SQLite3 PkgConfig::SEMGRAPH_TEST_LZ4)
  target_compile_definitions(${t} PRIVATE
      SEMGRAPH_ROS_BAG_FIXTURES="${SEMGRAPH_ROS_BAG_FIXTURES}"
      SEMGRAPH_ROS_TEST_SCRATCH="${CMAKE_CURRENT_BINARY_DIR}/scratch_${name}"
      SEMGRAPH_ROS_FIXTURES="${SEMGRAPH_ROS_FIXTURES}")
  gtest_discover_tests(${t} TEST_PREFIX "${t}." DISCOVERY_TIMEOUT 60
                       PROPERTIES TIMEOUT 600 FIXTURES_REQUIRED ros_bag_fixtures LABELS ros)
endforeach()

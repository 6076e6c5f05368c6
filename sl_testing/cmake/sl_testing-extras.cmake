# The test block every package of the stack writes, once (sl_testing's CFG_EXTRAS). In a package:
#   if(CATKIN_ENABLE_TESTING)
#     find_package(sl_testing REQUIRED)
#     sl_package_tests(<pkg>_test test/a_test.cpp ... LIBRARIES <pkg>_core)
#     sl_rostest_client(foo_rostest test/foo_rostest.cpp TEST test/foo.test DEPENDS foo_node)
#   endif()

# sl_package_tests(<target> <source>... [LIBRARIES <lib>...] [INCLUDE_DIRS <dir>...])
# The package's one gtest binary (gtest_main linked), and roslaunch's check of every launch file in
# launch/ (arguments, includes, node types, dependencies declared in package.xml) if there is one.
# A macro: find_package(rostest) must define add_rostest* in the package's scope.
macro(sl_package_tests _slt_target)
  cmake_parse_arguments(_slt "" "" "LIBRARIES;INCLUDE_DIRS" ${ARGN})
  find_package(rostest REQUIRED)
  if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/launch)
    find_package(roslaunch REQUIRED)
    roslaunch_add_file_check(launch)
  endif()
  catkin_add_gtest(${_slt_target} ${_slt_UNPARSED_ARGUMENTS})
  if(TARGET ${_slt_target})
    target_include_directories(${_slt_target} PRIVATE ${_slt_INCLUDE_DIRS} ${sl_testing_INCLUDE_DIRS})
    target_link_libraries(${_slt_target} ${_slt_LIBRARIES} GTest::gtest_main)
  endif()
endmacro()

# sl_rostest_client(<target> <source>... [TEST <test file>] [LIBRARIES <lib>...]
#                   [INCLUDE_DIRS <dir>...] [DEPENDS <target>...])
# The gtest client of a rostest, built against catkin_INCLUDE_DIRS/LIBRARIES and sl_testing's
# headers. With TEST, `make run_tests` runs <test file>; without, the client is only built (by
# `make tests`) and each run is added with add_rostest(<file> ARGS ... DEPENDENCIES <target>), as
# for rostests that take launch arguments. DEPENDS: what the rostest starts, each where it is a
# target (another package's target exists only if the workspace configures that package first).
function(sl_rostest_client target)
  cmake_parse_arguments(ARG "" "TEST" "LIBRARIES;INCLUDE_DIRS;DEPENDS" ${ARGN})
  if(ARG_TEST)
    add_rostest_gtest(${target} ${ARG_TEST} ${ARG_UNPARSED_ARGUMENTS})
  else()
    catkin_add_executable_with_gtest(${target} ${ARG_UNPARSED_ARGUMENTS} EXCLUDE_FROM_ALL)
    if(TARGET tests)
      add_dependencies(tests ${target})
    endif()
  endif()
  target_include_directories(${target} PRIVATE ${ARG_INCLUDE_DIRS} ${catkin_INCLUDE_DIRS} ${sl_testing_INCLUDE_DIRS})
  target_link_libraries(${target} ${ARG_LIBRARIES} ${catkin_LIBRARIES})
  foreach(_dep ${ARG_DEPENDS})
    if(TARGET ${_dep})
      add_dependencies(${target} ${_dep})
    endif()
  endforeach()
endfunction()

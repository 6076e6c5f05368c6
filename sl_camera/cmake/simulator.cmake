# The projector-camera simulator: scenes, renderer, contact signal (ROS-free core), the
# sl_camera/sim_camera nodelet and sim_camera_node, the sl_render tool, the sl_camera_benchmark
# benchmark and the tests. Included by ../CMakeLists.txt.

list(APPEND SL_CAMERA_CORE_SOURCES
  src/sim/scene.cpp
  src/sim/sim_settings.cpp
  src/sim/renderer.cpp
  src/sim/lanes.cpp
  src/sim/contact.cpp
)
# The renderer's kernels: no errno from sqrt and no trapping maths, so that their loops vectorise.
set_source_files_properties(src/sim/lanes.cpp PROPERTIES COMPILE_OPTIONS "-fno-math-errno;-fno-trapping-math")

list(APPEND SL_CAMERA_NODELET_SOURCES src/nodelets/sim_camera_nodelet.cpp)

list(APPEND SL_CAMERA_TEST_SOURCES
  test/scene_test.cpp
  test/sim_settings_test.cpp
  test/renderer_test.cpp
  test/contact_test.cpp
)

# Executables and the benchmark (after the libraries exist).
function(sl_camera_simulator_targets)
  add_executable(sim_camera_node src/sim_camera_node.cpp)
  target_include_directories(sim_camera_node PRIVATE ${catkin_INCLUDE_DIRS})
  target_link_libraries(sim_camera_node ${catkin_LIBRARIES})

  add_executable(sl_render src/tools/sl_render.cpp)
  target_link_libraries(sl_render sl_camera_core)

  install(TARGETS sim_camera_node sl_render RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

  # Google Benchmark (libbenchmark-dev): one frame of the room scene. Built, never run as a test:
  #   rosrun sl_camera sl_camera_benchmark   (or devel/lib/sl_camera/sl_camera_benchmark)
  if(benchmark_FOUND)
    add_executable(sl_camera_benchmark benchmark/render_benchmark.cpp)
    target_link_libraries(sl_camera_benchmark sl_camera_core benchmark::benchmark)
    target_compile_definitions(sl_camera_benchmark PRIVATE
      SL_CAMERA_SCENES_DIR="${CMAKE_CURRENT_SOURCE_DIR}/scenes"
      SL_PROJECTOR_CONFIG_DIR="${sl_projector_SOURCE_PREFIX}/config")
  else()
    message(STATUS "sl_camera: Google Benchmark not found (libbenchmark-dev), sl_camera_benchmark not built")
  endif()
endfunction()

# Rostests (with CATKIN_ENABLE_TESTING).
function(sl_camera_simulator_tests)
  add_rostest_gtest(sim_camera_rostest test/sim_camera.test test/sim_camera_rostest.cpp)
  target_include_directories(sim_camera_rostest PRIVATE ${catkin_INCLUDE_DIRS})
  target_link_libraries(sim_camera_rostest ${catkin_LIBRARIES})
  target_compile_definitions(sim_camera_rostest PRIVATE
    SL_CAMERA_SCENES_DIR="${CMAKE_CURRENT_SOURCE_DIR}/scenes"
    SL_PROJECTOR_CONFIG_DIR="${sl_projector_SOURCE_PREFIX}/config")
  add_dependencies(sim_camera_rostest sim_camera_node sl_camera_nodelets)
  # The same client on a simulated clock (only its SimCameraClock tests).
  add_rostest(test/sim_camera_clock.test DEPENDENCIES sim_camera_rostest)
endfunction()

# Calibration: plane calibration (per-primitive linear and rational depth tables) and full
# projector-camera calibration (camera from checkerboards, projector as an inverse camera), their
# command-line tools and the live calibration nodelet. Included by ../CMakeLists.txt after
# sl_decoder_core exists. Calibration in simulation (sl_calibrate_sim, the calibration_sim_stage
# nodelet) and the calibration tests, which render, are in sl_evaluation.
#
#   sl_calibration_core       ROS-free library (OpenCV calib3d, Eigen, yaml-cpp)
#   sl_calibrate_plane        plane calibration from images, folders or bags with known distances
#   sl_calibrate_full         full calibration from checkerboard and pattern images
#   sl_calibration_nodelets   nodelet sl_decoder/calibration (live procedure)
#   calibration_node          loads the calibration nodelet

find_package(PkgConfig REQUIRED)
pkg_check_modules(SL_CALIBRATION_YAML REQUIRED yaml-cpp)
find_package(std_srvs REQUIRED)
find_package(std_msgs REQUIRED)
# Bags are optional: without librosbag-dev the tools read images and folders only.
find_package(rosbag QUIET)

add_library(sl_calibration_core
  src/calibration/common.cpp
  src/calibration/optimizer.cpp
  src/calibration/plane_calibration.cpp
  src/calibration/camera_calibration.cpp
  src/calibration/projector_calibration.cpp
  src/calibration/full_calibration.cpp
)
target_include_directories(sl_calibration_core PUBLIC include ${OpenCV_INCLUDE_DIRS} ${EIGEN3_INCLUDE_DIRS}
  PRIVATE ${SL_CALIBRATION_YAML_INCLUDE_DIRS})
target_link_libraries(sl_calibration_core sl_decoder_core opencv_calib3d ${OpenCV_LIBS}
  ${SL_CALIBRATION_YAML_LIBRARIES})

# Command-line tools (no ROS master needed).
add_executable(sl_calibrate_plane src/tools/sl_calibrate_plane.cpp)
target_link_libraries(sl_calibrate_plane sl_calibration_core)
if(rosbag_FOUND)
  target_compile_definitions(sl_calibrate_plane PRIVATE SL_CALIBRATION_WITH_ROSBAG=1)
  target_include_directories(sl_calibrate_plane PRIVATE ${rosbag_INCLUDE_DIRS} ${catkin_INCLUDE_DIRS})
  target_link_libraries(sl_calibrate_plane ${rosbag_LIBRARIES} ${catkin_LIBRARIES})
else()
  message(STATUS "sl_decoder: rosbag not found (librosbag-dev): sl_calibrate_plane reads images and folders only")
endif()
add_executable(sl_calibrate_full src/tools/sl_calibrate_full.cpp)
target_link_libraries(sl_calibrate_full sl_calibration_core)

# Live procedure: the calibration nodelet and its node.
add_library(sl_calibration_nodelets src/nodelets/calibration_nodelet.cpp)
target_include_directories(sl_calibration_nodelets PRIVATE ${catkin_INCLUDE_DIRS} ${std_srvs_INCLUDE_DIRS}
  ${std_msgs_INCLUDE_DIRS})
target_link_libraries(sl_calibration_nodelets sl_calibration_core ${catkin_LIBRARIES})
add_executable(calibration_node src/nodes/calibration_node.cpp)
target_include_directories(calibration_node PRIVATE ${catkin_INCLUDE_DIRS})
target_link_libraries(calibration_node ${catkin_LIBRARIES})

install(TARGETS sl_calibration_core sl_calibration_nodelets
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_GLOBAL_BIN_DESTINATION})
install(TARGETS sl_calibrate_plane sl_calibrate_full calibration_node
  RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

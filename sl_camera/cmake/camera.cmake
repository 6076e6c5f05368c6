# Real cameras: V4L2 (OpenCV), GenICam through Aravis (optional), image folder / video player,
# the capture thread, the sl_camera/camera nodelet and camera_node. Included by ../CMakeLists.txt.

find_package(Threads REQUIRED)

list(APPEND SL_CAMERA_CORE_SOURCES
  src/camera/player_source.cpp
  src/camera/start_gate.cpp
  src/camera/unreadable_files.cpp
  src/camera/v4l2_source.cpp
  src/camera/capture_thread.cpp
  src/camera/camera_config.cpp
  src/camera/capture_status.cpp
)
list(APPEND SL_CAMERA_CORE_LIBRARIES Threads::Threads)

# Aravis (libaravis-dev) is optional: without it the aravis back-end is left out and the nodelet
# refuses backend:=aravis with a message saying so.
pkg_check_modules(ARAVIS QUIET IMPORTED_TARGET aravis-0.8)
if(ARAVIS_FOUND)
  message(STATUS "sl_camera: Aravis ${ARAVIS_VERSION} found, building the GenICam (aravis) camera back-end")
  list(APPEND SL_CAMERA_CORE_SOURCES src/camera/aravis_source.cpp)
  list(APPEND SL_CAMERA_CORE_LIBRARIES PkgConfig::ARAVIS)
  set_source_files_properties(src/camera/camera_config.cpp PROPERTIES COMPILE_DEFINITIONS SL_CAMERA_HAVE_ARAVIS)
else()
  message(STATUS "sl_camera: aravis-0.8 not found by pkg-config, building without the GenICam (aravis) camera back-end "
                 "(install libaravis-dev to add it)")
endif()

list(APPEND SL_CAMERA_NODELET_SOURCES
  src/nodelets/camera_params.cpp
  src/nodelets/camera_diagnostics.cpp
  src/nodelets/camera_image.cpp
  src/nodelets/camera_nodelet.cpp)

list(APPEND SL_CAMERA_TEST_SOURCES
  test/camera_player_test.cpp
  test/camera_capture_thread_test.cpp
  test/camera_v4l2_test.cpp
  test/camera_config_test.cpp
  test/camera_status_test.cpp
)
if(ARAVIS_FOUND)
  list(APPEND SL_CAMERA_TEST_SOURCES test/camera_aravis_test.cpp)
endif()

# Executables (after the libraries exist).
function(sl_camera_camera_targets)
  sl_add_node(camera_node)
  install(TARGETS camera_node RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
endfunction()

# Rostests (with CATKIN_ENABLE_TESTING).
function(sl_camera_camera_tests)
  set(_started camera_node sl_camera_nodelets)
  sl_rostest_client(camera_player_rostest test/camera_player_rostest.cpp TEST test/camera_player.test
    INCLUDE_DIRS ${OpenCV_INCLUDE_DIRS} LIBRARIES ${OpenCV_LIBS} DEPENDS ${_started})
  if(ARAVIS_FOUND)
    sl_rostest_client(camera_aravis_rostest test/camera_aravis_rostest.cpp TEST test/camera_aravis.test
      DEPENDS ${_started})
    # A GigE Vision camera on 127.0.0.1: arv-fake-gv-camera-0.8 (Debian package aravis-tools).
    find_program(ARV_FAKE_GV_CAMERA arv-fake-gv-camera-0.8)
    find_program(ARV_TOOL arv-tool-0.8)
    if(ARV_FAKE_GV_CAMERA AND ARV_TOOL)
      sl_rostest_client(camera_fake_gv_rostest test/camera_fake_gv_rostest.cpp TEST test/camera_fake_gv.test
        DEPENDS ${_started})
    else()
      message(WARNING "sl_camera: arv-fake-gv-camera-0.8 or arv-tool-0.8 not found, skipping the camera_fake_gv "
                      "rostest (install aravis-tools and aravis-tools-cli)")
    endif()
  endif()
endfunction()

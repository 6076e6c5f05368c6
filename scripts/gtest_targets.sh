# The gtest binary of each package (one per package), for make test-unit and make test-asan.
# shellcheck disable=SC2034
gtest_targets=(sl_projector_test sl_camera_test sl_sim_test sl_decoder_test sl_calibration_test sl_evaluation_test
               sl_obstacle_test sl_navigation_test create_driver_test sl_bringup_test sl_testing_test)

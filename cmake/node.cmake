# The ROS shell: node units, cloth_sim_node, pin_teleop and their tests
# (included from CMakeLists.txt, after catkin_package).
# ---------------------------------------------------------------------------------------------
# cloth_sim_ros: the node's units (names, options, conversions, tf, markers, monitoring,
# diagnostics, reconfigure, handles, teleop logic); pure ones are unit-tested without a master.
include_directories(SYSTEM ${catkin_INCLUDE_DIRS})  # node targets only: included last

add_library(cloth_sim_ros
  src/node/options.cpp
  src/node/conversions.cpp
  src/node/frame_resolver.cpp
  src/node/marker_builder.cpp
  src/node/step_monitor.cpp
  src/node/log_throttle.cpp
  src/node/pin_handles.cpp
  src/node/sim_clock.cpp
  src/node/grasp_frames.cpp
  src/node/grasp_output.cpp
  src/node/point_cloud.cpp
  src/node/render_pacer.cpp
  src/node/reconfigure_bridge.cpp
  src/node/diagnostics_report.cpp
  src/node/urdf_colliders.cpp
  src/node/body_messages.cpp
)
target_include_directories(cloth_sim_ros PUBLIC include)
target_link_libraries(cloth_sim_ros PUBLIC cloth_sim_core ${catkin_LIBRARIES})
add_dependencies(cloth_sim_ros ${PROJECT_NAME}_generate_messages_cpp ${PROJECT_NAME}_gencfg
                 ${catkin_EXPORTED_TARGETS})

add_executable(cloth_sim_node
  src/node/cloth_sim_node_main.cpp
  src/node/cloth_sim_node.cpp
  src/node/node_inputs.cpp
  src/node/node_time.cpp
  src/node/node_grasps.cpp
  src/node/node_colliders.cpp
  src/node/node_state.cpp
)
target_link_libraries(cloth_sim_node cloth_sim_ros)

# pin_teleop: a keyboard tool that drives the node's pins (tools/pin_teleop).
add_library(cloth_sim_teleop STATIC tools/pin_teleop/pin_teleop.cpp)
target_include_directories(cloth_sim_teleop PUBLIC tools/pin_teleop)
target_link_libraries(cloth_sim_teleop PUBLIC cloth_sim_ros)
add_executable(pin_teleop tools/pin_teleop/pin_teleop_main.cpp)
target_link_libraries(pin_teleop cloth_sim_teleop)

# The grasp demo's scripted gripper (launch/grasp_demo.launch).
catkin_install_python(PROGRAMS tools/gripper/scripted_gripper.py tools/gripper/pinch_gripper.py
  DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

install(TARGETS cloth_sim_ros cloth_sim_node pin_teleop
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
install(DIRECTORY launch rviz DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})

# ---------------------------------------------------------------------------------------------
# Tests: gtest for the pure units (no master), rostest with a real master for the node.
if(CATKIN_ENABLE_TESTING)
  set(NODE_UNIT_TESTS
    options_test conversions_test frame_resolver_test marker_builder_test step_monitor_test
    pin_handles_test reconfigure_cfg_test grasp_frames_test grasp_output_test render_pacer_test
    reconfigure_bridge_test diagnostics_report_test urdf_colliders_test body_messages_test)
  foreach(t ${NODE_UNIT_TESTS})
    catkin_add_gtest(node_${t} test/node/${t}.cpp WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
    target_link_libraries(node_${t} cloth_sim_ros GTest::gtest_main)
    target_compile_definitions(node_${t} PRIVATE CLOTH_SIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  endforeach()

  catkin_add_gtest(pin_teleop_test test/tools/pin_teleop_test.cpp)
  target_link_libraries(pin_teleop_test cloth_sim_teleop GTest::gtest_main)

  find_package(rostest REQUIRED)
  # Helpers of the rostests, compiled once for all of them (built only with the tests).
  add_library(cloth_sim_rostest_util STATIC EXCLUDE_FROM_ALL test/node/ros_test_util.cpp)
  target_link_libraries(cloth_sim_rostest_util PUBLIC cloth_sim_ros GTest::gtest)
  target_compile_definitions(cloth_sim_rostest_util PUBLIC
                             CLOTH_SIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  set(NODE_ROSTESTS integration bad_input bad_input_random reconfigure grasp robot pinch tf_buffer
      freeze reconfigure_random)
  foreach(t ${NODE_ROSTESTS})
    add_rostest_gtest(node_${t}_test test/node/${t}.test test/node/${t}_test.cpp)
    target_link_libraries(node_${t}_test cloth_sim_rostest_util)
    target_compile_definitions(node_${t}_test PRIVATE
                               CLOTH_SIM_NODE_EXE="$<TARGET_FILE:cloth_sim_node>")
    add_dependencies(node_${t}_test cloth_sim_node)
  endforeach()
  # The same pinch test binary with the fingers' friction at 0.1: the cloth slips out.
  add_rostest(test/node/pinch_slip.test DEPENDENCIES node_pinch_test)
  # The grasp and pinch demos as users launch them, headless; the checks are Python scripts.
  add_rostest(test/node/grasp_demo.test DEPENDENCIES cloth_sim_node)
  add_rostest(test/node/pinch_demo.test DEPENDENCIES cloth_sim_node)
endif()

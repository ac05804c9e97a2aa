# Tools built on the core: headless runner and benchmark (included from CMakeLists.txt).
# ---------------------------------------------------------------------------------------------
add_library(cloth_sim_tools STATIC tools/runner/step_log.cpp tools/runner/fold_script.cpp)
target_include_directories(cloth_sim_tools PUBLIC tools/runner)
target_link_libraries(cloth_sim_tools PUBLIC cloth_sim_core)

add_executable(cloth_sim_run tools/runner/run_scene.cpp)
target_link_libraries(cloth_sim_run cloth_sim_tools CLI11::CLI11)

if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(run_scene_test test/tools/run_scene_test.cpp)
  target_link_libraries(run_scene_test GTest::gtest_main)
  add_dependencies(run_scene_test cloth_sim_run)
  target_compile_definitions(run_scene_test PRIVATE
    CLOTH_SIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    CLOTH_SIM_RUN_BINARY="$<TARGET_FILE:cloth_sim_run>")
  catkin_add_gtest(stability_test test/tools/stability_test.cpp)
  target_link_libraries(stability_test cloth_sim_bench_lib GTest::gtest_main)
  target_include_directories(stability_test PRIVATE tools/bench)
endif()

add_library(cloth_sim_bench_lib STATIC
  tools/bench/cases.cpp tools/bench/reference.cpp tools/bench/speed.cpp tools/bench/stability.cpp
  tools/bench/floor.cpp tools/bench/scaling.cpp tools/bench/accuracy.cpp tools/bench/drift.cpp
  tools/bench/threads.cpp tools/bench/precision.cpp tools/bench/self_collision_set.cpp)
target_link_libraries(cloth_sim_bench_lib PUBLIC cloth_sim_core)
# The randomized self-contact set shares its cases with the tests (header-only).
target_include_directories(cloth_sim_bench_lib PRIVATE test/core/collision)
add_executable(cloth_sim_bench tools/bench/bench_main.cpp)
target_link_libraries(cloth_sim_bench cloth_sim_bench_lib CLI11::CLI11)
target_compile_definitions(cloth_sim_bench PRIVATE CLOTH_SIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")

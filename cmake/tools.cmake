# Tools built on the core: headless runner (included from CMakeLists.txt).
# ---------------------------------------------------------------------------------------------
# Tools
add_executable(cloth_sim_run tools/run_scene.cpp)
target_link_libraries(cloth_sim_run cloth_sim_core CLI11::CLI11)


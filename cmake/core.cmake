# cloth_sim_core and its tests (included from CMakeLists.txt).
# ---------------------------------------------------------------------------------------------
# cloth_sim_core: C++17 + Eigen + yaml-cpp, no ROS header anywhere.
add_library(cloth_sim_core
  src/core/model.cpp
  src/core/pins.cpp
  src/core/dof_map.cpp
  src/core/spring_kernels.cpp
  src/core/sparse_pattern.cpp
  src/core/cholmod_factor.cpp
  src/core/triangular_kernels.cpp
  src/core/local_step.cpp
  src/core/scalar_system.cpp
  src/core/implicit_euler.cpp
  src/core/explicit_solvers.cpp
  src/core/newton_solver.cpp
  src/core/local_global_solver.cpp
  src/core/lbfgs_solver.cpp
  src/core/local_global_3n_solver.cpp
  src/core/solver.cpp
  src/core/colliders.cpp
  src/core/grid_builder.cpp
  src/core/simulation.cpp
  src/core/scene.cpp
  src/core/triangle_mesh.cpp
  src/core/mesh_builder.cpp
  src/core/spatial_hash.cpp
  src/core/contact_response.cpp
  src/core/mesh_obstacle.cpp
  src/core/sphere_impacts.cpp
  src/core/contact_forces.cpp
)
# CHOLMOD (SuiteSparse, Debian libsuitesparse-dev): no CMake package in Debian 12, so found by
# hand. Private: its headers stay in src/core/cholmod_factor.cpp.
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
find_library(CHOLMOD_LIBRARY cholmod REQUIRED)
target_include_directories(cloth_sim_core PUBLIC include ${EIGEN3_INCLUDE_DIRS})
find_package(tinyobjloader REQUIRED)
target_include_directories(cloth_sim_core PRIVATE ${CHOLMOD_INCLUDE_DIR})
target_link_libraries(cloth_sim_core PUBLIC yaml-cpp
                      PRIVATE tinyobjloader::tinyobjloader_double ${CHOLMOD_LIBRARY})
set_target_properties(cloth_sim_core PROPERTIES POSITION_INDEPENDENT_CODE ON)


# ---------------------------------------------------------------------------------------------
# Core tests: one gtest per core module, no ROS master.
if(CATKIN_ENABLE_TESTING)
  set(CORE_TESTS
    model_test pins_test spring_kernels_test implicit_euler_test explicit_solvers_test
    newton_solver_test local_global_solver_test colliders_test grid_builder_test
    simulation_test scene_test triangle_mesh_test mesh_builder_test mesh_obstacle_test
    sphere_impacts_test dynamic_spheres_test cholmod_factor_test triangular_kernels_test
    local_step_test scalar_system_test local_global_3n_solver_test)
  foreach(t ${CORE_TESTS})
    catkin_add_gtest(${t} test/core/${t}.cpp test/core/test_util.cpp
                     WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
    target_link_libraries(${t} cloth_sim_core GTest::gtest_main)
    target_compile_definitions(${t} PRIVATE CLOTH_SIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  endforeach()
endif()


# ---------------------------------------------------------------------------------------------
# Per-particle strain field, for display by the ROS node (issue 3).
target_sources(cloth_sim_core PRIVATE src/core/strain_field.cpp)
if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(strain_field_test test/core/strain_field_test.cpp)
  target_link_libraries(strain_field_test cloth_sim_core GTest::gtest_main)
endif()

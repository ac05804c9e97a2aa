# cloth_sim_core and its tests (included from CMakeLists.txt).
# The folders are the layers, each depending only on the ones below it:
#   io -> simulation -> solvers -> collision -> model -> linalg
# and settings (the table of tunables and their ranges) below them all.
# ---------------------------------------------------------------------------------------------
# cloth_sim_core: C++17 + Eigen + yaml-cpp + CHOLMOD, no ROS header anywhere.
add_library(cloth_sim_core
  src/core/settings/range.cpp
  src/core/settings/settings_table.cpp
  src/core/linalg/block_pattern.cpp
  src/core/linalg/cholmod_factor.cpp
  src/core/linalg/supernodal_solves.cpp
  src/core/linalg/solve_partition.cpp
  src/core/linalg/parallel.cpp
  src/core/model/model.cpp
  src/core/model/pins.cpp
  src/core/model/free_particles.cpp
  src/core/model/spring_kernels.cpp
  src/core/model/strain_field.cpp
  src/core/model/material.cpp
  src/core/model/grid_builder.cpp
  src/core/model/triangle_mesh.cpp
  src/core/model/mesh_builder.cpp
  src/core/model/mesh_file.cpp
  src/core/collision/body_collider.cpp
  src/core/collision/body_contact.cpp
  src/core/collision/colliders.cpp
  src/core/collision/contact_projection.cpp
  src/core/collision/contact_forces.cpp
  src/core/collision/contact_detection.cpp
  src/core/collision/sphere_impacts.cpp
  src/core/collision/spatial_hash.cpp
  src/core/collision/mesh_obstacle.cpp
  src/core/collision/cell_hash.cpp
  src/core/collision/triangle_intersection.cpp
  src/core/collision/primitive_distance.cpp
  src/core/collision/additive_ccd.cpp
  src/core/collision/surface_topology.cpp
  src/core/collision/pair_list.cpp
  src/core/collision/pair_search.cpp
  src/core/collision/proximity_projection.cpp
  src/core/collision/impact_failsafe.cpp
  src/core/collision/contour_untangling.cpp
  src/core/collision/triangle_self_contact.cpp
  src/core/collision/particle_self_contact.cpp
  src/core/collision/self_contact.cpp
  src/core/solvers/solver.cpp
  src/core/solvers/registry.cpp
  src/core/solvers/implicit_euler_problem.cpp
  src/core/solvers/pin_reactions.cpp
  src/core/solvers/midpoint_safeguard.cpp
  src/core/solvers/newton_solver.cpp
  src/core/solvers/local_global/local_step.cpp
  src/core/solvers/local_global/global_system.cpp
  src/core/solvers/local_global/local_global_problem.cpp
  src/core/solvers/local_global/local_global_driver.cpp
  src/core/solvers/local_global/chebyshev_acceleration.cpp
  src/core/solvers/local_global/anderson_acceleration.cpp
  src/core/solvers/local_global/local_global_solver.cpp
  src/core/solvers/local_global/lbfgs_solver.cpp
  src/core/solvers/baselines/explicit_solvers.cpp
  src/core/solvers/baselines/local_global_3n_solver.cpp
  src/core/solvers/baselines/xpbd_solver.cpp
  src/core/simulation/step_report.cpp
  src/core/simulation/grasp_set.cpp
  src/core/simulation/frame_inputs.cpp
  src/core/simulation/substep.cpp
  src/core/simulation/simulation.cpp
  src/core/simulation/simulation_snapshot.cpp
  src/core/simulation/frame_budget.cpp
  src/core/simulation/step_controller.cpp
  src/core/simulation/frame_error.cpp
  src/core/io/scene_fields.cpp
  src/core/io/scene_reader.cpp
  src/core/io/scene_bodies.cpp
  src/core/io/scene_builder.cpp
  src/core/io/scene_overrides.cpp
  src/core/io/scene_limits.cpp
)
# CHOLMOD (SuiteSparse, Debian libsuitesparse-dev): no CMake package in Debian 12, so found by
# hand. Private: its headers stay in src/core/linalg/cholmod_factor.cpp.
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
find_library(CHOLMOD_LIBRARY cholmod REQUIRED)
target_include_directories(cloth_sim_core PUBLIC include ${EIGEN3_INCLUDE_DIRS})
find_package(tinyobjloader REQUIRED)
target_include_directories(cloth_sim_core PRIVATE ${CHOLMOD_INCLUDE_DIR})
target_link_libraries(cloth_sim_core PUBLIC yaml-cpp
                      PRIVATE tinyobjloader::tinyobjloader_double ${CHOLMOD_LIBRARY})
# The kernels' threads (linalg/parallel.h): a small team of std::threads.
find_package(Threads REQUIRED)
target_link_libraries(cloth_sim_core PRIVATE Threads::Threads)
set_target_properties(cloth_sim_core PROPERTIES POSITION_INDEPENDENT_CODE ON)

# ---------------------------------------------------------------------------------------------
# Core tests: one gtest per core module, in the folder of its module, no ROS master.
if(CATKIN_ENABLE_TESTING)
  # Shared test helpers, compiled once (built only with the tests).
  add_library(cloth_sim_core_test_util STATIC EXCLUDE_FROM_ALL test/core/test_util.cpp)
  target_link_libraries(cloth_sim_core_test_util PUBLIC cloth_sim_core GTest::gtest)
  target_include_directories(cloth_sim_core_test_util PUBLIC test/core)
  target_compile_definitions(cloth_sim_core_test_util PRIVATE
                             CLOTH_SIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")

  set(CORE_TESTS
    linalg/cholmod_factor_test linalg/supernodal_solves_test linalg/parallel_test
    model/model_test model/pins_test model/spring_kernels_test model/strain_field_test
    model/grid_builder_test model/triangle_mesh_test model/mesh_builder_test model/mesh_file_test
    collision/colliders_test collision/body_collider_test collision/mesh_obstacle_test collision/sphere_impacts_test
    collision/friction_test
    collision/dynamic_spheres_test collision/contact_random_test
    collision/cell_hash_test collision/triangle_intersection_test collision/self_contact_test
    collision/particle_self_contact_test collision/primitive_distance_test collision/additive_ccd_test
    collision/triangle_self_contact_test collision/pair_list_test collision/self_contact_thin_scenes_test
    collision/self_contact_untangle_test
    collision/self_contact_scenes_test
    solvers/implicit_euler_problem_test solvers/newton_solver_test solvers/revision_cache_test
    solvers/bdf2_test solvers/midpoint_test solvers/midpoint_safeguard_test solvers/registry_test
    solvers/local_global/local_step_test solvers/local_global/global_system_test
    solvers/local_global/local_global_solver_test
    solvers/baselines/explicit_solvers_test solvers/baselines/local_global_3n_solver_test
    solvers/baselines/xpbd_solver_test
    simulation/step_report_test simulation/grasp_set_test simulation/frame_inputs_test
    simulation/simulation_test simulation/substeps_test simulation/frame_budget_test
    simulation/live_limits_test
    simulation/error_control_test simulation/frame_error_test
    simulation/grasp_test simulation/snapshot_test simulation/body_motion_test simulation/threads_test
    io/scene_test io/scene_bodies_test io/bad_scene_random_test
    settings/settings_table_test)
  foreach(path ${CORE_TESTS})
    get_filename_component(t ${path} NAME)
    catkin_add_gtest(${t} test/core/${path}.cpp WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
    target_link_libraries(${t} cloth_sim_core_test_util GTest::gtest_main)
    target_compile_definitions(${t} PRIVATE CLOTH_SIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  endforeach()
endif()

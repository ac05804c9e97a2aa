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

# Bullet's implicit deformable solver as a peer (cloth_sim_bench peers, docs/benchmark.md):
# optional, only the benchmark uses it. Debian's libbullet-dev ships a double build
# (pkg-config bullet-float64, BT_USE_DOUBLE_PRECISION), preferred: cloth_sim and the reference
# run in double; else the float one. Each is used only if a program using the deformable world
# really compiles and links with it. Off: -DCLOTH_SIM_WITH_BULLET=OFF.
option(CLOTH_SIM_WITH_BULLET "build Bullet's deformable solver into cloth_sim_bench if found" ON)
set(CLOTH_SIM_BULLET "")
if(CLOTH_SIM_WITH_BULLET)
  find_package(PkgConfig QUIET)
  if(PkgConfig_FOUND)
    include(CheckCXXSourceCompiles)
    foreach(module bullet-float64 bullet)
      string(MAKE_C_IDENTIFIER "${module}" prefix)
      pkg_check_modules(${prefix} QUIET IMPORTED_TARGET ${module})
      if(${prefix}_FOUND)
        set(CMAKE_REQUIRED_INCLUDES ${${prefix}_INCLUDE_DIRS})
        set(CMAKE_REQUIRED_DEFINITIONS ${${prefix}_CFLAGS_OTHER})
        set(CMAKE_REQUIRED_LIBRARIES ${${prefix}_LINK_LIBRARIES})
        set(CMAKE_REQUIRED_QUIET ON)
        check_cxx_source_compiles("
          #include <BulletSoftBody/btDeformableBodySolver.h>
          #include <BulletSoftBody/btDeformableMultiBodyDynamicsWorld.h>
          #include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
          #include <btBulletDynamicsCommon.h>
          int main() {
            btSoftBodyRigidBodyCollisionConfiguration configuration;
            btCollisionDispatcher dispatcher(&configuration);
            btDbvtBroadphase broadphase;
            btDeformableBodySolver solver;
            btDeformableMultiBodyConstraintSolver constraints;
            btDeformableMultiBodyDynamicsWorld world(&dispatcher, &broadphase, &constraints,
                                                     &configuration, &solver);
            return world.stepSimulation(btScalar(0.01), 0) == 1 ? 0 : 1;
          }" CLOTH_SIM_BULLET_LINKS_${prefix})
        unset(CMAKE_REQUIRED_INCLUDES)
        unset(CMAKE_REQUIRED_DEFINITIONS)
        unset(CMAKE_REQUIRED_LIBRARIES)
        unset(CMAKE_REQUIRED_QUIET)
        if(CLOTH_SIM_BULLET_LINKS_${prefix})
          set(CLOTH_SIM_BULLET ${module})
          set(CLOTH_SIM_BULLET_TARGET PkgConfig::${prefix})
          break()
        endif()
      endif()
    endforeach()
  endif()
endif()
if(CLOTH_SIM_BULLET)
  message(STATUS "cloth_sim_bench peers: Bullet ${${prefix}_VERSION} (${CLOTH_SIM_BULLET})")
else()
  message(STATUS "cloth_sim_bench peers: Bullet not found (libbullet-dev), built without it")
endif()

# peers.cpp alone sees Bullet's headers (and its BT_USE_DOUBLE_PRECISION), only the bench links it.
add_library(cloth_sim_bench_peers STATIC tools/bench/peers.cpp)
target_link_libraries(cloth_sim_bench_peers PUBLIC cloth_sim_bench_lib)
if(CLOTH_SIM_BULLET)
  target_link_libraries(cloth_sim_bench_peers PRIVATE ${CLOTH_SIM_BULLET_TARGET})
  target_compile_definitions(cloth_sim_bench_peers PRIVATE CLOTH_SIM_HAVE_BULLET=1)
  # Bullet's own headers (btModifiedGramSchmidt inlined at -O3) warn about themselves.
  target_compile_options(cloth_sim_bench_peers PRIVATE -Wno-maybe-uninitialized)
endif()

add_executable(cloth_sim_bench tools/bench/bench_main.cpp)
target_link_libraries(cloth_sim_bench cloth_sim_bench_peers cloth_sim_bench_lib CLI11::CLI11)
target_compile_definitions(cloth_sim_bench PRIVATE CLOTH_SIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")

if(CATKIN_ENABLE_TESTING AND CLOTH_SIM_BULLET)
  # Bullet runs the same model: its trajectory approaches the true motion as its step shrinks,
  # and at the same step it matches cloth_sim's converged implicit Euler.
  catkin_add_gtest(peers_test test/tools/peers_test.cpp)
  target_link_libraries(peers_test cloth_sim_bench_peers GTest::gtest_main)
  target_include_directories(peers_test PRIVATE tools/bench)
  target_compile_definitions(peers_test PRIVATE CLOTH_SIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
endif()

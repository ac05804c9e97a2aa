// The headless runner as a user calls it: exit codes, CSV / JSON per step, final positions.
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace {

const std::string kRunner = CLOTH_SIM_RUN_BINARY;
const std::string kScene = std::string(CLOTH_SIM_SOURCE_DIR) + "/config/scenes/hanging.yaml";

int run(const std::string& args) {
  const int status = std::system((kRunner + " " + args + " > /dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

int countLines(const std::string& text) {
  int n = 0;
  for (char c : text) n += c == '\n';
  return n;
}

std::string tmp(const std::string& name) { return ::testing::TempDir() + "cloth_sim_run_" + name; }

TEST(RunScene, WritesOneCsvRowPerStepAndTheFinalPositions) {
  const std::string csv = tmp("steps.csv"), positions = tmp("positions.csv");
  ASSERT_EQ(run("--scene " + kScene + " --duration 0.1 --iterations 3 --csv " + csv +
                " --positions " + positions),
            0);
  const std::string table = slurp(csv);
  EXPECT_EQ(countLines(table), 1 + 6);  // header + 0.1 s at h = 1/60
  EXPECT_EQ(table.rfind("step,time,wall_ms,solve_ms,iterations,convergence,converged,max_strain,"
                        "energy,contacts,status,self_contacts,intersections,self_contact_ms,"
                        "intersection_ms\n", 0), 0u);
  EXPECT_NE(table.find("\n6,0.1,"), std::string::npos);
  EXPECT_NE(table.find(",3,"), std::string::npos);  // the iteration count took effect
  EXPECT_EQ(countLines(slurp(positions)), 1 + 32 * 32);
}

TEST(RunScene, JsonHasTheRunAndEveryStep) {
  const std::string json = tmp("steps.json");
  ASSERT_EQ(run("--scene " + kScene + " --duration 0.05 --dt 0.0125 --solver chebyshev --json " + json), 0);
  const std::string text = slurp(json);
  EXPECT_EQ(text.front(), '{');
  EXPECT_NE(text.find("\"solver\": \"chebyshev\""), std::string::npos);
  EXPECT_NE(text.find("\"time_step\": 0.0125"), std::string::npos);
  EXPECT_NE(text.find("{\"step\": 4,"), std::string::npos);
  EXPECT_EQ(text.find("{\"step\": 5,"), std::string::npos);
  EXPECT_NE(text.find("]}"), std::string::npos);
}

TEST(RunScene, SubstepsSplitEachFrameAndTheRowsStayPerFrame) {
  const std::string csv = tmp("substeps.csv");
  ASSERT_EQ(run("--scene " + kScene + " --duration 0.1 --substeps 4 --iterations 2 --csv " + csv), 0);
  const std::string table = slurp(csv);
  EXPECT_EQ(countLines(table), 1 + 6);
  EXPECT_NE(table.find("\n6,0.1,"), std::string::npos);
}

TEST(RunScene, FoldScriptCountsIntersectionsAndSelfCollisionSwitches) {
  const std::string fold = std::string(CLOTH_SIM_SOURCE_DIR) + "/config/scenes/fold.yaml";
  const std::string on = tmp("fold_on.csv"), off = tmp("fold_off.csv");
  ASSERT_EQ(run("--scene " + fold + " --resolution 12 --duration 0.5 --fold 0.3 --csv " + on), 0);
  ASSERT_EQ(run("--scene " + fold + " --resolution 12 --duration 0.1 --self-collision off --csv " +
                off), 0);
  // The row ends: ...,status,self_contacts,intersections,self_contact_ms,intersection_ms
  const std::string with = slurp(on), without = slurp(off);
  EXPECT_NE(with.find(",ok,"), std::string::npos);
  EXPECT_EQ(with.find(",-1,"), std::string::npos);   // counted at every step
  EXPECT_NE(without.find(",ok,0,-1,0,0\n"), std::string::npos) << without;  // not counted
  EXPECT_EQ(run("--scene " + fold + " --self-collision maybe"), 1);
  EXPECT_EQ(run("--scene " + kScene + " --fold 1 --duration 0.1"), 0);  // hanging has pins
}

TEST(RunScene, ARunTooLongToCountIsRefused) {
  // 1 s of 1e-10 s frames: 1e10 frames overflowed the count into a run of one step.
  EXPECT_EQ(run("--scene " + kScene + " --dt 1e-10 --duration 1"), 1);
  EXPECT_EQ(run("--scene " + kScene + " --substeps 0"), 1);
}

TEST(RunScene, IntegratorOptionRunsBdf2AndRefusesWhatCannotUseIt) {
  EXPECT_EQ(run("--scene " + kScene + " --duration 0.05 --integrator bdf2"), 0);
  EXPECT_EQ(run("--scene " + kScene + " --integrator bdf3"), 1);
  EXPECT_EQ(run("--scene " + kScene + " --integrator bdf2 --solver verlet"), 1);  // explicit
}

TEST(RunScene, BadArgumentsExitWithOne) {
  EXPECT_EQ(run("--scene " + kScene + " --solver rk4"), 1);
  EXPECT_EQ(run("--scene /nonexistent.yaml"), 1);
  EXPECT_EQ(run("--scene " + kScene + " --dt -0.01"), 1);
  EXPECT_EQ(run("--scene " + kScene + " --iterations 0"), 1);
  EXPECT_EQ(run("--scene " + kScene + " --linear-solver lu"), 1);
  EXPECT_EQ(run("--scene " + kScene + " --csv a.csv --json b.json"), 1);
  EXPECT_EQ(run("--scene " + kScene + " --duration 0.02 --csv /nonexistent/dir/x.csv"), 1);
  EXPECT_EQ(run("--help"), 0);
}

TEST(RunDemo, ABadSceneStopsWithAFailingStatusBeforeLaunching) {
  // make run with a scene that cannot be used exited 0 (the node died, roslaunch did not care).
  const std::string scene = tmp("duplicate_key.yaml");
  std::ofstream(scene) << "time_step: 1/60\ntime_step: 1/30\n";
  const std::string script = std::string(CLOTH_SIM_SOURCE_DIR) + "/scripts/run_demo.sh";
  const int status = std::system(("SCENE=" + scene + " timeout 60 bash " + script + " > /dev/null 2>&1").c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
}

}  // namespace

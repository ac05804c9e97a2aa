// The headless runner as a user calls it: exit codes, CSV / JSON per step, final positions.
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <random>
#include <sstream>
#include <string>
#include <vector>

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
  ASSERT_EQ(run("--scene " + kScene + " --duration 0.1 --iterations 3 --error-tolerance 0 --csv " + csv +
                " --positions " + positions),
            0);
  const std::string table = slurp(csv);
  EXPECT_EQ(countLines(table), 1 + 6);  // header + 0.1 s at h = 1/60
  EXPECT_EQ(table.rfind("step,time,wall_ms,solve_ms,iterations,convergence,converged,max_strain,"
                        "energy,contacts,status,self_contacts,intersections,self_contact_ms,"
                        "intersection_ms,substeps,total_iterations,iteration_error,error_estimate,"
                        "rejected_substeps,carried_iteration_error,cut_substeps,"
                        "merged_substeps\n", 0), 0u);
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
  EXPECT_NE(without.find(",ok,0,-1,0,0,"), std::string::npos) << without;  // not counted
  EXPECT_EQ(run("--scene " + fold + " --self-collision maybe"), 1);
  EXPECT_EQ(run("--scene " + kScene + " --fold 1 --duration 0.1"), 0);  // hanging has pins
}

TEST(RunScene, ARunTooLongToCountIsRefused) {
  // 1 s of 1e-10 s frames: 1e10 frames overflowed the count into a run of one step (a frame
  // under 1e-6 s is now refused by --dt itself; 1e-6 s frames for 1000 s are 1e9 frames).
  EXPECT_EQ(run("--scene " + kScene + " --dt 1e-10 --duration 1"), 1);
  EXPECT_EQ(run("--scene " + kScene + " --dt 1e-6 --duration 1000"), 1);
  EXPECT_EQ(run("--scene " + kScene + " --duration 1e-300"), 1);  // no frame at all
  // Substeps chosen by the error estimate need a tolerance to aim at.
  EXPECT_EQ(run("--scene " + kScene + " --substeps 0 --error-tolerance 0"), 1);
}

int runCapturing(const std::string& dir, const std::string& args, std::string& err);

/// Each of @p bads given to @p option exits with 1 and a message naming the option (and
/// @p rule, when not empty).
void expectRefused(const std::string& option, std::initializer_list<const char*> bads,
                   const std::string& rule) {
  const std::string dir = ::testing::TempDir() + "cloth_sim_run_refused";
  ASSERT_EQ(std::system(("mkdir -p '" + dir + "'").c_str()), 0);
  for (const char* bad : bads) {
    std::string err;
    EXPECT_EQ(runCapturing(dir, "--scene " + kScene + " --duration 0.05 " + option + " " + bad,
                           err),
              1)
        << bad;
    EXPECT_NE(err.find(option), std::string::npos) << err;
    if (!rule.empty()) EXPECT_NE(err.find(rule), std::string::npos) << err;
  }
}

TEST(RunScene, ToleranceIsInZeroToOne) {
  // A relative change is 1 at the first iteration: --tolerance 2 stopped every step after one
  // iteration without a word. Now [0, 1), refused naming the option and the rule.
  expectRefused("--tolerance", {"2", "1", "-0.1", "nan"}, "must be in [0, 1)");
  EXPECT_EQ(run("--scene " + kScene + " --duration 0.05 --tolerance 0.999"), 0);
  EXPECT_EQ(run("--scene " + kScene + " --duration 0.05 --tolerance 0"), 0);
}

/// The last two fields of each data row of CSV @p table: cut_substeps + merged_substeps.
std::vector<int> shortfalls(const std::string& table) {
  std::vector<int> out;
  std::istringstream lines(table);
  std::string line;
  std::getline(lines, line);  // the header
  while (std::getline(lines, line)) {
    const std::size_t last = line.rfind(','), before = line.rfind(',', last - 1);
    out.push_back(std::stoi(line.substr(before + 1, last - before - 1)) +
                  std::stoi(line.substr(last + 1)));
  }
  return out;
}

TEST(RunScene, FrameDeadlineCutsAFrameTooLongAndSaysSo) {
  // 100,000 iterations a substep take seconds a frame: the deadline cuts each frame, and the
  // CSV says so. Without one the same frames do all their work (0 and 0).
  const std::string cut = tmp("deadline.csv"), whole = tmp("no_deadline.csv");
  ASSERT_EQ(run("--scene " + kScene + " --duration 0.05 --iterations 100000 --tolerance 0 "
                "--error-tolerance 0 --frame-deadline-ms 20 --csv " + cut),
            0);
  const std::vector<int> cut_rows = shortfalls(slurp(cut));
  ASSERT_EQ(cut_rows.size(), 3u);
  for (const int s : cut_rows) EXPECT_GT(s, 0);
  ASSERT_EQ(run("--scene " + kScene + " --duration 0.05 --iterations 3 --error-tolerance 0 --csv " +
                whole),
            0);
  const std::vector<int> whole_rows = shortfalls(slurp(whole));
  ASSERT_EQ(whole_rows.size(), 3u);
  for (const int s : whole_rows) EXPECT_EQ(s, 0);
  expectRefused("--frame-deadline-ms", {"-1", "60001", "nan", "soon"}, "");
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

/// The runner's exit status, with what it printed on stderr in @p err, run in @p dir.
int runCapturing(const std::string& dir, const std::string& args, std::string& err) {
  const std::string err_file = dir + "/stderr.txt";
  const int status = std::system(("cd '" + dir + "' && " + kRunner + " " + args + " > /dev/null 2> " +
                                  err_file).c_str());
  err = slurp(err_file);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// @p text quoted for the shell.
std::string quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

TEST(RunScene, RandomBadOptionsAreRefusedByNameOrRunWithoutRollback) {
  // Every runner option with NaN, infinities, huge and tiny numbers, wrong types and
  // long strings (fixed seed, printed). Each run exits 1 naming the option, or 0: ran with no
  // rolled-back step (2) and no crash. A small scene keeps the accepted runs short.
  const std::string dir = ::testing::TempDir() + "cloth_sim_run_random";
  ASSERT_EQ(std::system(("mkdir -p '" + dir + "'").c_str()), 0);
  const std::string scene = dir + "/small.yaml";
  std::ofstream(scene) << "cloth: {grid: {rows: 6, cols: 6, size: [0.5, 0.5], position: [0, 0, 1]}}\n"
                          "material: {springs: {structural: 500, shear: 50}}\n"
                          "pins: [{row: 0, col: 0}, {row: 0, col: 5}]\n";
  const std::vector<std::string> options = {
      "--solver", "--iterations", "--substeps", "--dt", "--duration", "--tolerance",
      "--linear-solver", "--integrator", "--csv", "--json", "--positions", "--scene",
      "--warm-start", "--quiet", "--check"};
  const std::vector<std::string> values = {
      "nan", "inf", "-inf", "1e308", "-1e308", "1e300", "1e-300", "5e-324", "0", "-0", "-1",
      "0.5", "1", "3", "1e5", "100000", "2147483648", "99999999999999999999", "abc", "",
      "newton", "chebyshev", "bdf2", "cholmod", "1/60", "0x10", "true", "-", "/nonexistent/x",
      std::string(100000, 'x')};
  constexpr unsigned kSeed = 13;
  constexpr int kCases = 150;
  std::printf("[measured] runner options: seed %u, %d cases\n", kSeed, kCases);
  std::mt19937 rng(kSeed);
  std::uniform_int_distribution<std::size_t> pick_option(0, options.size() - 1),
      pick_value(0, values.size() - 1);
  int refused = 0, ran = 0;
  for (int k = 0; k < kCases; ++k) {
    const std::string& option = options[pick_option(rng)];
    const std::string& value = values[pick_value(rng)];
    SCOPED_TRACE("case " + std::to_string(k) + ": " + option + "=" + value.substr(0, 40));
    // --duration short unless it is the option tried; --scene the small one unless tried.
    std::string args = option == "--scene" ? "" : "--scene " + scene;
    if (option != "--duration") args += " --duration 0.05";
    if (option == "--iterations" || option == "--substeps") args += " --dt 0.1";
    args += " " + quoted(option + "=" + value);
    std::string err;
    const int code = runCapturing(dir, args, err);
    EXPECT_TRUE(code == 0 || code == 1) << "exit " << code << ": " << err.substr(0, 300);
    if (code == 1) {
      ++refused;
      EXPECT_NE(err.find(option), std::string::npos) << err.substr(0, 300);
      EXPECT_LT(err.size(), 1000u) << "a long value must not be echoed whole";
    } else {
      ++ran;
    }
  }
  std::printf("[measured] runner options: %d refused by name, %d ran cleanly\n", refused, ran);
  EXPECT_GT(refused, 0);
  EXPECT_GT(ran, 0);
}

TEST(RunScene, CheckBuildsTheSceneAndRunsNothing) {
  // scripts/run_demo.sh checks a scene this way before launching (it used --duration 1e-9,
  // which now is less than one frame and refused).
  const std::string csv = tmp("check.csv");
  std::remove(csv.c_str());
  EXPECT_EQ(run("--scene " + kScene + " --check --csv " + csv), 0);
  EXPECT_EQ(run("--scene " + kScene + " --check --substeps 0 --error-tolerance 0"), 1);
  const std::string bad = tmp("check_bad.yaml");
  std::ofstream(bad) << "time_step: 1/60\ntime_step: 1/30\n";
  EXPECT_EQ(run("--scene " + bad + " --check"), 1);
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

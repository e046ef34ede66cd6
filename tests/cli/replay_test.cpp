// xfdem replay end to end: record a run's per-step hashes, check a re-run
// against them (identical), and name the first differing step and field when an
// override perturbs the run.
#include <gtest/gtest.h>

#include "support/command.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

fs::path scratch() { return xfdem::testing::scratch("replay_test"); }

using Result = xfdem::testing::CommandResult;

Result xfdem(const std::string& args) { return xfdem::testing::run_command(XFDEM_CLI, args); }

std::string scene(const char* name) { return xfdem::testing::scene_file(name); }

TEST(Replay, RecordThenCheckIsIdentical) {
  const fs::path hashes = scratch() / "case2.hashes";
  const Result rec = xfdem("replay record " + scene("case2_xfem.json") + " --steps 2000 --out " + hashes.string());
  ASSERT_EQ(rec.exit_code, 0) << rec.err;
  EXPECT_NE(rec.out.find("recorded 2000 steps of case2_xfem"), std::string::npos) << rec.out;
  const Result check = xfdem("replay check " + scene("case2_xfem.json") + " --against " + hashes.string());
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  EXPECT_NE(check.out.find("identical, 2000 steps"), std::string::npos) << check.out;
}

TEST(Replay, APerturbedRunNamesTheFirstStepAndField) {
  const fs::path hashes = scratch() / "v1.hashes";
  ASSERT_EQ(xfdem("replay record " + scene("v1_k1e4.json") + " --steps 8000 --out " + hashes.string()).exit_code, 0);
  // Gravity is not state, but the built state holds the first acceleration.
  const Result g = xfdem("replay check " + scene("v1_k1e4.json") + " --set gravity.0=-9.8 --against " + hashes.string());
  EXPECT_EQ(g.exit_code, 1) << g.out << g.err;
  EXPECT_NE(g.out.find("first difference at step 0 "), std::string::npos) << g.out;
  EXPECT_NE(g.out.find("field hist_a[0] "), std::string::npos) << g.out;
  EXPECT_NE(g.out.find("model differs"), std::string::npos) << g.out;
  // A velocity perturbation is in the state from the start.
  const Result v = xfdem("replay check " + scene("v1_k1e4.json") +
                         " --set dem.particles.0.velocity.0=1e-12 --against " + hashes.string());
  EXPECT_EQ(v.exit_code, 1) << v.out << v.err;
  EXPECT_NE(v.out.find("first difference at step 0 "), std::string::npos) << v.out;
  EXPECT_NE(v.out.find("field v "), std::string::npos) << v.out;
  // The damping ratio acts only in contact: the runs part at the first step
  // the particle touches the plane (t = 0.769 s), where the velocity differs.
  const Result d = xfdem("replay check " + scene("v1_k1e4.json") + " --set dem.contact.damping_ratio=0.2 --against " +
                         hashes.string());
  EXPECT_EQ(d.exit_code, 1) << d.out << d.err;
  EXPECT_NE(d.out.find("first difference at step 7690 "), std::string::npos) << d.out;
  EXPECT_NE(d.out.find("field v "), std::string::npos) << d.out;
}

TEST(Replay, AnotherSceneOrABadFileIsReported) {
  const fs::path hashes = scratch() / "c2.hashes";
  ASSERT_EQ(xfdem("replay record " + scene("case2_xfem.json") + " --steps 10 --out " + hashes.string()).exit_code, 0);
  const Result other = xfdem("replay check " + scene("case1_xfem.json") + " --against " + hashes.string());
  EXPECT_EQ(other.exit_code, 1);
  EXPECT_NE(other.out.find("different layout"), std::string::npos) << other.out;
  const fs::path junk = scratch() / "junk.hashes";
  std::ofstream(junk) << "not hashes";
  const Result bad = xfdem("replay check " + scene("case2_xfem.json") + " --against " + junk.string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("is not an xfdem hashes file"), std::string::npos) << bad.err;
  const Result usage = xfdem("replay record " + scene("case2_xfem.json"));
  EXPECT_EQ(usage.exit_code, 2);
  EXPECT_NE(usage.err.find("--out FILE is required"), std::string::npos) << usage.err;
}

}  // namespace

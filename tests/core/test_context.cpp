// The execution context (core/context.hpp): thread counts checked where they enter, progress reported
// under a task's name and scaled to its part, cancellation seen by every copy, and images over the
// texel limit refused unless allowed.
#include <gtest/gtest.h>
#include <brdfbake/core/context.hpp>
#include <brdfbake/core/error.hpp>

#include <string>
#include <thread>
#include <vector>

namespace brdfbake {
namespace {

TEST(Context, ThreadCountsAreLimitedTo1024) {
  // --threads 2147483647 crashed TBB (SIGSEGV), 70,000 already did: refused before any work.
  try {
    Context({.threads = 2147483647});
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::InvalidArgument);
    EXPECT_STREQ(e.what(), "threads must be in [0, 1024] (0 = every core), got 2147483647");
  }
  EXPECT_THROW(Context({.threads = -1}), Error);
  EXPECT_EQ(Context({.threads = 1024}).threads(), 1024);
  EXPECT_EQ(Context().arenaThreads(), -1);  // tbb::task_arena::automatic
  EXPECT_THROW(Context().withThreads(1025), Error);
}

TEST(Context, ReportsEachTaskScaledToItsPart) {
  std::vector<std::pair<std::string, double>> reports;
  const Context context({.progress = [&](const std::string& task, double f) { reports.emplace_back(task, f); }});
  const Context fit = context.task("fit");
  fit.part(0.5, 1.0).report(0.5);
  fit.part(0.5, 1.0).part(0.0, 0.5).report(1.0);
  fit.withoutProgress().report(0.3);  // nowhere
  fit.report(2.0);                    // clamped
  ASSERT_EQ(reports.size(), 3u);
  EXPECT_EQ(reports[0], std::make_pair(std::string("fit"), 0.75));
  EXPECT_EQ(reports[1], std::make_pair(std::string("fit"), 0.75));
  EXPECT_EQ(reports[2], std::make_pair(std::string("fit"), 1.0));
}

// Worker threads finish their steps out of order: a bar fed by them must still not jump back (the
// sanitizer build's slower threads made an auto search report 0.62 after 0.63).
TEST(Context, ATasksReportsNeverGoBackwardsAndANewTaskStartsAtZero) {
  std::vector<std::pair<std::string, double>> reports;
  const Context context({.progress = [&](const std::string& task, double f) { reports.emplace_back(task, f); }});
  const Context bake = context.task("bake");
  bake.report(0.4);
  bake.part(0.0, 0.5).report(0.6);  // 0.3 of the task, behind 0.4
  bake.report(0.5);
  context.task("write").report(0.1);
  using Report = std::pair<std::string, double>;
  EXPECT_EQ(reports, (std::vector<Report>{{"bake", 0.4}, {"bake", 0.4}, {"bake", 0.5}, {"write", 0.1}}));
}

TEST(Context, ACancelReachesEveryCopyFromAnyThread) {
  const Context context;
  const Context task = context.task("bake").part(0.2, 0.4).withThreads(1).withoutProgress();
  EXPECT_NO_THROW(task.checkCancelled());
  std::thread([copy = context] { copy.cancel(); }).join();
  EXPECT_TRUE(task.cancelled());
  EXPECT_THROW(task.checkCancelled(), Cancelled);
  EXPECT_THROW(task.report(0.5), Cancelled);
  // Cancelled is no brdfbake::Error: a layer that carries on after a failed part does not swallow it.
  bool caughtAsError = false;
  try {
    task.checkCancelled();
  } catch (const Error&) {
    caughtAsError = true;
  } catch (const Cancelled&) {
  }
  EXPECT_FALSE(caughtAsError);
  EXPECT_FALSE(Context().cancelled());  // a new context starts afresh
}

TEST(Context, ImagesOverTheTexelLimitNeedAllowLarge) {
  try {
    Context().requireImageSize(8193, 8192, "spec.json: maps[0]");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::Resource);
    EXPECT_EQ(std::string(e.what()).rfind("spec.json: maps[0]: a 8193 x 8192 map needs 1 GiB", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find("--allow-large"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(Context().requireImageSize(8192, 8192));
}

}  // namespace
}  // namespace brdfbake

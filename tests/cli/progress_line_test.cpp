// The progress line shows the iteration out of its limit only while that limit can end the
// run, and the share done of whichever limit is nearer.
#include "apps/common/progress_reporter.hpp"

#include <gtest/gtest.h>

namespace splat::cli {
namespace {

TEST(ProgressLine, ShowsTheIterationLimitOnlyWhileItCanEndTheRun) {
  ProgressSnapshot s;
  s.iteration = 300;
  s.total_iterations = 3000;
  s.iterations_per_second = 10;
  s.model_size = "1000 Gaussians";
  EXPECT_NE(progress_line(s).find("iter 300/3000 ( 10%)"), std::string::npos) << progress_line(s);
  EXPECT_NE(progress_line(s).find("ETA 4m30s"), std::string::npos) << progress_line(s);

  // A 60 s budget ends it long before iteration 3,000 (270 s away): the time is the limit.
  s.max_seconds = 60;
  s.elapsed_seconds = 30;
  EXPECT_NE(progress_line(s).find("iter 300 ( 50%)"), std::string::npos) << progress_line(s);
  EXPECT_NE(progress_line(s).find("ETA 30s"), std::string::npos) << progress_line(s);

  // A long budget: the iterations end it first, and stay shown out of their limit.
  s.max_seconds = 3600;
  EXPECT_NE(progress_line(s).find("iter 300/3000 ( 10%)"), std::string::npos) << progress_line(s);
}

}  // namespace
}  // namespace splat::cli

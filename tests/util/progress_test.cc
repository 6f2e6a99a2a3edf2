// ProgressBar: thread-safe counting, and no failure when callers over-count.
#include "pgba/util/progress.h"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include "pgba/util/timer.h"

namespace pgba {
namespace {

TEST(ProgressBar, ParallelIncrementsAndOvercount) {
  testing::internal::CaptureStderr();
  {
    ProgressBar bar("parallel", 1000);
    tbb::parallel_for(0, 1000, [&](int) { bar.Increment(); });
    bar.Increment(500);  // more than announced
    bar.Finish();
    bar.Finish();  // idempotent
  }
  { ProgressBar empty("empty", 0); }
  const std::string err = testing::internal::GetCapturedStderr();
  // Not a terminal: one summary line per bar (at the default verbosity).
  EXPECT_NE(err.find("parallel"), std::string::npos);
  EXPECT_NE(err.find("1500/1000"), std::string::npos) << err;
  EXPECT_NE(err.find("0/0"), std::string::npos) << err;
}

TEST(Timer, MeasuresAndReportsMemory) {
  Timer t;
  volatile double x = 0;
  for (int i = 0; i < 1000000; ++i) x = x + i;
  EXPECT_GT(t.Seconds(), 0.0);
  EXPECT_GT(PeakRssMb(), 1.0);
}

}  // namespace
}  // namespace pgba

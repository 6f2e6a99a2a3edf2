// ProgressBar: thread-safe counting, and no failure when callers over-count.
#include "pgba/util/progress.h"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include "pgba/util/logging.h"
#include "pgba/util/timer.h"

namespace pgba {
namespace {

// Bars that are run and over-counted, and what they print off a terminal at `verbosity`.
std::string BarsPrinted(int verbosity) {
  const int before = LogVerbosity();
  SetLogVerbosity(verbosity);
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
  SetLogVerbosity(before);
  return err;
}

TEST(ProgressBar, ParallelIncrementsAndOvercount) {
  // Not a terminal: at the default verbosity nothing (each stage prints its own summary line),
  // at -v 2 one line per bar with its last state.
  EXPECT_EQ(BarsPrinted(1), "");
  const std::string err = BarsPrinted(2);
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

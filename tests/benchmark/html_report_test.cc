// report.html's convergence rows: a curve evaluated on a sample of the tracks says so and
// gives the exact final sigma beside it; a curve on every track reads as before.
#include "benchmark/html_report.h"

#include <gtest/gtest.h>

namespace pgba {
namespace {

TEST(HtmlReport, ASampledConvergenceCurveSaysSoAndGivesTheExactFinalSigma) {
  const std::vector<double> curve = {0.3145, 0.2, 0.1708};
  EvaluationMetrics metrics;
  metrics.sigma.num_inliers = 10;
  metrics.sigma.rms = 0.1673;
  HtmlReportInput in;
  in.title = "t";
  in.convergence = &curve;
  in.metrics = &metrics;
  in.convergence_tracks = 20000;
  in.convergence_tracks_total = 111132;
  const std::string sampled = RunReportHtml(in);
  EXPECT_NE(sampled.find("sigma final (px, sample of 20000 of 111132 tracks)</th><td>0.1708"), std::string::npos);
  EXPECT_NE(sampled.find("sigma final (px, every track)</th><td>0.1673"), std::string::npos);
  EXPECT_NE(sampled.find("sigma per iteration, sample of 20000 of 111132 tracks"), std::string::npos);

  in.convergence_tracks = 111132;  // every track: no note, no second row
  const std::string exact = RunReportHtml(in);
  EXPECT_NE(exact.find("sigma final (px)</th><td>0.1708"), std::string::npos);
  EXPECT_EQ(exact.find("every track"), std::string::npos);
  EXPECT_EQ(exact.find("sample of"), std::string::npos);
}

}  // namespace
}  // namespace pgba

// report.html: a convergence curve evaluated on a sample of the tracks says so, and the final
// sigma is the result's; a log axis has a labelled tick at each decade and at least three
// labels; the camera parameters by name from the run's prior to the final value; the images
// not registered with their reasons; the stages in order, a folded pass's stages under it.
#include "report/html_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <regex>

#include "report/svg_plot.h"

namespace pgba {
namespace {

TEST(HtmlReport, ASampledConvergenceCurveSaysSoAndTheFinalSigmaIsTheResults) {
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
  EXPECT_NE(sampled.find("sigma initial poses (px, sample of 20000 of 111132 tracks)</th><td>0.3145"), std::string::npos);
  // The final sigma is the result's (the evaluation's, as the console prints it), not the sample's.
  EXPECT_NE(sampled.find("sigma final (px)</th><td>0.1673"), std::string::npos);
  EXPECT_EQ(sampled.find("0.1708"), std::string::npos);
  EXPECT_NE(sampled.find("sigma per iteration, sample of 20000 of 111132 tracks"), std::string::npos);

  in.convergence_tracks = 111132;  // every track: no note
  in.metrics = nullptr;            // no evaluation: the curve's last point
  const std::string exact = RunReportHtml(in);
  EXPECT_NE(exact.find("sigma final (px)</th><td>0.1708"), std::string::npos);
  EXPECT_EQ(exact.find("sample of"), std::string::npos);
}

// The y labels of an SVG plot (right-aligned texts), as numbers.
std::vector<double> YLabels(const std::string& svg) {
  std::vector<double> labels;
  const std::regex label(R"(text-anchor="end">([^<]+)</text>)");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), label); it != std::sregex_iterator(); ++it)
    labels.push_back(std::stod((*it)[1]));
  return labels;
}

TEST(SvgPlot, ALogAxisHasALabelAtEachDecadeAndAtLeastThreeLabels) {
  PlotOptions o;
  o.log_y = true;
  // A narrow curve inside one decade (0.35-0.38 px), a curve over three (4 px to 0.004 px).
  const std::vector<double> narrow = {0.38, 0.36, 0.35}, wide = {4.0, 0.3, 0.004};
  for (const std::vector<double>* y : {&narrow, &wide}) {
    const std::vector<double> labels = YLabels(LinePlotSvg({{"a", {0, 1, 2}, *y}}, o));
    ASSERT_GE(labels.size(), 3u);
    const double lo = *std::min_element(y->begin(), y->end()), hi = *std::max_element(y->begin(), y->end());
    // Every decade from the one below the data to the one above it is labelled.
    for (double d = std::pow(10.0, std::floor(std::log10(lo))); d <= 10 * hi; d *= 10)
      EXPECT_TRUE(std::any_of(labels.begin(), labels.end(), [&](double l) { return std::abs(l / d - 1) < 1e-9; }))
          << d;
    for (double l : labels) {  // on 1, 2 or 5 of a decade
      const double m = l / std::pow(10.0, std::floor(std::log10(l) + 1e-9));
      EXPECT_TRUE(std::abs(m - 1) < 1e-6 || std::abs(m - 2) < 1e-6 || std::abs(m - 5) < 1e-6) << l;
    }
  }
  EXPECT_EQ(YLabels(LinePlotSvg({{"a", {0, 1, 2}, narrow}}, o)), (std::vector<double>{0.1, 0.2, 0.5, 1}));
  // Ticks: one per integer multiple of each decade, the decades (and 2, 5 up to 3 decades) labelled.
  const std::vector<AxisTick> ticks = LogTicks(-1.0, 1.0);
  EXPECT_EQ(ticks.size(), 19u);  // 0.1 ... 0.9, 1 ... 9, 10
  EXPECT_EQ(std::count_if(ticks.begin(), ticks.end(), [](const AxisTick& t) { return t.labelled; }), 7);
  const std::vector<AxisTick> five = LogTicks(-3.0, 2.0);
  EXPECT_EQ(std::count_if(five.begin(), five.end(), [](const AxisTick& t) { return t.labelled; }), 6);
}

TEST(HtmlReport, CameraParametersByNameFromThePriorToTheFinalValue) {
  // The global BA estimated f and k of a SIMPLE_RADIAL camera, starting from a second pass's
  // values (2437.19, -0.01); the run began from the prior 2323.2, k 0.
  const nlohmann::json report = nlohmann::json::parse(R"({"intrinsics": [{"camera_id": 1, "model": "SIMPLE_RADIAL",
      "params": [{"index": 0, "name": "f", "initial": 2437.19, "final": 2440.531, "stddev": 0.8512},
                 {"index": 3, "name": "k", "initial": -0.01, "final": -0.0123456, "stddev": 0.000412}],
      "final_params": [2440.531, 1416.0, 1064.0, -0.0123456], "prior_params": [2323.2, 1416.0, 1064.0, 0.0]}]})");
  HtmlReportInput in;
  in.report = &report;
  const std::string html = RunReportHtml(in);
  const auto row = [](const char* name, const char* start, const char* final_value, const char* sd) {
    return std::string("<td>") + name + "</td><td class=\"n\">" + start + "</td><td class=\"n\">" + final_value +
           "</td><td class=\"n\">" + sd + "</td></tr>";
  };
  EXPECT_NE(html.find(row("f", "2323.20", "2440.53", "0.85")), std::string::npos) << html;
  EXPECT_NE(html.find(row("cx", "1416.00", "1416.00", "held")), std::string::npos);
  EXPECT_NE(html.find(row("cy", "1064.00", "1064.00", "held")), std::string::npos);
  EXPECT_NE(html.find(row("k", "0", "-0.01235", "0.00041")), std::string::npos);
  EXPECT_EQ(html.find("2437.19"), std::string::npos);  // the second pass's start is not the run's

  // A principal point an earlier pass moved and the last one held is not "held".
  nlohmann::json moved = report;
  moved["intrinsics"][0]["final_params"][1] = 1400.5;
  in.report = &moved;
  EXPECT_NE(RunReportHtml(in).find(row("cx", "1416.00", "1400.50", "held in the last pass")), std::string::npos);
}

TEST(HtmlReport, ImagesNotRegisteredWithTheirReasons) {
  nlohmann::json report = nlohmann::json::parse(R"({"images_dropped": ["b.jpg", "a.jpg"],
      "images_dropped_reason": {"a.jpg": "no image pair verified", "b.jpg": "not connected"}})");
  HtmlReportInput in;
  in.report = &report;
  std::string html = RunReportHtml(in);
  EXPECT_NE(html.find("<tr><td>b.jpg</td><td>not connected</td></tr>"), std::string::npos) << html;
  EXPECT_NE(html.find("<tr><td>a.jpg</td><td>no image pair verified</td></tr>"), std::string::npos);
  // The final check's record: images registered again listed apart; a dropped image without
  // a reason of its own takes the record's.
  report = nlohmann::json::parse(R"({"images_dropped": ["c.jpg"], "stages": {"verification": {"images": [
      {"image": "b.jpg", "status": "reregistered", "reason": "its rotation disagrees with its pairs"},
      {"image": "c.jpg", "status": "dropped", "reason": "too few inliers"}]}}})");
  html = RunReportHtml(in);
  EXPECT_NE(html.find("<tr><td>c.jpg</td><td>dropped by the final check: too few inliers</td></tr>"), std::string::npos)
      << html;
  const size_t again = html.find("Images registered again after failing the final check");
  ASSERT_NE(again, std::string::npos);
  EXPECT_NE(html.find("<tr><td>b.jpg</td><td>its rotation disagrees with its pairs</td></tr>", again), std::string::npos);
}

TEST(HtmlReport, StagesInTheOrderTheyRanWithTheirTotalAndTheRunsTime) {
  const nlohmann::json report = nlohmann::json::parse(R"({"seconds": 10.5, "stages": {
      "match_recalibrated": {"seconds": 2.0, "order": 2},
      "features": {"seconds": 1.0, "order": 0},
      "first_pass": {"seconds": 4.0, "order": 1, "stages": {"pairs": {"seconds": 1.5, "order": 2},
                                                            "global_ba": {"seconds": 2.25, "order": 3}}},
      "global_ba": {"seconds": 3.25, "order": 3}}})");
  HtmlReportInput in;
  in.report = &report;
  const std::string html = RunReportHtml(in);
  size_t last = 0;
  for (const char* row : {"<td>features</td>", "<td>first_pass</td>", "first_pass / pairs", "first_pass / global_ba",
                          "<td>match_recalibrated</td>", "<td>global_ba</td>", "<th>total</th><th class=\"n\">10.25<",
                          "<th>whole run</th><th class=\"n\">10.50<"}) {
    const size_t at = html.find(row, last);
    ASSERT_NE(at, std::string::npos) << row << "\n" << html;
    last = at;
  }
}

// A stage done again: its first round says which stage it was and why it was done again.
TEST(HtmlReport, AStageDoneAgainSaysWhy) {
  const nlohmann::json report = nlohmann::json::parse(R"({"stages": {
      "verification_before_readjustment": {"seconds": 1.0, "order": 0},
      "verification": {"seconds": 1.0, "order": 1},
      "global_ba_before_joining": {"seconds": 1.0, "order": 2}}})");
  HtmlReportInput in;
  in.report = &report;
  const std::string html = RunReportHtml(in);
  EXPECT_NE(html.find("<td>verification_before_readjustment</td><td class=\"n\">1.00</td><td class=\"n\">0</td>"
                      "<td>every registered image checked against its observations and verified pairs (first round, "
                      "done again without the images the verification dropped)</td>"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("<td>pointless global bundle adjustment: the final poses (first round, done again with the "
                      "images joined by absolute pose)</td>"),
            std::string::npos);
}

TEST(HtmlReport, GlobalBaPassesAndWhetherItConverged) {
  nlohmann::json report = nlohmann::json::parse(R"({"stages": {"global_ba": {"seconds": 1, "order": 0,
      "converged": false, "passes": [{"cost": 1234.5, "iterations": 7}, {"iterations": 3, "cost": 1200.25}]}}})");
  HtmlReportInput in;
  in.report = &report;
  std::string html = RunReportHtml(in);
  EXPECT_NE(html.find("Did not converge"), std::string::npos);
  EXPECT_NE(html.find("<tr><th>pass</th><th>cost</th><th>iterations</th></tr>"), std::string::npos) << html;
  report["stages"]["global_ba"]["passes"][0]["outlier_px"] = 4;  // a column of report.json's by its name
  EXPECT_NE(RunReportHtml(in).find("<th>outlier threshold (px)</th>"), std::string::npos);
  EXPECT_NE(html.find("<tr><td>2</td><td class=\"n\">1200.25</td><td class=\"n\">3</td></tr>"), std::string::npos);
  report["stages"]["global_ba"].erase("passes");
  report["stages"]["global_ba"]["converged"] = true;
  html = RunReportHtml(in);
  EXPECT_NE(html.find("Converged."), std::string::npos);
  report["stages"]["global_ba"]["stop_reason"] = "cost_tolerance";
  EXPECT_NE(RunReportHtml(in).find("Converged: the last pass lowered the reprojection cost by less than "
                                    "global_ba.relinearize_cost_tolerance."),
            std::string::npos);
  report["stages"]["global_ba"].erase("stop_reason");
  EXPECT_EQ(html.find("<th>pass</th>"), std::string::npos);
  report["stages"]["global_ba"].erase("converged");  // neither key: no section
  EXPECT_EQ(RunReportHtml(in).find("Global bundle adjustment"), std::string::npos);
}

}  // namespace
}  // namespace pgba

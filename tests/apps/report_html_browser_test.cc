// report.html as a browser shows it. `pgba run` with self-calibration (rendered photographs
// through a lens the prior does not know, run with --calib-prior, as in
// report_identities_cli_test.cc) writes a page with the camera parameters' table, the 3D view
// and the convergence plot; headless Chromium (the Debian package `chromium`, which
// scripts/install_deps.sh installs) loads a copy of the page alone in another folder (it needs
// no file beside it and no network):
//   - without an error or a message on the browser's console;
//   - into a screenshot that is a page, not a blank one: ink from the title down to the view
//     graph at the bottom, and the coloured marks that only rendered SVG plots put there (the
//     red convergence curve and cameras of the top view, the blue view graph);
//   - with the 3D view drawn by WebGL: its background (a colour only the renderer paints) over
//     a box of the view's size, and in it the points (dark) and the frusta (the saturated
//     colours of the residual scale), which a view that fails to draw, draws nothing or draws
//     only the points does not have.
// Software WebGL (SwiftShader) draws the 3D view; a machine without chromium fails this test
// (the browser is a test dependency, not optional).
//
// docs/report_3d_view.png is this test's picture of the 3D view; to make it again:
//   PGBA_WRITE_DOCS_SCREENSHOT=1 build/bin/test_apps --gtest_filter='ReportHtmlBrowser.*'
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>

#include "tests/apps/cli_runner.h"

namespace {
namespace fs = std::filesystem;

std::string Slurp(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The browser's path, empty when none is installed.
std::string FindChromium() {
  const pgba::test::CliResult r = pgba::test::RunCommand("command -v chromium || command -v chromium-browser");
  std::string path = r.output.substr(0, r.output.find('\n'));
  return r.code == 0 ? path : "";
}

TEST(ReportHtmlBrowser, ChromiumRendersThePageWithoutConsoleErrors) {
  const std::string chromium = FindChromium();
  ASSERT_FALSE(chromium.empty()) << "chromium is not installed: bash scripts/install_deps.sh installs it";

  const fs::path dir = fs::temp_directory_path() / ("pgba_report_browser_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  ASSERT_EQ(pgba::test::RunPgba("-v 0 synth --render --images 12 --seed 4 --k1 -0.08 --focal-prior-error 0.15 --out " +
                                (dir / "scene").string())
                .code,
            0);
  const fs::path out = dir / "out";
  const pgba::test::CliResult run =
      pgba::test::RunPgba("-v 0 run --images " + (dir / "scene" / "images").string() + " --calib " +
                          (dir / "scene" / "cameras.txt").string() + " --calib-prior --out " + out.string());
  ASSERT_EQ(run.code, 0) << run.output;
  const std::string html = Slurp(out / "report.html");
  ASSERT_NE(html.find("<h2>Camera parameters</h2>"), std::string::npos);
  ASSERT_NE(html.find("<h2>Convergence</h2>"), std::string::npos);
  ASSERT_NE(html.find("<h2>3D view</h2>"), std::string::npos);

  // The page alone, copied into another folder: nothing else of the run is beside it.
  const fs::path copied = dir / "copied" / "report.html";
  fs::create_directories(copied.parent_path());
  fs::copy_file(out / "report.html", copied);
  EXPECT_EQ(html.find("<script src"), std::string::npos);

  // A profile of its own (nothing read from or written to the user's), the page at 1280 px wide
  // and tall enough for all of it; the browser's log on stderr. WebGL in software: SwiftShader
  // through ANGLE, opted in (Chromium no longer falls back to it by itself).
  const fs::path png = dir / "report.png", log = dir / "chromium.log";
  const pgba::test::CliResult browser = pgba::test::RunCommand(
      "timeout --kill-after=10 120 " + chromium +
      " --headless --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader --hide-scrollbars --no-first-run"
      " --user-data-dir=" +
      (dir / "profile").string() + " --enable-logging=stderr --v=0 --window-size=1280,4000 --screenshot=" +
      png.string() + " file://" + fs::absolute(copied).string() + " > /dev/null 2> " + log.string());
  const std::string messages = Slurp(log);
  ASSERT_EQ(browser.code, 0) << messages;
  // Page errors and console messages are logged as "...:CONSOLE(line)] ..." or "Uncaught ...".
  std::istringstream lines(messages);
  for (std::string line; std::getline(lines, line);) {
    EXPECT_EQ(line.find("CONSOLE"), std::string::npos) << line;
    EXPECT_EQ(line.find("Uncaught"), std::string::npos) << line;
  }

  const cv::Mat shot = cv::imread(png.string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(shot.empty()) << "no screenshot at " << png;
  ASSERT_EQ(shot.cols, 1280);
  // The 3D view: the box of the pixels of its background, #eef1f5.
  cv::Rect view;
  {
    int x0 = shot.cols, y0 = shot.rows, x1 = -1, y1 = -1;
    for (int y = 0; y < shot.rows; ++y)
      for (int x = 0; x < shot.cols; ++x) {
        const cv::Vec3b bgr = shot.at<cv::Vec3b>(y, x);
        if (std::abs(bgr[0] - 0xf5) <= 2 && std::abs(bgr[1] - 0xf1) <= 2 && std::abs(bgr[2] - 0xee) <= 2)
          x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
      }
    ASSERT_GE(x1, 0) << "no 3D view: WebGL drew nothing";
    view = cv::Rect(x0, y0, x1 - x0 + 1, y1 - y0 + 1);
  }
  EXPECT_GT(view.width, 800) << "the 3D view is the page's width";
  EXPECT_GT(view.height, 500) << "the 3D view is 560 px tall";
  int view_ink = 0, frustum = 0;
  for (int y = view.y; y < view.y + view.height; ++y)
    for (int x = view.x; x < view.x + view.width; ++x) {
      const cv::Vec3b bgr = shot.at<cv::Vec3b>(y, x);
      const int hi = std::max({bgr[0], bgr[1], bgr[2]}), lo = std::min({bgr[0], bgr[1], bgr[2]});
      view_ink += hi < 200;            // points (#555) and frustum lines
      frustum += hi - lo > 60;         // the residual scale's blue to red; points and background are grey
    }
  EXPECT_GT(view_ink, 2000) << "no points in the 3D view";
  EXPECT_GT(frustum, 200) << "no camera in the 3D view";
  const cv::Mat view_png = shot(view).clone();
  ASSERT_TRUE(cv::imwrite((dir / "report_3d_view.png").string(), view_png));
  if (const char* write = std::getenv("PGBA_WRITE_DOCS_SCREENSHOT"); write && std::string(write) == "1") {
    ASSERT_TRUE(cv::imwrite(std::string(PGBA_SOURCE_DIR) + "/docs/report_3d_view.png", view_png));
  }

  // The rest of the page, the 3D view left out (its frusta are red and blue too).
  int ink = 0, red = 0, blue = 0, first_row = -1, last_row = -1;
  for (int y = 0; y < shot.rows; ++y) {
    for (int x = 0; x < shot.cols; ++x) {
      if (view.contains(cv::Point(x, y))) continue;
      const cv::Vec3b bgr = shot.at<cv::Vec3b>(y, x);
      const int b = bgr[0], g = bgr[1], r = bgr[2];
      if (b > 240 && g > 240 && r > 240) continue;
      ++ink;
      if (first_row < 0) first_row = y;
      last_row = y;
      red += r > 150 && g < 90 && b < 90;
      blue += b > 120 && b > r + 60 && b > g + 20;
    }
  }
  const double ink_fraction = static_cast<double>(ink) / (static_cast<double>(shot.rows) * shot.cols);
  EXPECT_GT(ink_fraction, 0.02) << "a blank page";
  EXPECT_LT(first_row, 100) << "the title at the top";
  EXPECT_GT(last_row, 1500) << "the page ends after " << last_row << " px: the plots and the view graph are missing";
  EXPECT_GT(red, 100) << "no convergence curve, no camera in the top view";
  EXPECT_GT(blue, 100) << "no view graph";
  fs::remove_all(dir);
}

}  // namespace

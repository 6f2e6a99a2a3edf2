// The numbers of `pgba run` agree wherever they are printed, and with the files written. On
// rendered photographs through a lens the prior does not know (`pgba synth --render --k1 -0.08
// --focal-prior-error 0.15`, run with --calib-prior, so the self-calibration moves the image
// enough to match again and run a second pass):
//   - the view graph's verified pairs = those from the matching's geometry + those by RANSAC, in
//     the console, in report.json and in report.html's summary and view graph;
//   - the tracks of the last matching in the console, report.json, tracks/ and report.html;
//   - the points of the console = the triangulation stage's = the evaluation's tracks
//     triangulated (report.json and the console's table) = the points of sparse/points3D.txt
//     and of points.ply = report.html's;
//   - the stages' seconds add up to the run's time, in the order they ran (the first pass one
//     stage before the second matching, holding its own stages);
//   - the camera parameters start from the prior of cameras.txt, by name, in the console and
//     report.html;
//   - the console at the default verbosity: one line for the global BA, no solver internals.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "pgba/io/colmap_text.h"
#include "tests/apps/cli_runner.h"

namespace {
namespace fs = std::filesystem;

std::string Slurp(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The last match of `pattern` in `text` (its groups), empty when none.
std::smatch LastMatch(const std::string& text, const std::regex& pattern) {
  std::smatch last;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), pattern); it != std::sregex_iterator(); ++it)
    last = *it;
  return last;
}

long DataLines(const fs::path& p) {
  std::ifstream in(p);
  long n = 0;
  for (std::string line; std::getline(in, line);) n += !line.empty() && line[0] != '#';
  return n;
}

// points.ply's header: its vertices, and the points and cameras its comment says they are.
struct PlyHeader {
  long vertices = -1, points = -1, cameras = -1;
};
PlyHeader ReadPlyHeader(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  PlyHeader h;
  for (std::string line; std::getline(in, line) && line.rfind("end_header", 0) != 0;) {
    std::smatch m;
    if (std::regex_match(line, m, std::regex(R"(element vertex (\d+))"))) h.vertices = std::stol(m[1]);
    if (std::regex_match(line, m, std::regex(R"(comment pgba points (\d+) cameras (\d+))")))
      h.points = std::stol(m[1]), h.cameras = std::stol(m[2]);
  }
  return h;
}

TEST(ReportIdentitiesCli, EveryCountAgreesWithTheOthersAndWithTheFiles) {
  const fs::path dir = fs::temp_directory_path() / ("pgba_report_identities_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  ASSERT_EQ(pgba::test::RunPgba("-v 0 synth --render --images 12 --seed 4 --k1 -0.08 --focal-prior-error 0.15 --out " +
                                (dir / "scene").string())
                .code,
            0);
  const fs::path out = dir / "out";
  const pgba::test::CliResult run = pgba::test::RunPgba("run --images " + (dir / "scene" / "images").string() +
                                                        " --calib " + (dir / "scene" / "cameras.txt").string() +
                                                        " --calib-prior --out " + out.string());
  ASSERT_EQ(run.code, 0) << run.output;
  const std::string& console = run.output;
  const nlohmann::json r = nlohmann::json::parse(Slurp(out / "report.json"));
  const nlohmann::json& stages = r["stages"];
  const std::string html = Slurp(out / "report.html");
  ASSERT_FALSE(html.empty());

  // Verified pairs: the console's last view graph (the pass that made the result) adds up, and
  // says what report.json and report.html say.
  const std::smatch graph = LastMatch(
      console, std::regex(R"(view graph: (\d+) image pairs verified of (\d+) sharing tracks \((\d+) with the matching's )"
                          R"(geometry, (\d+) by RANSAC on the tracks\))"));
  ASSERT_FALSE(graph.empty()) << console;
  const int verified = std::stoi(graph[1]), front_end = std::stoi(graph[3]), ransac = std::stoi(graph[4]);
  EXPECT_EQ(verified, front_end + ransac);
  EXPECT_LE(verified, std::stoi(graph[2]));
  EXPECT_EQ(stages["pairs"]["pairs_kept"], verified);
  EXPECT_EQ(stages["pairs"]["pairs_kept_front_end"], front_end);
  EXPECT_EQ(stages["pairs"]["pairs_kept_ransac"], ransac);
  EXPECT_NE(html.find("<h2>View graph</h2><p>" + std::to_string(verified) + " verified pairs"), std::string::npos);
  EXPECT_NE(html.find("<th>image pairs verified (view graph)</th><td>" + std::to_string(verified) + " (" +
                      std::to_string(front_end) + " with the matching's geometry, " + std::to_string(ransac) +
                      " by RANSAC on the tracks)</td>"),
            std::string::npos);

  // Tracks: the last matching's (with the self-calibrated cameras), in the console, report.json
  // and report.html.
  const std::smatch matching = LastMatch(console, std::regex(R"(matching: \d+ of \d+ image pairs verified, (\d+) tracks)"));
  ASSERT_FALSE(matching.empty()) << console;
  const long tracks = std::stol(matching[1]);
  EXPECT_EQ(stages["match_recalibrated"]["tracks"], tracks);
  EXPECT_EQ(DataLines(out / "tracks" / "points3D.txt"), tracks);
  EXPECT_NE(html.find("<th>tracks (points seen in 2 or more images)</th><td>" + std::to_string(tracks) + "</td>"),
            std::string::npos);

  // Points.
  const std::smatch summary =
      LastMatch(console, std::regex(R"(pgba run: (\d+) of (\d+) images registered, (\d+) points, ([0-9.]+) s)"));
  ASSERT_FALSE(summary.empty()) << console;
  const long points = std::stol(summary[3]);
  EXPECT_EQ(std::stoi(summary[1]), 12);
  EXPECT_GT(points, 1000);
  EXPECT_LE(points, tracks);
  EXPECT_NE(console.find("points: " + std::to_string(points) + " of " + std::to_string(tracks) + " tracks triangulated"),
            std::string::npos);
  EXPECT_EQ(stages["triangulation"]["points"], points);
  EXPECT_EQ(r["evaluation"]["details"]["tracks_triangulated"], points);
  const std::smatch evaluated = LastMatch(console, std::regex(R"(tracks triangulated +(\d+) of (\d+) seen in 2 or more)"));
  ASSERT_FALSE(evaluated.empty()) << console;
  EXPECT_EQ(std::stol(evaluated[1]), points);
  EXPECT_EQ(std::stol(evaluated[2]), tracks);  // every image registered: every track is seen twice
  EXPECT_EQ(DataLines(out / "sparse" / "points3D.txt"), points);
  const PlyHeader ply = ReadPlyHeader(out / "points.ply");  // the points, then one vertex per camera
  EXPECT_EQ(ply.points, points);
  EXPECT_EQ(ply.cameras, 12);
  EXPECT_EQ(ply.vertices, ply.points + ply.cameras);
  EXPECT_NE(html.find("<tr><th>points</th><td>" + std::to_string(points) + "</td></tr>"), std::string::npos);

  // Stage times: their sum is the run's time (what is not in a stage is reading the inputs and
  // writing the report: well under a second here), in the order the stages ran.
  double sum = 0.0;
  std::vector<std::pair<int, std::string>> order;
  for (const auto& [name, st] : stages.items()) {
    sum += st["seconds"].get<double>();
    order.push_back({st["order"].get<int>(), name});
  }
  std::sort(order.begin(), order.end());
  const double seconds = r["seconds"].get<double>();
  EXPECT_NEAR(sum, seconds, 0.5 + 0.02 * seconds) << stages.dump(1);
  EXPECT_LE(sum, seconds);
  EXPECT_NEAR(std::stod(summary[4]), seconds, 0.051);
  for (size_t k = 0; k < order.size(); ++k) EXPECT_EQ(order[k].first, static_cast<int>(k)) << order[k].second;
  std::vector<std::string> names;
  for (const auto& [o, name] : order) names.push_back(name);
  const auto at = [&](const std::string& name) {
    return std::find(names.begin(), names.end(), name) - names.begin();
  };
  ASSERT_TRUE(stages.contains("first_pass")) << stages.dump(1);
  ASSERT_TRUE(stages.contains("match_recalibrated"));
  EXPECT_LT(at("match"), at("first_pass"));
  EXPECT_LT(at("first_pass"), at("match_recalibrated"));
  EXPECT_LT(at("match_recalibrated"), at("pairs"));
  EXPECT_LT(at("global_ba"), at("output"));
  for (const char* inner : {"pairs", "triplets", "global_init", "local_hessians", "global_ba", "triangulation"})
    EXPECT_TRUE(stages["first_pass"]["stages"].contains(inner)) << inner;
  double first_pass_inner = 0.0;
  for (const auto& [name, st] : stages["first_pass"]["stages"].items()) first_pass_inner += st["seconds"].get<double>();
  EXPECT_LE(first_pass_inner, stages["first_pass"]["seconds"].get<double>());

  // Camera parameters: the table starts from the prior of cameras.txt (not the second pass's
  // start) and names every parameter; the console names them too.
  const auto prior = pgba::ReadColmapCameras((dir / "scene" / "cameras.txt").string()).begin()->second.params;
  ASSERT_EQ(prior.size(), 4u);  // SIMPLE_RADIAL f cx cy k
  ASSERT_TRUE(r["intrinsics"].is_array() && !r["intrinsics"].empty());
  EXPECT_EQ(r["intrinsics"][0]["prior_params"].get<std::vector<double>>(), prior);
  char f_row[96];
  std::snprintf(f_row, sizeof(f_row), "<td>f</td><td class=\"n\">%.2f</td>", prior[0]);
  EXPECT_NE(html.find(f_row), std::string::npos) << f_row;
  for (const char* name : {"cx", "cy", "k"}) EXPECT_NE(html.find(std::string("<td>") + name + "</td>"), std::string::npos);
  EXPECT_TRUE(std::regex_search(console, std::regex(R"(camera 1 \(SIMPLE_RADIAL\) self-calibrated: f [0-9.]+ -> )")))
      << console;

  // The global BA in one line per pass, what went in and what came out; the solver's internals
  // (its fitting scale, misfit, unknowns, each re-linearisation's local Hessians) and the
  // progress bars' last states, which repeat the stages' own lines, only at -v 2.
  EXPECT_TRUE(std::regex_search(
      console, std::regex(R"(global BA \(pointless\): 12 images, on \d+ local bundle adjustments?, converged in \d+ )"
                          R"(iterations, [0-9.]+ s \(local adjustments [0-9.]+ s\))")))
      << console;
  for (const char* internal : {"fitting scale", "misfit", "unknowns", "motions ok", "triplet residuals", "[#"})
    EXPECT_EQ(console.find(internal), std::string::npos) << internal;
  fs::remove_all(dir);
}

}  // namespace

// pgba match --out WS [--pairs exhaustive|sequential|retrieval] [--window N] [--loop]
//   [--neighbors K] [--threshold PX]
//   -> WS/tracks/ (COLMAP text model of the tracks, the input of `pgba init --tracks`),
//      WS/matching/two_view_geometries.txt, stage "match" in WS/report.json.
// pgba match --database DB.db --out WS
//   -> the same WS/tracks/ from COLMAP's features and verified matches (as GLOMAP does).
#include <filesystem>

#include "apps/commands.h"
#include "apps/output_dir.h"
#include "apps/report_merge.h"
#include "matching/match_images.h"
#include "pgba/io/colmap_database.h"
#include "pgba/io/colmap_text.h"
#include "pgba/util/logging.h"
#include "pgba/io/report.h"
#include "pgba/util/timer.h"

namespace pgba::app {
namespace fs = std::filesystem;

void RegisterMatch(CLI::App& app) {
  struct Args {
    std::string out, database;
    MatchingOptions options;
  };
  auto args = std::make_shared<Args>();
  CLI::App* sub = app.add_subcommand("match", "match, verify and chain features into tracks (WS/tracks/)");
  sub->add_option("--out", args->out, "workspace directory (with features from `pgba features`)")->required();
  sub->add_option("--pairs", args->options.pairs.method, "pair selection: exhaustive, sequential, retrieval")
      ->capture_default_str();
  sub->add_option("--window", args->options.pairs.window, "sequential: images after each image")
      ->check(InConfigRange("matching.pairs.window"))
      ->capture_default_str();
  sub->add_flag("--loop", args->options.pairs.loop, "sequential: wrap the window around (closed rings)");
  sub->add_option("--neighbors", args->options.pairs.vlad.neighbors, "retrieval: most similar images per image")
      ->check(InConfigRange("matching.pairs.vlad.neighbors"))
      ->capture_default_str();
  sub->add_option("--threshold", args->options.verification.relative_pose.threshold_px,
                  "RANSAC inlier threshold, pixels of the (possibly downscaled) images SIFT ran on")
      ->check(InConfigRange("matching.verification.relative_pose.threshold_px"))
      ->capture_default_str();
  sub->add_option("--min-inliers", args->options.verification.relative_pose.min_inliers,
                  "verified pairs need at least this many inliers")
      ->check(InConfigRange("matching.verification.relative_pose.min_inliers"))
      ->capture_default_str();
  sub->add_option("--database", args->database,
                  "import tracks from a COLMAP database.db instead (its verified two_view_geometries)");
  AddCommand(app, sub, [args] {
    CheckOutputDir(args->out, kMatchOutputs, {{"--database", args->database}});
    ForgetStage(args->out, "match", {"tracks", "matching"});
    const fs::path ws(args->out);
    const std::string report = (ws / "report.json").string();
    if (!args->database.empty()) {
      Timer timer;
      TrackStats st;
      const Reconstruction rec =
          TracksFromColmapDatabase(ReadColmapDatabase(args->database), args->options.tracks, &st, args->database);
      fs::create_directories(ws);
      WriteColmapText(rec, (ws / "tracks").string());
      nlohmann::json record = TrackRecord(rec, st);
      record["seconds"] = timer.Seconds();
      record["source"] = args->database;
      MergeStageIntoReport(report, "match", record);
      PGBA_LOG_INFO << "imported " << st.num_tracks << " tracks over " << rec.images.size() << " images from "
                    << args->database;
      return 0;
    }
    const CpuTimer cpu;
    const MatchingResult r = MatchImages(args->out, args->options);
    WriteMatchingResult(args->out, r);
    nlohmann::json record = MatchingRecord(r);
    record["seconds"] = r.seconds;
    record["cpu_seconds"] = cpu.Seconds();
    record["load_average"] = NumberOrNull(LoadAverage1Min());
    record["peak_rss_mb"] = PeakRssMb();
    record["options"] = args->options;
    MergeStageIntoReport(report, "match", record);
    return 0;
  });
}

}  // namespace pgba::app

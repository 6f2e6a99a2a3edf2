// pgba run --images DIR [--calib cameras.txt [--calib-prior]] --out OUT [--config configs/X.json]
//          [--gt GT] [--gcp GCP_FILE]
//
// The whole pipeline from a folder of calibrated photos: features, matching, global
// initialisation, local hessians, pointless global BA. OUT is a resumable workspace (cached
// features and tracks are reused). Outputs: OUT/sparse/0/, OUT/sparse/1/, ... (one COLMAP text
// model per component of the view graph, largest first, each with its points.ply), the
// largest again as OUT/sparse/ and OUT/points.ply, OUT/report.json (every image's fate under
// "image_fates"), OUT/report.html (open it first) and OUT/log.txt. With --gt, each model's poses
// are evaluated against a ground-truth COLMAP model with their own similarity.
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <string>

#include "apps/commands.h"
#include "apps/output_dir.h"
#include "evaluation/model_set_evaluation.h"
#include "mapper/run_pipeline.h"
#include "pgba/io/colmap_text.h"
#include "pgba/io/gcp_file.h"
#include "pgba/util/text_format.h"
#include "pgba/util/timer.h"
#include "pgba/util/atomic_file.h"
#include "pgba/util/error.h"
#include "pgba/util/logging.h"
#include "report/html_report.h"

namespace pgba::app {

void RegisterRun(CLI::App& app) {
  struct Args {
    std::string images, out, config, gt, gcp;
    CalibrationInput calib;
    bool calib_prior = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* sub = app.add_subcommand("run", "Images -> poses and points: every stage, with report.html");
  sub->add_option("--images", args->images, "Folder of photos")->required();
  AddCalibrationOptions(sub, &args->calib);
  sub->add_flag("--calib-prior", args->calib_prior,
                "The calibration file is only a prior: every BA refines its focal and distortion (section "
                "intrinsics; default: a given calibration is held)");
  sub->add_option("--out", args->out, "Output folder (also the resumable workspace)")->required();
  sub->add_option("--config", args->config, "JSON config or a preset of configs/");
  sub->add_option("--gt", args->gt, "Ground-truth COLMAP text model to evaluate the result against");
  sub->add_option("--gcp", args->gcp, "Ground control points (GCP/OBS lines): the result is put in their frame");

  AddCommand(app, sub, [args] {
    namespace fs = std::filesystem;
    const Timer run_timer;  // the whole run, which the stages' seconds add up to
    CheckOutputDir(args->out, kRunOutputs,
                   {{"--images", args->images},
                    {"--calib", args->calib.cameras_path},
                    {"--camera-map", args->calib.camera_map_path},
                    {"--config", args->config},
                    {"--gt", args->gt},
                    {"--gcp", args->gcp}});
    const fs::path out(args->out);
    // First: a re-run refused at its options or inputs must not leave the earlier result.
    RemovePreviousResults(args->out);
    RunOptions options = LoadRunOptions(args->config);
    options.reconstruction.gcp_path = args->gcp;
    options.calibration_is_prior = args->calib_prior;
    if (!args->gcp.empty()) ReadGcpFile(args->gcp);  // a malformed file fails before any work
    Reconstruction gt;
    if (!args->gt.empty()) gt = ReadColmapText(args->gt, /*points_optional=*/true);
    PrepareOutputDir(args->out);
    SetLogFile((out / "log.txt").string());
    Report report;
    report["command"] = "run";
    report["images"] = args->images;
    report["config"] = args->config;
    try {
      const RunOutput result = RunPipeline(args->images, args->calib, args->out, options, &report);
      const PointlessMapperResult& rec = result.reconstruction;
      WriteWorkspaceFingerprint(out, FingerprintOf(result.tracks, options.reconstruction, /*with_hessians=*/true));
      // Each model against the ground truth with its own similarity; "evaluation" is the
      // largest model's, "evaluation_models" every model's images together.
      ModelSetEvaluation evaluation;
      {
        StageTimer timer(&report, "evaluation");
        evaluation = EvaluateModelSet(rec.Models(), result.tracks, args->gt.empty() ? nullptr : &gt);
      }
      const EvaluationMetrics& metrics = evaluation.models.front();
      report["evaluation"] = metrics.ToJson();
      report["evaluation_models"] = evaluation.ToJson();
      for (size_t m = 0; m < evaluation.models.size() && m < report["models"].size(); ++m)
        report["models"][m]["evaluation"] = evaluation.models[m].ToJson();
      std::map<std::string, double> rot_err_deg;
      for (size_t i = 0; i < evaluation.names.size(); ++i) rot_err_deg[evaluation.names[i]] = evaluation.rot_err_deg[i];
      for (nlohmann::json& fate : report["image_fates"])
        if (const auto e = rot_err_deg.find(fate["image"].get<std::string>()); e != rot_err_deg.end())
          fate["rot_err_deg"] = e->second;
      // The page shows the report as it will read; report.json is written after the page, so
      // that a failure writing the page (a full disk) leaves no report.json with status ok.
      report["status"] = "ok";
      report["seconds"] = run_timer.Seconds();
      const std::vector<const Reconstruction*> models = rec.Models();
      HtmlReportInput page;
      page.title = "pgba run: " + args->images;
      page.report = &report.json();
      page.model = &rec.model;
      page.models = &models;
      page.convergence = &rec.convergence.sigma;
      page.convergence_tracks = rec.convergence.tracks_evaluated;
      page.convergence_tracks_total = rec.convergence.tracks_total;
      page.metrics = &metrics;
      // The view graph the reconstruction started from: the pairs the "pairs" stage verified.
      const ViewGraphPicture view_graph = MakeViewGraphPicture(result.tracks, rec.initial.pairs, models);
      page.view_graph = &view_graph;
      WriteStringAtomically((out / "report.html").string(), RunReportHtml(page));
      report.Write((out / "report.json").string());
      // Of several models the table is the largest's; the others' lines follow the summary.
      metrics.PrintTable(std::cout, models.size() == 1 ? "evaluation" : "evaluation of the largest model");
      std::cout << "pgba run: " << evaluation.images_registered << " of " << result.tracks.images.size()
                << " images registered"
                << (models.size() == 1 ? ", " : " in " + std::to_string(models.size()) + " models, ")
                << rec.model.points3D.size() << (models.size() == 1 ? " points, " : " points in the largest, ")
                << FormatNumber("%.1f", report["seconds"].get<double>()) << " s\n";
      for (size_t m = 1; m < models.size(); ++m) {
        std::cout << "model " << m << ": " << models[m]->images.size() << " images, " << models[m]->points3D.size()
                  << " points";
        if (const auto& gt_errors = evaluation.models[m].ground_truth; gt_errors && gt_errors->ok)
          std::cout << ", rotation error vs ground truth median " << FormatNumber("%.3g", gt_errors->rot_err_deg_median)
                    << " deg, max " << FormatNumber("%.3g", gt_errors->rot_err_deg_max) << " deg";
        std::cout << "\n";
      }
      std::cout << "report: " << (out / "report.html").string() << "\n";
    } catch (const std::exception& e) {
      RecordFailure(args->out, e, &report);
      SetLogFile("");
      throw;
    }
    SetLogFile("");
    return 0;
  });
}

}  // namespace pgba::app

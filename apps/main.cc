// pgba: pointless global bundle adjustment, from tracks or images to poses.
#include <iostream>
#include <vector>

#include "apps/commands.h"
#include "pgba/util/error.h"
#include "pgba/util/logging.h"

namespace pgba::app {
namespace {
std::vector<std::pair<CLI::App*, CommandRunner>>& Runners() {
  static std::vector<std::pair<CLI::App*, CommandRunner>> runners;
  return runners;
}
}  // namespace

void AddCommand(CLI::App& app, CLI::App* sub, CommandRunner run) { Runners().emplace_back(sub, std::move(run)); }

void AddCalibrationOptions(CLI::App* sub, pgba::CalibrationInput* calib) {
  sub->add_option("--calib", calib->cameras_path,
                  "COLMAP cameras.txt or a .json calibration (default: cameras.txt in the image folder or its "
                  "parent; none: EXIF focal priors)");
  sub->add_option("--camera-map", calib->camera_map_path,
                  "Lines IMAGE_NAME CAMERA_ID, needed when the calibration has several cameras");
}

}  // namespace pgba::app

int main(int argc, char** argv) {
  using namespace pgba;
  CLI::App app{"pgba: Structure-from-Motion with pointless global bundle adjustment"};
  app.require_subcommand(1);
  int verbosity = 1;
  app.add_option("-v,--verbosity", verbosity, "0 quiet, 1 info (default), 2 debug");
  app::RegisterSynth(app);
  app::RegisterEvaluate(app);
  app::RegisterInit(app);
  app::RegisterFeatures(app);
  app::RegisterMatch(app);
  app::RegisterReconstruct(app);
  app::RegisterBenchmark(app);
  app::RegisterRun(app);
  app::RegisterConvert(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    std::cerr << "error: " << e.what() << "\nRun with --help for usage." << std::endl;
    return kInputErrorExitCode;
  }
  SetLogVerbosity(verbosity);
  try {
    for (auto& [sub, run] : app::Runners())
      if (sub->parsed()) return run();
  } catch (const InputError& e) {
    std::cerr << "error: " << e.what() << std::endl;
    return kInputErrorExitCode;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << std::endl;
    return 1;
  }
  return 0;
}

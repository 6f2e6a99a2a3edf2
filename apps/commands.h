// Each `pgba <subcommand>` lives in its own apps/cmd_<name>.cc and registers itself here.
// A command's callback returns the process exit code; InputError thrown anywhere below is
// turned into "error: <message>" and exit code 2 by main().
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

#include "features/image_catalog.h"
#include "pgba/scene/reconstruction.h"

namespace pgba::app {

using CommandRunner = std::function<int()>;

// Registers a subcommand; `run` is invoked if it was selected on the command line.
void AddCommand(CLI::App& app, CLI::App* sub, CommandRunner run);

// --calib and --camera-map of the commands that read images (features, run).
void AddCalibrationOptions(CLI::App* sub, pgba::CalibrationInput* calib);

// A command-line number that sets a config option (`key`, the dotted config path) is held to
// the option's range in io/option_ranges.cc, as in a config file: "--threshold: -1 is out of
// range (> 0; config key matching.verification.relative_pose.threshold_px)", exit code 2.
CLI::Validator InConfigRange(const std::string& key);

// A number > 0 (>= 0): "--inlier-px: must be > 0, got '0'" (CLI11's own PositiveNumber
// printed its range with the largest double written out in 300 digits).
CLI::Validator PositiveNumber();
CLI::Validator NonNegativeNumber();

// The tracks a reconstruction starts from, with at least 3 images: InputError naming
// `source` (the --tracks model's images.txt or the --database) otherwise, before any stage
// reports the problem without the file.
void RequireEnoughImages(const pgba::Reconstruction& tracks, const std::string& source);

void RegisterSynth(CLI::App& app);
void RegisterEvaluate(CLI::App& app);
void RegisterInit(CLI::App& app);
void RegisterFeatures(CLI::App& app);
void RegisterMatch(CLI::App& app);
void RegisterReconstruct(CLI::App& app);
void RegisterBenchmark(CLI::App& app);
void RegisterRun(CLI::App& app);
void RegisterConvert(CLI::App& app);

}  // namespace pgba::app

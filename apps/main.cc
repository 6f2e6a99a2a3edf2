// pgba: pointless global bundle adjustment, from tracks or images to poses.
#include <tbb/global_control.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <new>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "pgba/io/option_ranges.h"
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

void RequireEnoughImages(const Reconstruction& tracks, const std::string& source) {
  if (tracks.images.size() < 3)
    ThrowInputError(source, 0,
                    std::to_string(tracks.images.size()) + " image(s); a reconstruction needs at least 3 images");
}

namespace {

// The whole of `text` as one number into `v`: "" when it is, else the problem.
std::string ParseNumber(const std::string& text, double* v) {
  char* end = nullptr;
  *v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size()) return "expected a number, got '" + text + "'";
  return "";
}

// A finite number that satisfies `ok`, described as `bound` ("> 0").
CLI::Validator FiniteNumber(bool (*ok)(double), const std::string& bound, const std::string& name) {
  return CLI::Validator(
      [ok, bound](std::string& text) -> std::string {
        double v = 0.0;
        if (std::string problem = ParseNumber(text, &v); !problem.empty()) return problem;
        if (!std::isfinite(v)) return "expected a finite number, got '" + text + "'";
        return ok(v) ? "" : "must be " + bound + ", got '" + text + "'";
      },
      bound, name);
}

}  // namespace

CLI::Validator InConfigRange(const std::string& key) {
  const std::optional<OptionRange> range = RangeOfOption(key);
  if (!range) throw std::logic_error("InConfigRange: no range for " + key + " in io/option_ranges.cc");
  return CLI::Validator(
      [range = *range, key](std::string& text) -> std::string {
        double v = 0.0;
        if (std::string problem = ParseNumber(text, &v); !problem.empty()) return problem;
        if (!range.Contains(v)) return text + " is out of range (" + range.Describe() + "; config key " + key + ")";
        return "";
      },
      range->Describe(), "RANGE");
}

CLI::Validator PositiveNumber() {
  return FiniteNumber([](double v) { return v > 0; }, "> 0", "POSITIVE");
}

CLI::Validator NonNegativeNumber() {
  return FiniteNumber([](double v) { return v >= 0; }, ">= 0", "NONNEGATIVE");
}

// The one parser of command-line numbers: every floating-point option is held to a finite
// value (CLI11's own checks, e.g. Range(0, 1), let NaN through: no comparison fails), and
// every unsigned one to a plain non-negative integer its type holds (CLI11 read "-5" as
// 2^64 - 5 and 10^23 as 2^64 - 1 for a 64-bit seed).
void RequireFiniteNumbers(CLI::App* app) {
  for (CLI::Option* opt : app->get_options()) {
    if (opt->get_type_name().rfind("UINT", 0) == 0) {
      opt->check(CLI::Validator(
          [](std::string& text) -> std::string {
            if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
              return "expected a non-negative integer, got '" + text + "'";
            errno = 0;
            std::strtoull(text.c_str(), nullptr, 10);
            if (errno == ERANGE) return text + " is out of range (at most 18446744073709551615)";
            return "";
          },
          ""));
      continue;
    }
    if (opt->get_type_name().rfind("FLOAT", 0) != 0) continue;
    opt->check(CLI::Validator(
        [](std::string& text) -> std::string {
          char* end = nullptr;
          const double v = std::strtod(text.c_str(), &end);
          if (text.empty() || end != text.c_str() + text.size()) return "expected a number, got '" + text + "'";
          if (!std::isfinite(v)) return "expected a finite number, got '" + text + "'";
          return "";
        },
        ""));
  }
  for (CLI::App* sub : app->get_subcommands([](CLI::App*) { return true; })) RequireFiniteNumbers(sub);
}

// A global option written after the command ("pgba features --threads 1"): CLI11 says only
// that the arguments were not expected. Empty if there is none.
std::string MisplacedGlobalOption(int argc, char** argv, const std::string& command) {
  bool after = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (!after) {
      if (arg == command) after = true;
      else if (arg == "-v" || arg == "--verbosity" || arg == "--threads") ++i;
      continue;
    }
    for (const char* global : {"--threads", "--verbosity", "-v"}) {
      const std::string g = global;
      if (arg == g || arg.rfind(g + "=", 0) == 0)
        return g + ": a global option, placed before the command (pgba " + g + " VALUE " + command + " ...)";
    }
  }
  return "";
}

// The first word that is not a global option or its value: the subcommand the user meant.
// CLI11 reports an unknown one as "arguments were not expected", not naming it as a command.
std::string RequestedCommand(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.empty() || arg[0] != '-') return arg;
    if (arg == "-v" || arg == "--verbosity" || arg == "--threads") ++i;  // their value
  }
  return "";
}

}  // namespace pgba::app

int main(int argc, char** argv) {
  using namespace pgba;
  CLI::App app{"pgba: Structure-from-Motion with pointless global bundle adjustment"};
  app.require_subcommand(1);
  int verbosity = 1;
  app.add_option("-v,--verbosity", verbosity, "0 warnings only, 1 one line per stage (default), 2 every stage's diagnostics")->check(CLI::Range(0, 2));
  int threads = 0;
  app.add_option("--threads", threads,
                 "Worker threads of every parallel stage (0 = all cores). Results do not depend on it: the same "
                 "input gives the same bytes with any thread count")
      ->check(CLI::Range(0, 4096));
  app::RegisterSynth(app);
  app::RegisterEvaluate(app);
  app::RegisterInit(app);
  app::RegisterFeatures(app);
  app::RegisterMatch(app);
  app::RegisterReconstruct(app);
  app::RegisterBenchmark(app);
  app::RegisterRun(app);
  app::RegisterConvert(app);
  app::RequireFiniteNumbers(&app);
  const std::string command = app::RequestedCommand(argc, argv);
  std::string known;
  bool is_command = false;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    known += (known.empty() ? "" : ", ") + sub->get_name();
    is_command = is_command || sub->get_name() == command;
  }
  if (!command.empty() && !is_command) {
    std::cerr << "error: unknown command '" << OneLine(command) << "' (commands: " << known << "; see --help)" << std::endl;
    return kInputErrorExitCode;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    if (const std::string misplaced = app::MisplacedGlobalOption(argc, argv, command); !misplaced.empty()) {
      std::cerr << "error: " << OneLine(misplaced) << std::endl;
      return kInputErrorExitCode;
    }
    // One line, as every other error: the problem, then where the usage is.
    std::cerr << "error: " << OneLine(e.what()) << " (usage: pgba " << (command.empty() ? "" : OneLine(command) + " ")
              << "--help)" << std::endl;
    return kInputErrorExitCode;
  }
  SetLogVerbosity(verbosity);
  // One limit for TBB (every parallel loop, and OpenCV, which Debian builds on TBB).
  std::unique_ptr<tbb::global_control> thread_limit;
  if (threads > 0)
    thread_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);
  try {
    for (auto& [sub, run] : app::Runners())
      if (sub->parsed()) return run();
  } catch (const InputError& e) {
    std::cerr << "error: " << OneLine(e.what()) << std::endl;
    return kInputErrorExitCode;
  } catch (const std::bad_alloc&) {
    std::cerr << "error: out of memory (the input or an option asks for more than this machine has)" << std::endl;
    return 1;
  } catch (const std::filesystem::filesystem_error& e) {
    // A path the checks before did not foresee: one line naming it, not the library's text.
    std::cerr << "error: " << OneLine(e.path1().string()) << ": " << e.code().message() << std::endl;
    return kInputErrorExitCode;
  } catch (const std::exception& e) {
    std::cerr << "error: " << OneLine(e.what()) << std::endl;
    return 1;
  }
  return 0;
}

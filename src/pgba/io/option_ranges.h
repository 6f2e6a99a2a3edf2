// The valid range of every numeric option of a config file, checked when the config is
// read (LoadConfig), so that an option outside its domain is an InputError naming the key
// and the range, e.g.
//   config.json: local_hessian.huber_px = -1 is out of range (> 0)
// instead of a run that quietly degrades (a negative Huber threshold) or ends as "no
// triplet survived" (triplets.outlier_threshold_px = 0).
//
// The ranges are one table keyed by the dotted config path (option_ranges.cc), the names the
// user writes; tests/io/option_ranges_test.cc checks that every numeric option of every
// section has an entry, so an option added to an Options struct without its range fails
// the suite.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace pgba {

struct OptionRange {
  double min = 0, max = 0;
  bool has_min = false, has_max = false;
  bool min_open = false, max_open = false;  // strict bounds
  std::string Describe() const;             // "> 0", ">= 1", "[0, 1]", "(0, 1)", "any"
  bool Contains(double v) const;
};

// The range of the option at `dotted_path` ("local_hessian.huber_px"; array elements as
// "local_motions.neighbour_strides[]"), nullopt if the table has none.
std::optional<OptionRange> RangeOfOption(const std::string& dotted_path);

// Checks every number of `root` (a config: sections of options) against its range; the
// first value out of range is an InputError "ORIGIN: KEY = VALUE is out of range (RANGE)".
// Keys without an entry are not checked here (the coverage test keeps that set empty).
void CheckOptionRanges(const nlohmann::json& root, const std::string& origin);

// The Check() of an Options struct, from the same table: its serialised fields checked under
// `section` (its config path, e.g. "local_hessian", or for a struct that is no config section
// its table prefix, e.g. "SyntheticOptions"). The first invalid value as one line naming the
// key relative to the section and its range ("huber_px = -1 is out of range (> 0)"), empty
// when all are valid.
std::string CheckRangesAt(const nlohmann::json& options, const std::string& section);
template <typename Options>
std::string CheckRanges(const Options& options, const std::string& section) {
  return CheckRangesAt(nlohmann::json(options), section);
}

}  // namespace pgba

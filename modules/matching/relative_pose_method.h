// The method names of a relative-pose estimate (RelativePoseOptions::scoring and ::algorithm,
// EssentialRansacOptions::algorithm): one enum each with its names, read by the matcher's
// parsers (relative_pose.cc, essential_ransac.cc) and by the config check
// (src/pgba/io/option_ranges.cc), so that a method added here is accepted by both or by
// neither. Header-only: the config check sits in pgba_core, below the matching library, and
// needs the names without linking it.
#pragma once

#include <array>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace pgba {

// How RANSAC scores a hypothesis (relative_pose.h, RelativePoseOptions::scoring).
enum class PoseScoring { kSampson, kOpenGv };
inline constexpr std::array<std::pair<PoseScoring, std::string_view>, 2> kPoseScoringNames{{
    {PoseScoring::kSampson, "sampson"},
    {PoseScoring::kOpenGv, "opengv"},
}};

// The minimal 5-point solver (OpenGV's).
enum class PoseSolver { kStewenius, kNister };
inline constexpr std::array<std::pair<PoseSolver, std::string_view>, 2> kPoseSolverNames{{
    {PoseSolver::kStewenius, "stewenius"},
    {PoseSolver::kNister, "nister"},
}};

// The names of a table in its order ("sampson", "opengv"): the config check's choices.
template <typename Enum, size_t N>
std::vector<std::string> MethodNames(const std::array<std::pair<Enum, std::string_view>, N>& table) {
  std::vector<std::string> names;
  for (const auto& entry : table) names.emplace_back(entry.second);
  return names;
}

// The enum value of `name`; std::invalid_argument "unknown relative pose WHAT 'NAME'
// (a, b)" for a name not in the table (an API caller that bypassed the config check).
template <typename Enum, size_t N>
Enum ParseMethod(const std::array<std::pair<Enum, std::string_view>, N>& table, const std::string& name,
                 const char* what) {
  std::string list;
  for (const auto& [value, n] : table) {
    if (name == n) return value;
    list += (list.empty() ? "" : ", ") + std::string(n);
  }
  throw std::invalid_argument(std::string("unknown relative pose ") + what + " '" + name + "' (" + list + ")");
}

inline PoseScoring ParsePoseScoring(const std::string& name) { return ParseMethod(kPoseScoringNames, name, "scoring"); }
inline PoseSolver ParsePoseSolver(const std::string& name) { return ParseMethod(kPoseSolverNames, name, "algorithm"); }

}  // namespace pgba

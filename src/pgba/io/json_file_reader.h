// A JSON file read with every problem reported as a one-line InputError "FILE[:LINE]: WHERE:
// problem" (parse errors with their line). The base of the workspace artefact readers
// (workspace_json.h) and of the calibration file (calibration_json.h).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

namespace pgba {

// Parses JSON text as every reader of pgba does: a syntax error is an InputError
// "ORIGIN:LINE: malformed JSON at column C: ...", and so are the two things nlohmann accepts
// or reports raw: a duplicate key (nlohmann silently keeps the last one, so a config could
// say two things at once) and a number beyond double range (1e999).
nlohmann::json ParseJsonStrictly(const std::string& text, const std::string& origin);

class JsonFileReader {
 public:
  explicit JsonFileReader(std::string path) : path_(std::move(path)) {}

  const std::string& path() const { return path_; }
  [[noreturn]] void Fail(const std::string& where, const std::string& problem) const;
  // The whole file parsed (ReadRegularFile, then ParseJsonStrictly).
  nlohmann::json Parse() const;
  const nlohmann::json& Field(const nlohmann::json& j, const char* key, const std::string& where) const;
  double Number(const nlohmann::json& j, const std::string& where) const;  // finite
  int64_t Integer(const nlohmann::json& j, const std::string& where) const;
  template <int N>
  Eigen::Matrix<double, N, 1> Numbers(const nlohmann::json& j, const std::string& where) const {
    return Numbers(j, N, where);
  }
  // An array of exactly n finite numbers.
  Eigen::VectorXd Numbers(const nlohmann::json& j, int n, const std::string& where) const {
    if (!j.is_array() || static_cast<int>(j.size()) != n)
      Fail(where, "expected an array of " + std::to_string(n) + " numbers");
    Eigen::VectorXd v(n);
    for (int k = 0; k < n; ++k) v(k) = Number(j[k], where);
    return v;
  }

 private:
  std::string path_;
};

}  // namespace pgba

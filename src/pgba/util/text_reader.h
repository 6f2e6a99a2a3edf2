// Line-oriented parsing of text inputs (COLMAP models, loop pairs, calibrations) with
// strict number parsing: a token that is not a finite number is an InputError naming the
// file and line. Comment lines ('#') and blank lines are skipped.
#pragma once

#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace pgba {

class TextReader {
 public:
  // Throws InputError if the file cannot be opened.
  explicit TextReader(const std::string& path);

  // Next non-comment, non-blank line split on whitespace; false at end of file.
  bool NextLine(std::vector<std::string>* tokens);
  // The very next line, blank or not, split on whitespace; false (and no tokens) at end of
  // file. For formats where an empty line carries meaning (COLMAP's POINTS2D lines).
  bool NextRawLine(std::vector<std::string>* tokens);
  // The raw text of the last line returned, from its token number `first_token` (0-based)
  // to the end, trailing whitespace removed: for a last field that may contain spaces
  // (COLMAP image names). Empty if the line has fewer tokens.
  std::string RestOfLine(size_t first_token) const;
  // The raw text of the last line returned (for messages).
  const std::string& raw_line() const { return raw_; }
  int line_number() const { return line_number_; }
  const std::string& path() const { return path_; }

  [[noreturn]] void Fail(const std::string& problem) const;

  // Strict conversions of tokens of the current line: the whole token must be a finite
  // number (NaN and Inf rejected) / a base-10 integer in int64 range.
  double ToDouble(const std::string& token, const char* what) const;
  int64_t ToInt(const std::string& token, const char* what) const;
  // Throws unless the current line has at least `n` tokens.
  void RequireTokens(const std::vector<std::string>& tokens, size_t n, const char* what) const;
  // A token made safe for a one-line message (control bytes escaped, long tokens cut).
  static std::string Printable(const std::string& token);

 private:
  static constexpr const char* kSpace = " \t\n\v\f\r";
  std::string path_;
  std::ifstream in_;
  std::string raw_;
  int line_number_ = 0;
};

}  // namespace pgba

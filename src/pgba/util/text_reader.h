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
  // The raw text of the last line returned (for messages).
  const std::string& raw_line() const { return raw_; }
  int line_number() const { return line_number_; }
  const std::string& path() const { return path_; }

  [[noreturn]] void Fail(const std::string& problem) const;

  // Strict conversions of tokens of the current line.
  double ToDouble(const std::string& token, const char* what) const;
  int64_t ToInt(const std::string& token, const char* what) const;
  // Throws unless the current line has at least `n` tokens.
  void RequireTokens(const std::vector<std::string>& tokens, size_t n, const char* what) const;

 private:
  std::string path_;
  std::ifstream in_;
  std::string raw_;
  int line_number_ = 0;
};

}  // namespace pgba

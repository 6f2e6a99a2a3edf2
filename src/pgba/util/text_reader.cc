#include "pgba/util/text_reader.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "pgba/util/error.h"

namespace pgba {

TextReader::TextReader(const std::string& path) : path_(path) {
  if (!std::filesystem::exists(path)) ThrowInputError(path, 0, "file not found");
  if (std::filesystem::is_directory(path)) ThrowInputError(path, 0, "is a directory, expected a file");
  in_.open(path);
  if (!in_) ThrowInputError(path, 0, "cannot open file for reading");
}

bool TextReader::NextLine(std::vector<std::string>* tokens) {
  tokens->clear();
  while (std::getline(in_, raw_)) {
    ++line_number_;
    if (!raw_.empty() && raw_.back() == '\r') raw_.pop_back();
    size_t first = raw_.find_first_not_of(" \t");
    if (first == std::string::npos || raw_[first] == '#') continue;
    std::istringstream ss(raw_);
    std::string tok;
    while (ss >> tok) tokens->push_back(tok);
    return true;
  }
  if (in_.bad()) Fail("read error");
  return false;
}

bool TextReader::NextRawLine(std::vector<std::string>* tokens) {
  tokens->clear();
  if (!std::getline(in_, raw_)) {
    if (in_.bad()) Fail("read error");
    return false;
  }
  ++line_number_;
  std::istringstream ss(raw_);
  std::string tok;
  while (ss >> tok) tokens->push_back(tok);
  return true;
}

void TextReader::Fail(const std::string& problem) const { ThrowInputError(path_, line_number_, problem); }

double TextReader::ToDouble(const std::string& token, const char* what) const {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(token.c_str(), &end);
  if (end == token.c_str() || *end != '\0' || errno == ERANGE)
    Fail(std::string("invalid number '") + token + "' for " + what);
  if (!std::isfinite(v)) Fail(std::string("non-finite value '") + token + "' for " + what);
  return v;
}

int64_t TextReader::ToInt(const std::string& token, const char* what) const {
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(token.c_str(), &end, 10);
  if (end == token.c_str() || *end != '\0' || errno == ERANGE)
    Fail(std::string("invalid integer '") + token + "' for " + what);
  return v;
}

void TextReader::RequireTokens(const std::vector<std::string>& tokens, size_t n, const char* what) const {
  if (tokens.size() < n)
    Fail(std::string("truncated line: ") + what + " needs " + std::to_string(n) + " fields, found " +
         std::to_string(tokens.size()));
}

}  // namespace pgba

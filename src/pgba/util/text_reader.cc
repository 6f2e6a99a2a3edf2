#include "pgba/util/text_reader.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "pgba/util/error.h"
#include "pgba/util/input_file.h"

namespace pgba {

TextReader::TextReader(const std::string& path) : path_(path) {
  RequireRegularFile(path);
  in_.open(path, std::ios::binary);
  if (!in_) ThrowInputError(path, 0, "cannot open file for reading");
}

bool TextReader::NextLine(std::vector<std::string>* tokens) {
  tokens->clear();
  while (std::getline(in_, raw_)) {
    ++line_number_;
    if (!raw_.empty() && raw_.back() == '\r') raw_.pop_back();
    // Blank by the same whitespace that splits the tokens: a line of "\r\r", "\v" or "\f" has no
    // token, and returning it gave the parsers an empty line to index (tok[0]; libFuzzer).
    size_t first = raw_.find_first_not_of(kSpace);
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
  if (!raw_.empty() && raw_.back() == '\r') raw_.pop_back();
  std::istringstream ss(raw_);
  std::string tok;
  while (ss >> tok) tokens->push_back(tok);
  return true;
}

void TextReader::Fail(const std::string& problem) const { ThrowInputError(path_, line_number_, problem); }

std::string TextReader::RestOfLine(size_t first_token) const {
  size_t pos = 0;
  for (size_t k = 0;; ++k) {
    pos = raw_.find_first_not_of(kSpace, pos);
    if (pos == std::string::npos || k == first_token) break;
    pos = raw_.find_first_of(kSpace, pos);
  }
  if (pos == std::string::npos) return "";
  const size_t last = raw_.find_last_not_of(kSpace);
  return raw_.substr(pos, last + 1 - pos);
}

double TextReader::ToDouble(const std::string& token, const char* what) const {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(token.c_str(), &end);
  // The whole token must be the number (an embedded NUL byte ends strtod early).
  if (token.empty() || end != token.c_str() + token.size())
    Fail(std::string("invalid number '") + Printable(token) + "' for " + what);
  // ERANGE is also set on underflow to a subnormal, which is a valid value (written by
  // %.17g, it must round-trip); only overflow is an error.
  if (errno == ERANGE && std::isinf(v))
    Fail(std::string("invalid number '") + Printable(token) + "' for " + what + ": out of range");
  if (!std::isfinite(v)) Fail(std::string("non-finite value '") + Printable(token) + "' for " + what);
  return v;
}

int64_t TextReader::ToInt(const std::string& token, const char* what) const {
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(token.c_str(), &end, 10);
  if (token.empty() || end != token.c_str() + token.size() || errno == ERANGE)
    Fail(std::string("invalid integer '") + Printable(token) + "' for " + what);
  return v;
}

std::string TextReader::Printable(const std::string& token) {
  // Messages are one line (control bytes of a corrupt file shown escaped), very long tokens cut.
  return OneLine(token.substr(0, 40)) + (token.size() > 40 ? "..." : "");
}

void TextReader::RequireTokens(const std::vector<std::string>& tokens, size_t n, const char* what) const {
  if (tokens.size() < n)
    Fail(std::string("truncated line: ") + what + " needs " + std::to_string(n) + " fields, found " +
         std::to_string(tokens.size()));
}

}  // namespace pgba

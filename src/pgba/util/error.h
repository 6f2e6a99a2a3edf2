// Errors that end a run with a clear one-line message.
//
// InputError is thrown for anything the user handed us that we cannot use (missing
// file, malformed line, NaN, unresolved id, unknown option value). The CLI catches it,
// prints "error: <what>" and exits with code 2. The message always names the file (and
// the line where there is one) so the user can go straight to the problem.
#pragma once

#include <stdexcept>
#include <string>

namespace pgba {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& what) : std::runtime_error(what) {}
};

// "FILE:LINE: problem" (LINE omitted when <= 0).
std::string FormatInputError(const std::string& file, int line, const std::string& problem);

[[noreturn]] void ThrowInputError(const std::string& file, int line, const std::string& problem);

// `text` as one line: control characters (a line break in a path the user gave, in a name
// read from a file) shown as \xNN, so that an error message is always exactly one line.
std::string OneLine(const std::string& text);

// Exit code used by the CLI for unusable input.
constexpr int kInputErrorExitCode = 2;

}  // namespace pgba

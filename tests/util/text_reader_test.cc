// The strict line reader every text input goes through: line numbering, comments and blank
// lines, raw lines, exact number parsing, and errors of the form "FILE:LINE: problem".
#include "pgba/util/text_reader.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "pgba/util/error.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

class TextReaderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = (fs::temp_directory_path() /
             ("pgba_text_reader_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
              "_" + std::to_string(::getpid()) + ".txt"))
                .string();
  }
  void TearDown() override { fs::remove(path_); }
  void Write(const std::string& content) {
    std::ofstream out(path_, std::ios::binary | std::ios::trunc);
    out << content;
  }
  // The InputError message of f(), or "" if none is thrown.
  template <typename F>
  static std::string ErrorOf(F f) {
    try {
      f();
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  std::string path_;
};

using Tokens = std::vector<std::string>;

TEST_F(TextReaderTest, NextLineSkipsCommentsAndBlankLinesCountingThem) {
  // Lines 7-9 hold only whitespace the tokenizer splits on ("\r\r": one CR is the line end's).
  Write("# header\n\n  \t\na b  c\n   # indented comment\n\t1\t2 \r\n\r\r\n \v\f\n\r \r\nlast without newline");
  TextReader r(path_);
  Tokens t;
  ASSERT_TRUE(r.NextLine(&t));
  EXPECT_EQ(t, Tokens({"a", "b", "c"}));
  EXPECT_EQ(r.line_number(), 4);
  ASSERT_TRUE(r.NextLine(&t));
  EXPECT_EQ(t, Tokens({"1", "2"}));
  EXPECT_EQ(r.line_number(), 6);
  EXPECT_EQ(r.raw_line(), "\t1\t2 ");  // CR of a CRLF line end removed
  ASSERT_TRUE(r.NextLine(&t));
  EXPECT_EQ(t, Tokens({"last", "without", "newline"}));
  EXPECT_EQ(r.line_number(), 10);
  EXPECT_FALSE(r.NextLine(&t));
  EXPECT_TRUE(t.empty());
  EXPECT_FALSE(r.NextLine(&t));
}

TEST_F(TextReaderTest, NextRawLineReturnsBlankLines) {
  Write("head\n\n# not a comment here\nx y\r\n");
  TextReader r(path_);
  Tokens t;
  ASSERT_TRUE(r.NextLine(&t));
  ASSERT_TRUE(r.NextRawLine(&t));
  EXPECT_TRUE(t.empty());
  EXPECT_EQ(r.line_number(), 2);
  ASSERT_TRUE(r.NextRawLine(&t));
  EXPECT_EQ(t, Tokens({"#", "not", "a", "comment", "here"}));
  ASSERT_TRUE(r.NextRawLine(&t));
  EXPECT_EQ(t, Tokens({"x", "y"}));
  EXPECT_EQ(r.raw_line(), "x y");
  EXPECT_FALSE(r.NextRawLine(&t));
  EXPECT_TRUE(t.empty());
  EXPECT_EQ(r.line_number(), 4);
}

TEST_F(TextReaderTest, RestOfLineKeepsInnerSpacing) {
  Write("  1 2\t 3 my  file\tname.jpg  \t\n1 2\n");
  TextReader r(path_);
  Tokens t;
  ASSERT_TRUE(r.NextLine(&t));
  EXPECT_EQ(r.RestOfLine(3), "my  file\tname.jpg");
  EXPECT_EQ(r.RestOfLine(0), "1 2\t 3 my  file\tname.jpg");
  EXPECT_EQ(r.RestOfLine(5), "name.jpg");
  EXPECT_EQ(r.RestOfLine(6), "");
  ASSERT_TRUE(r.NextLine(&t));
  EXPECT_EQ(r.RestOfLine(1), "2");
  EXPECT_EQ(r.RestOfLine(2), "");
}

TEST_F(TextReaderTest, ToDoubleIsStrict) {
  Write("line one\nline two\n");
  TextReader r(path_);
  Tokens t;
  r.NextLine(&t);
  r.NextLine(&t);
  EXPECT_EQ(r.ToDouble("1", "x"), 1.0);
  EXPECT_EQ(r.ToDouble("-2.5e3", "x"), -2500.0);
  EXPECT_EQ(r.ToDouble("0.10000000000000001", "x"), 0.1);
  EXPECT_TRUE(std::signbit(r.ToDouble("-0", "x")));
  EXPECT_EQ(r.ToDouble("4.9406564584124654e-324", "x"), 4.9406564584124654e-324);  // subnormal round-trips
  EXPECT_EQ(r.ToDouble("1.7976931348623157e308", "x"), 1.7976931348623157e308);
  const std::string at = path_ + ":2: ";
  EXPECT_EQ(ErrorOf([&] { r.ToDouble("abc", "QW"); }), at + "invalid number 'abc' for QW");
  EXPECT_EQ(ErrorOf([&] { r.ToDouble("", "QW"); }), at + "invalid number '' for QW");
  EXPECT_EQ(ErrorOf([&] { r.ToDouble("1.5x", "QW"); }), at + "invalid number '1.5x' for QW");
  EXPECT_EQ(ErrorOf([&] { r.ToDouble("nan", "X"); }), at + "non-finite value 'nan' for X");
  EXPECT_EQ(ErrorOf([&] { r.ToDouble("-inf", "X"); }), at + "non-finite value '-inf' for X");
  EXPECT_EQ(ErrorOf([&] { r.ToDouble("1e999", "X"); }), at + "invalid number '1e999' for X: out of range");
  EXPECT_EQ(ErrorOf([&] { r.ToDouble("-1e999", "X"); }), at + "invalid number '-1e999' for X: out of range");
  EXPECT_EQ(r.ToDouble("1e-400", "x"), 0.0);  // underflow to zero, as C does
  // An embedded NUL byte must not cut the token short.
  EXPECT_EQ(ErrorOf([&] { r.ToDouble(std::string("1\0" "5", 3), "X"); }), at + "invalid number '1\\x005' for X");
  // Long tokens are cut in messages, which stay on one line.
  const std::string msg = ErrorOf([&] { r.ToDouble(std::string(100, 'z') + "\n", "X"); });
  EXPECT_NE(msg.find("zzz..."), std::string::npos);
  EXPECT_EQ(msg.find('\n'), std::string::npos);
}

TEST_F(TextReaderTest, ToIntIsStrict) {
  Write("only line\n");
  TextReader r(path_);
  Tokens t;
  r.NextLine(&t);
  EXPECT_EQ(r.ToInt("0", "id"), 0);
  EXPECT_EQ(r.ToInt("-1", "id"), -1);
  EXPECT_EQ(r.ToInt("9223372036854775807", "id"), INT64_MAX);
  const std::string at = path_ + ":1: ";
  for (const char* bad : {"1.0", "", "1e3", "0x10", "12a", "9223372036854775808", "-9223372036854775809", "nan"})
    EXPECT_EQ(ErrorOf([&] { r.ToInt(bad, "IMAGE_ID"); }), at + "invalid integer '" + bad + "' for IMAGE_ID") << bad;
}

TEST_F(TextReaderTest, FailAndRequireTokensNameFileAndLine) {
  Write("a\nb c\n");
  TextReader r(path_);
  Tokens t;
  r.NextLine(&t);
  r.NextLine(&t);
  EXPECT_EQ(ErrorOf([&] { r.RequireTokens(t, 3, "pair line"); }),
            path_ + ":2: truncated line: pair line needs 3 fields, found 2");
  EXPECT_EQ(ErrorOf([&] { r.RequireTokens(t, 2, "pair line"); }), "");
  EXPECT_EQ(ErrorOf([&] { r.Fail("something wrong"); }), path_ + ":2: something wrong");
  EXPECT_EQ(r.path(), path_);
  // Before any line: no line number.
  TextReader fresh(path_);
  EXPECT_EQ(ErrorOf([&] { fresh.Fail("empty"); }), path_ + ": empty");
}

TEST_F(TextReaderTest, MissingFileAndDirectory) {
  EXPECT_EQ(ErrorOf([&] { TextReader r(path_ + ".missing"); }), path_ + ".missing: file not found");
  const std::string dir = path_ + ".d";
  fs::create_directory(dir);
  EXPECT_EQ(ErrorOf([&] { TextReader r(dir); }), dir + ": is a directory, expected a file");
  fs::remove(dir);
  // A path through a regular file.
  Write("x\n");
  EXPECT_NE(ErrorOf([&] { TextReader r(path_ + "/child"); }).rfind(path_ + "/child: ", 0), std::string::npos);
}

TEST_F(TextReaderTest, EmptyFile) {
  Write("");
  TextReader r(path_);
  Tokens t;
  EXPECT_FALSE(r.NextLine(&t));
  EXPECT_FALSE(r.NextRawLine(&t));
  EXPECT_EQ(r.line_number(), 0);
}

}  // namespace
}  // namespace pgba

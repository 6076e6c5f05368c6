#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sl_rig/tool_args.h"

namespace
{
/// Runs @p read over the arguments @p words (after a program name); returns the error, "" if none.
template <typename F>
std::string parse(std::vector<std::string> words, F read)
{
  words.insert(words.begin(), "tool");
  std::vector<char*> argv;
  for (std::string& w : words)
    argv.push_back(&w[0]);
  try
  {
    sl_rig::ToolArgs args(static_cast<int>(argv.size()), argv.data());
    read(args);
  }
  catch (const std::invalid_argument& e)
  {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(ToolArgs, OptionsValuesAndNumbers)
{
  std::string csv, flag;
  long long frames = 0;
  double ambient = 0.0;
  const std::string error = parse({ "--csv", "out.csv", "--flag", "--frames", "12", "--ambient", "-0.25" },
                                  [&](sl_rig::ToolArgs& args)
                                  {
                                    for (std::string a; args.next(a);)
                                      if (a == "--csv")
                                        csv = args.value();
                                      else if (a == "--frames")
                                        frames = args.integer(1, 100);
                                      else if (a == "--ambient")
                                        ambient = args.number(-1.0, 1.0);
                                      else if (a == "--flag")
                                        flag = a;
                                      else
                                        args.unknown();
                                  });
  EXPECT_EQ(error, "");
  EXPECT_EQ(csv, "out.csv");
  EXPECT_EQ(flag, "--flag");
  EXPECT_EQ(frames, 12);
  EXPECT_DOUBLE_EQ(ambient, -0.25);
}

TEST(ToolArgs, BadInputIsRefusedNamingTheOption)
{
  const auto readFrames = [](sl_rig::ToolArgs& args)
  {
    for (std::string a; args.next(a);)
      if (a == "--frames")
        args.integer(1, 100);
      else if (a == "--ambient")
        args.number();
      else
        args.unknown();
  };
  // std::stoi read "3x" as 3 and said only "stoi" for "abc".
  EXPECT_EQ(parse({ "--frames", "3x" }, readFrames), "--frames: expects an integer in [1, 100], got '3x'");
  EXPECT_EQ(parse({ "--frames", "abc" }, readFrames), "--frames: expects an integer in [1, 100], got 'abc'");
  EXPECT_EQ(parse({ "--frames", "0" }, readFrames), "--frames: expects an integer in [1, 100], got '0'");
  EXPECT_EQ(parse({ "--frames", "" }, readFrames), "--frames: expects an integer in [1, 100], got ''");
  EXPECT_EQ(parse({ "--ambient", "nan" }, readFrames), "--ambient: expects a number, got 'nan'");
  EXPECT_EQ(parse({ "--ambient", "1e999" }, readFrames), "--ambient: expects a number, got '1e999'");
  EXPECT_EQ(parse({ "--frames" }, readFrames), "--frames needs a value");
  EXPECT_EQ(parse({ "--bogus" }, readFrames), "unknown option --bogus");
}

// Running a command from a test and reading what it prints: a node that must refuse a parameter, a
// tool, a device utility.
#pragma once

#include <array>
#include <cstdio>
#include <string>

#include <sys/wait.h>

namespace sl_testing
{
/**
 * @brief Runs @p command in a shell and appends its standard output to @p output.
 * @return its exit status; -1 if it could not be started or did not exit normally (a signal)
 */
inline int runShell(const std::string& command, std::string& output)
{
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe)
    return -1;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0)
    output.append(buf.data(), n);
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// @brief runShell() with standard error on standard output: @p output gets both.
inline int run(const std::string& command, std::string& output)
{
  return runShell(command + " 2>&1", output);
}
}  // namespace sl_testing

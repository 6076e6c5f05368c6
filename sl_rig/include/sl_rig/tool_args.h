#pragma once
/// @file tool_args.h
/// @brief The command-line reader of the stack's tools (sl_pattern, sl_decode, sl_calibrate_*,
/// sl_eval, sl_render): options with values, numbers parsed whole and range-checked, every error
/// naming the option (header-only, no ROS).

#include <cerrno>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace sl_rig
{

/**
 * @brief Walks argv option by option.
 *
 * @code
 *   ToolArgs args(argc, argv);
 *   for (std::string option; args.next(option);)
 *     if (option == "--csv") csv = args.value();
 *     else if (option == "--frames") frames = args.integer(1, 1000);
 *     else args.unknown();
 * @endcode
 *
 * Errors are std::invalid_argument whose message starts with the option ("--frames: expects an
 * integer in [1, 1000], got '3x'"); `std::stoi` would read "3x" as 3 and report "abc" as "stoi".
 */
class ToolArgs
{
public:
  /// @brief Reads the arguments from argv[@p first] on (1: after the program name).
  ToolArgs(int argc, char** argv, int first = 1) : argc_(argc), argv_(argv), index_(first - 1) {}

  /// @brief Moves to the next argument; false when there is none. Sets @p option to it.
  bool next(std::string& option)
  {
    if (index_ + 1 >= argc_)
      return false;
    option_ = argv_[++index_];
    option = option_;
    return true;
  }

  /// @brief The value that follows the current option.
  /// @throws std::invalid_argument "<option> needs a value" at the end of the arguments.
  std::string value()
  {
    if (index_ + 1 >= argc_)
      throw std::invalid_argument(option_ + " needs a value");
    return argv_[++index_];
  }

  /// @brief The value as an integer in [@p lo, @p hi], all of it a number.
  long long integer(long long lo = std::numeric_limits<long long>::lowest(),
                    long long hi = std::numeric_limits<long long>::max())
  {
    const std::string text = value();
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || errno == ERANGE || v < lo || v > hi)
      refuse("an integer", lo, hi, text);
    return v;
  }

  /// @brief The value as a finite number in [@p lo, @p hi], all of it a number.
  double number(double lo = std::numeric_limits<double>::lowest(), double hi = std::numeric_limits<double>::max())
  {
    const std::string text = value();
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || errno == ERANGE || !(v >= lo && v <= hi))
      refuse("a number", lo, hi, text);
    return v;
  }

  /// @brief The current option.
  const std::string& option() const { return option_; }

  /// @brief Throws "unknown option <option>".
  [[noreturn]] void unknown() const { throw std::invalid_argument("unknown option " + option_); }

private:
  template <typename T>
  [[noreturn]] void refuse(const char* what, T lo, T hi, const std::string& text) const
  {
    std::ostringstream s;
    s << option_ << ": expects " << what;
    if (lo != std::numeric_limits<T>::lowest() || hi != std::numeric_limits<T>::max())
      s << " in [" << lo << ", " << hi << "]";
    s << ", got '" << text << "'";
    throw std::invalid_argument(s.str());
  }

  int argc_;
  char** argv_;
  int index_;
  std::string option_;
};

}  // namespace sl_rig

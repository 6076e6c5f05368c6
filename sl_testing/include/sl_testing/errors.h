// What a test asks of a refusal: the message of the std::invalid_argument thrown (every validate()
// of the stack throws one that starts with the parameter's name).
#pragma once

#include <stdexcept>
#include <string>

namespace sl_testing
{
/// @brief The message of the std::invalid_argument that @p f throws; "" when it throws none.
template <class F>
std::string invalidArgumentOf(F f)
{
  try
  {
    f();
  }
  catch (const std::invalid_argument& e)
  {
    return e.what();
  }
  return "";
}

/// @brief The message of the std::invalid_argument that @p config.validate() throws; "" when valid.
template <class Config>
std::string validationError(const Config& config)
{
  return invalidArgumentOf([&] { config.validate(); });
}
}  // namespace sl_testing

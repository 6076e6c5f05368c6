// What a test asks of a refusal: the message of the std::invalid_argument thrown (every validate()
// of the stack throws one that starts with the parameter's name).
#pragma once

#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

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
/**
 * @brief Whether a default @p Config changed by @p change is refused by its validate() with a message
 * that starts with @p name (the parameter's name), for EXPECT_TRUE.
 */
template <class Config, class Change>
::testing::AssertionResult refusedNaming(const std::string& name, Change change)
{
  Config config;
  change(config);
  const std::string error = validationError(config);
  if (error.rfind(name, 0) == 0)
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "expected a refusal starting with \"" << name << "\", got \"" << error
                                       << "\"";
}
}  // namespace sl_testing

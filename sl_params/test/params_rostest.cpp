#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <ros/ros.h>

#include <sl_testing/errors.h>
#include <sl_testing/rostest_main.h>

#include "sl_params/params.h"

using sl_testing::invalidArgumentOf;

namespace
{
/// The part of a generated dynamic_reconfigure Config that checkReconfigureTypes() reads.
template <const char* const* kNames, const char* const* kTypes, size_t kCount>
struct FakeConfig
{
  struct Description
  {
    std::string name, type;
  };
  static std::vector<std::shared_ptr<const Description>> __getParamDescriptions__()
  {
    std::vector<std::shared_ptr<const Description>> d;
    for (size_t i = 0; i < kCount; ++i)
      d.push_back(std::make_shared<const Description>(Description{ kNames[i], kTypes[i] }));
    return d;
  }
};
constexpr const char* kGoodNames[] = { "an_int", "a_double", "an_int_for_a_double", "a_bool", "a_string", "not_set" };
constexpr const char* kGoodTypes[] = { "int", "double", "double", "bool", "str", "int" };
constexpr const char* kBadNames[] = { "a_double", "a_string_for_a_double", "an_int" };
constexpr const char* kBadTypes[] = { "double", "double", "int" };
}  // namespace

TEST(Params, ReconfigureTypesAreCheckedForEveryParameterOfAConfig)
{
  const ros::NodeHandle pnh("~");
  EXPECT_EQ(invalidArgumentOf([&] { sl_params::checkReconfigureTypes<FakeConfig<kGoodNames, kGoodTypes, 6>>(pnh); }),
            "");
  EXPECT_EQ(invalidArgumentOf([&] { sl_params::checkReconfigureTypes<FakeConfig<kBadNames, kBadTypes, 3>>(pnh); }),
            "~a_string_for_a_double must be a number, got a string");
}

TEST(Params, ValuesOfTheRightTypeAreRead)
{
  const ros::NodeHandle pnh("~");
  EXPECT_EQ(sl_params::read(pnh, "an_int", 0), 3);
  EXPECT_DOUBLE_EQ(sl_params::read(pnh, "a_double", 0.0), 0.25);
  EXPECT_FLOAT_EQ(sl_params::read(pnh, "a_double", 0.f), 0.25f);
  EXPECT_DOUBLE_EQ(sl_params::read(pnh, "an_int_for_a_double", 0.0), 2.0);
  EXPECT_TRUE(sl_params::read(pnh, "a_bool", false));
  EXPECT_EQ(sl_params::read(pnh, "a_string", "x"), "abc");
  EXPECT_EQ(sl_params::required<int>(pnh, "an_int"), 3);
  EXPECT_EQ(sl_params::read(pnh, "a_list", std::vector<double>()), std::vector<double>({ 0.5, 1.0, 2.5 }));
}

TEST(Params, MissingValuesTakeTheFallback)
{
  const ros::NodeHandle pnh("~");
  EXPECT_EQ(sl_params::read(pnh, "not_set", 7), 7);
  EXPECT_EQ(sl_params::read(pnh, "not_set", "default"), "default");
  double v = 1.5;
  EXPECT_FALSE(sl_params::readIfSet(pnh, "not_set", v));
  EXPECT_DOUBLE_EQ(v, 1.5);
}

TEST(Params, WrongTypesAreRefusedNamingTheParameter)
{
  const ros::NodeHandle pnh("~");
  EXPECT_EQ(invalidArgumentOf([&] { sl_params::read(pnh, "a_string_for_a_double", 0.5); }),
            "~a_string_for_a_double must be a number, got a string");
  EXPECT_EQ(invalidArgumentOf([&] { sl_params::read(pnh, "a_double_for_an_int", 1); }),
            "~a_double_for_an_int must be an integer, got a number");
  EXPECT_EQ(invalidArgumentOf([&] { sl_params::read(pnh, "a_number_for_a_bool", false); }),
            "~a_number_for_a_bool must be a boolean, got an integer");
  EXPECT_EQ(invalidArgumentOf([&] { sl_params::read(pnh, "an_int", std::string()); }),
            "~an_int must be a string, got an integer");
  EXPECT_EQ(sl_params::read<uint64_t>(pnh, "an_int", 0), 3u);  // unsigned 64-bit: range compared unsigned
  EXPECT_EQ(invalidArgumentOf([&] { sl_params::read<uint8_t>(pnh, "too_big_for_a_byte", 0); }),
            "~too_big_for_a_byte must be an integer in [0, 255], got 300");
  EXPECT_EQ(invalidArgumentOf([&] { sl_params::read(pnh, "a_mixed_list", std::vector<double>()); }),
            "~a_mixed_list must be a list of numbers, got a list");
  EXPECT_EQ(invalidArgumentOf([&] { sl_params::read(pnh, "a_double", std::vector<double>()); }),
            "~a_double must be a list of numbers, got a number");
}

TEST(Params, RequiredAndRangesNameTheParameter)
{
  const ros::NodeHandle pnh("~");
  EXPECT_EQ(invalidArgumentOf([&] { sl_params::required<double>(pnh, "not_set"); }), "~not_set is required (a number)");
  EXPECT_EQ(invalidArgumentOf([&] { sl_params::readInRange(pnh, "negative", 1.0, 0.0, 2.0); }),
            "~negative must be in [0, 2], got -0.5");
  EXPECT_DOUBLE_EQ(sl_params::readInRange(pnh, "a_double", 1.0, 0.0, 2.0), 0.25);
  EXPECT_DOUBLE_EQ(sl_params::readInRange(pnh, "not_set", 1.0, 0.0, 2.0), 1.0);
  EXPECT_NE(invalidArgumentOf([&] { sl_params::readInRange(pnh, "not_set", std::nan(""), 0.0, 2.0); }), "");
}

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "params_rostest", 0);
}

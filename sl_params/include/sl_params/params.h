#pragma once
/// @file params.h
/// @brief The one way the stack's nodelets read their ROS parameters: typed, a wrong type refused,
/// ranges checked, every message naming the parameter (header-only; roscpp only).
///
/// `ros::NodeHandle::param()` falls back to the default when a value has the wrong type (a
/// `max_speed: "fast"` in a launch file would silently become 0.5). Here a present value of the
/// wrong type is an error, so a typo fails at start instead of running with a value nobody chose.
/// Ranges belong to the core types' `validate()`; `readInRange()` is for the few parameters that have
/// no core type (topics' rates, timeouts of the ROS adapter itself).

#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <ros/console.h>
#include <ros/node_handle.h>
#include <xmlrpcpp/XmlRpcValue.h>

namespace sl_params
{

/// @brief The parameter's name as messages show it (the nodelets read private parameters: `~name`).
inline std::string displayName(const std::string& name)
{
  return "~" + name;
}

namespace detail
{
inline const char* typeName(XmlRpc::XmlRpcValue::Type t)
{
  switch (t)
  {
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return "a boolean";
    case XmlRpc::XmlRpcValue::TypeInt:
      return "an integer";
    case XmlRpc::XmlRpcValue::TypeDouble:
      return "a number";
    case XmlRpc::XmlRpcValue::TypeString:
      return "a string";
    case XmlRpc::XmlRpcValue::TypeArray:
      return "a list";
    case XmlRpc::XmlRpcValue::TypeStruct:
      return "a dictionary";
    default:
      return "a value of another type";
  }
}

template <typename T>
struct IsVector : std::false_type
{
};
template <typename E>
struct IsVector<std::vector<E>> : std::true_type
{
};

template <typename T>
constexpr const char* expected()
{
  if constexpr (IsVector<T>::value)
  {
    if constexpr (std::is_same<typename T::value_type, bool>::value)
      return "a list of booleans";
    else if constexpr (std::is_same<typename T::value_type, std::string>::value)
      return "a list of strings";
    else if constexpr (std::is_integral<typename T::value_type>::value)
      return "a list of integers";
    else
      return "a list of numbers";
  }
  else if constexpr (std::is_same<T, bool>::value)
    return "a boolean";
  else if constexpr (std::is_same<T, std::string>::value)
    return "a string";
  else if constexpr (std::is_integral<T>::value)
    return "an integer";
  else
    return "a number";
}

/// Converts @p v to T, or returns false when its type cannot hold a T (an int is a number too; a
/// list converts element by element).
template <typename T>
bool convert(XmlRpc::XmlRpcValue& v, T& out)
{
  using Type = XmlRpc::XmlRpcValue;
  if constexpr (IsVector<T>::value)
  {
    if (v.getType() != Type::TypeArray)
      return false;
    T items(static_cast<size_t>(v.size()));
    for (int i = 0; i < v.size(); ++i)
      if (!convert(v[i], items[static_cast<size_t>(i)]))
        return false;
    out = std::move(items);
  }
  else if constexpr (std::is_same<T, std::string>::value)
  {
    if (v.getType() != Type::TypeString)
      return false;
    out = static_cast<std::string>(v);
  }
  else if constexpr (std::is_same<T, bool>::value)
  {
    if (v.getType() != Type::TypeBoolean)
      return false;
    out = static_cast<bool>(v);
  }
  else if constexpr (std::is_integral<T>::value)
  {
    if (v.getType() != Type::TypeInt)
      return false;
    const long long i = static_cast<int>(v);  // XmlRpc integers are 32-bit
    if constexpr (std::is_unsigned<T>::value)
    {
      if (i < 0 || static_cast<unsigned long long>(i) > std::numeric_limits<T>::max())
        return false;
    }
    else if (i < static_cast<long long>(std::numeric_limits<T>::lowest()) ||
             i > static_cast<long long>(std::numeric_limits<T>::max()))
      return false;
    out = static_cast<T>(i);
  }
  else
  {
    if (v.getType() == Type::TypeInt)
      out = static_cast<T>(static_cast<int>(v));
    else if (v.getType() == Type::TypeDouble)
      out = static_cast<T>(static_cast<double>(v));
    else
      return false;
  }
  return true;
}

/// Why @p v cannot be read as a T, for the message after "~name must be ".
template <typename T>
std::string refusal(XmlRpc::XmlRpcValue& v)
{
  std::ostringstream s;
  s << expected<T>();
  if constexpr (std::is_integral<T>::value && !std::is_same<T, bool>::value)
    if (v.getType() == XmlRpc::XmlRpcValue::TypeInt)
    {
      s << " in [" << +std::numeric_limits<T>::lowest() << ", " << +std::numeric_limits<T>::max() << "], got "
        << static_cast<int>(v);
      return s.str();
    }
  s << ", got " << typeName(v.getType());
  return s.str();
}
}  // namespace detail

/**
 * @brief Reads parameter @p name of @p nh if it is set.
 * @return true and @p out set when the parameter exists; false (and @p out untouched) when not.
 * @throws std::invalid_argument naming the parameter when its value has another type (an integer
 *         is accepted for a floating-point parameter, nothing else is converted).
 */
template <typename T>
bool readIfSet(const ros::NodeHandle& nh, const std::string& name, T& out)
{
  XmlRpc::XmlRpcValue v;
  if (!nh.getParam(name, v))
    return false;
  if (!detail::convert(v, out))
    throw std::invalid_argument(displayName(name) + " must be " + detail::refusal<T>(v));
  return true;
}

/**
 * @brief readIfSet() for a parameter that was renamed: @p name, or else its deprecated former name
 * @p old_name (with a warning that names both).
 * @return true when either is set.
 * @throws std::invalid_argument naming the parameter read when its value has another type.
 */
template <typename T>
bool readIfSetRenamed(const ros::NodeHandle& nh, const std::string& name, const std::string& old_name, T& out)
{
  if (readIfSet(nh, name, out))
  {
    if (nh.hasParam(old_name))
      ROS_WARN("%s is set too and ignored: it is the deprecated former name of %s (%s)", displayName(old_name).c_str(),
               displayName(name).c_str(), nh.getNamespace().c_str());
    return true;
  }
  if (!readIfSet(nh, old_name, out))
    return false;
  ROS_WARN("%s is deprecated: use %s (%s)", displayName(old_name).c_str(), displayName(name).c_str(),
           nh.getNamespace().c_str());
  return true;
}

/**
 * @brief Reads optional parameter @p name of @p nh.
 * @return its value, or @p fallback when it is not set.
 * @throws std::invalid_argument naming the parameter when its value has another type.
 */
template <typename T>
T read(const ros::NodeHandle& nh, const std::string& name, const T& fallback)
{
  T value = fallback;
  readIfSet(nh, name, value);
  return value;
}

/// @brief read() for string literals as the fallback.
inline std::string read(const ros::NodeHandle& nh, const std::string& name, const char* fallback)
{
  return read<std::string>(nh, name, fallback);
}

/**
 * @brief Reads required parameter @p name of @p nh.
 * @throws std::invalid_argument naming the parameter when it is missing or has another type.
 */
template <typename T>
T required(const ros::NodeHandle& nh, const std::string& name)
{
  T value{};
  if (!readIfSet(nh, name, value))
    throw std::invalid_argument(displayName(name) + " is required (" + detail::expected<T>() + ")");
  return value;
}

/**
 * @brief Reads optional parameter @p name and checks that it lies in [@p lo, @p hi].
 * @throws std::invalid_argument naming the parameter and the range when it is outside (or NaN) or
 *         of another type.
 */
template <typename T>
T readInRange(const ros::NodeHandle& nh, const std::string& name, const T& fallback, const T& lo, const T& hi)
{
  const T value = read(nh, name, fallback);
  if (!(value >= lo && value <= hi))
  {
    std::ostringstream s;
    s << displayName(name) << " must be in [" << lo << ", " << hi << "], got " << value;
    throw std::invalid_argument(s.str());
  }
  return value;
}

/**
 * @brief Refuses a value of parameter @p name whose type is not @p cfg_type, a dynamic_reconfigure
 * type name ("int", "double", "bool" or "str"): for parameters that a generated `...Config`
 * reads with `__fromServer__`, which keeps the default on a wrong type without a word.
 * @throws std::invalid_argument naming the parameter.
 */
inline void checkReconfigureType(const ros::NodeHandle& nh, const std::string& name, const std::string& cfg_type)
{
  if (cfg_type == "double")
  {
    double v;
    readIfSet(nh, name, v);
  }
  else if (cfg_type == "int")
  {
    int v;
    readIfSet(nh, name, v);
  }
  else if (cfg_type == "bool")
  {
    bool v;
    readIfSet(nh, name, v);
  }
  else
  {
    std::string v;
    readIfSet(nh, name, v);
  }
}

/**
 * @brief checkReconfigureType() for every parameter of a generated dynamic_reconfigure @p Config
 * (its `__getParamDescriptions__()`), before `__fromServer__` reads them.
 * @throws std::invalid_argument naming the first parameter of a wrong type.
 */
template <class Config>
void checkReconfigureTypes(const ros::NodeHandle& nh)
{
  for (const auto& description : Config::__getParamDescriptions__())
    checkReconfigureType(nh, description->name, description->type);
}

}  // namespace sl_params

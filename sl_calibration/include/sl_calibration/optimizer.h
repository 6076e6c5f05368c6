#pragma once
/// @file optimizer.h
/// @brief A small dense Levenberg-Marquardt least-squares solver with a numerical Jacobian, for the
/// calibration fits (ROS-free).

#include <functional>
#include <vector>

#include <Eigen/Core>

namespace sl_calibration
{

/**
 * @brief Minimises the sum of squared residuals r(p) over the free parameters p.
 *
 * Forward-difference Jacobian (step 1e-6 relative to each parameter's size), Marquardt's scaling
 * of the damping by the diagonal of J^T J. Meant for tens of parameters and tens of thousands of
 * residuals.
 */
struct LevenbergMarquardt
{
  /// Residual function: fills r (its size may not change between calls).
  using Residuals = std::function<void(const Eigen::VectorXd& params, Eigen::VectorXd& r)>;

  int max_iterations = 100;           ///< outer iterations
  double relative_tolerance = 1e-12;  ///< stop when the cost decreases by less than this fraction

  /// @brief Final cost (sum of squares) of the last minimize().
  double cost = 0.0;
  /// @brief Iterations used by the last minimize().
  int iterations = 0;

  /**
   * @brief Minimises in place.
   * @param free which parameters may change (empty: all).
   * @return the final cost.
   */
  double minimize(const Residuals& residuals, const std::vector<bool>& free, Eigen::VectorXd& params);
};

}  // namespace sl_calibration

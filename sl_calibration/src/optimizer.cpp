#include "sl_calibration/optimizer.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace sl_calibration
{

double LevenbergMarquardt::minimize(const Residuals& residuals, const std::vector<bool>& free, Eigen::VectorXd& params)
{
  std::vector<long> index;
  for (long i = 0; i < params.size(); ++i)
    if (free.empty() || (static_cast<size_t>(i) < free.size() && free[static_cast<size_t>(i)]))
      index.push_back(i);
  const long k = static_cast<long>(index.size());
  Eigen::VectorXd r, r_step;
  residuals(params, r);
  cost = r.squaredNorm();
  iterations = 0;
  if (k == 0 || !std::isfinite(cost))
    return cost;
  const long m = r.size();
  Eigen::MatrixXd J(m, k);
  double lambda = 1e-3;
  for (int it = 0; it < max_iterations; ++it)
  {
    iterations = it + 1;
    for (long j = 0; j < k; ++j)
    {
      Eigen::VectorXd p = params;
      const double h = 1e-6 * std::max(1.0, std::abs(p(index[static_cast<size_t>(j)])));
      p(index[static_cast<size_t>(j)]) += h;
      residuals(p, r_step);
      J.col(j) = (r_step - r) / h;
    }
    const Eigen::MatrixXd H = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * r;
    bool accepted = false;
    for (int tries = 0; tries < 12; ++tries)
    {
      Eigen::MatrixXd A = H;
      for (long j = 0; j < k; ++j)
        A(j, j) += lambda * std::max(H(j, j), 1e-12);
      const Eigen::VectorXd delta = A.ldlt().solve(-g);
      if (!delta.allFinite())
      {
        lambda *= 10.0;
        continue;
      }
      Eigen::VectorXd p = params;
      for (long j = 0; j < k; ++j)
        p(index[static_cast<size_t>(j)]) += delta(j);
      residuals(p, r_step);
      const double c = r_step.squaredNorm();
      if (std::isfinite(c) && c < cost)
      {
        const double gain = (cost - c) / std::max(cost, 1e-300);
        params = p;
        r = r_step;
        cost = c;
        lambda = std::max(lambda / 3.0, 1e-12);
        accepted = true;
        if (gain < relative_tolerance)
          return cost;
        break;
      }
      lambda *= 5.0;
    }
    if (!accepted)
      break;
  }
  return cost;
}

}  // namespace sl_calibration

#include "plane_view.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace sl_fuzz
{
PlaneRenderer::PlaneRenderer(const sl_projector::Rig& rig) : rig_(rig)
{
  const sl_projector::RigidTransform inv = rig.projector_pose.inverse();
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
      to_projector_[r * 4 + c] = inv.rotation(r, c);
    to_projector_[r * 4 + 3] = inv.translation[r];
  }
  // Rays on a grid of kStep px, interpolated: undistorting every pixel cost more than decoding.
  constexpr int kStep = 8;
  const int w = rig.camera.width, h = rig.camera.height;
  const int gw = w / kStep + 2, gh = h / kStep + 2;
  std::vector<Eigen::Vector2d> grid(static_cast<size_t>(gw) * static_cast<size_t>(gh));
  for (int j = 0; j < gh; ++j)
    for (int i = 0; i < gw; ++i)
      grid[static_cast<size_t>(j * gw + i)] = rig.camera.ray(Eigen::Vector2d(i * kStep, j * kStep)).head<2>();
  rays_.resize(2 * static_cast<size_t>(w) * static_cast<size_t>(h));
  size_t k = 0;
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u)
    {
      const int i = u / kStep, j = v / kStep;
      const double a = (u - i * kStep) / static_cast<double>(kStep), b = (v - j * kStep) / static_cast<double>(kStep);
      const Eigen::Vector2d r =
          (1 - b) * ((1 - a) * grid[static_cast<size_t>(j * gw + i)] + a * grid[static_cast<size_t>(j * gw + i + 1)]) +
          b * ((1 - a) * grid[static_cast<size_t>((j + 1) * gw + i)] +
               a * grid[static_cast<size_t>((j + 1) * gw + i + 1)]);
      rays_[k++] = r.x();
      rays_[k++] = r.y();
    }
}

void PlaneRenderer::render(const cv::Mat& pattern, const PlaneView& view, cv::Mat& image) const
{
  const int w = rig_.camera.width, h = rig_.camera.height;
  image.create(h, w, CV_8UC1);
  // Plane n . p = n . (0, 0, depth) with n = (tilt_x, tilt_y, -1); the ray through a pixel is t (x, y, 1).
  const double nx = view.tilt_x, ny = view.tilt_y, np0 = -view.depth;
  const sl_projector::PinholeModel& pr = rig_.projector;
  const double* m = to_projector_;
  size_t k = 0;
  for (int v = 0; v < h; ++v)
  {
    uint8_t* row = image.ptr<uint8_t>(v);
    for (int u = 0; u < w; ++u, k += 2)
    {
      const double x = rays_[k], y = rays_[k + 1];
      double value = view.background;
      const double nr = nx * x + ny * y - 1.0;
      const double t = std::abs(nr) > 1e-12 ? np0 / nr : -1.0;
      if (t > 0.05 && t < 20.0)
      {
        const double px = t * x, py = t * y, pz = t;
        const double qx = m[0] * px + m[1] * py + m[2] * pz + m[3];
        const double qy = m[4] * px + m[5] * py + m[6] * pz + m[7];
        const double qz = m[8] * px + m[9] * py + m[10] * pz + m[11];
        if (qz > 1e-6)
        {
          const Eigen::Vector2d d = pr.distort(Eigen::Vector2d(qx / qz, qy / qz));
          const double fx = pr.fx * d.x() + pr.cx, fy = pr.fy * d.y() + pr.cy;
          if (fx > -0.5 && fy > -0.5 && fx < pattern.cols - 0.5 && fy < pattern.rows - 0.5)
          {
            const int ix = static_cast<int>(fx + 0.5), iy = static_cast<int>(fy + 0.5);
            value += view.gain * (0.49 / (t * t)) * pattern.at<uint8_t>(iy, ix) / 255.0;
          }
        }
      }
      row[u] = static_cast<uint8_t>(std::min(255.0, std::max(0.0, value)));
    }
  }
  cv::GaussianBlur(image, image, cv::Size(3, 3), 0.7);
}
}  // namespace sl_fuzz

// The renderer: geometry of what it draws (blob positions, depth, projector coordinates, shadows),
// image formation (brightness, noise, blur, saturation) and its interface (determinism, errors).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "sl_sim/renderer.h"
#include "sl_sim/scene.h"
#include "sl_rig/pattern.h"
#include "sl_rig/rig.h"

namespace sl_sim
{
namespace
{
const std::string kScenes = SL_SIM_SCENES_DIR;
const std::string kRigFile = std::string(SL_PROJECTOR_CONFIG_DIR) + "/default_rig.yaml";

struct SimFixture
{
  sl_projector::Rig rig = sl_projector::loadRig(kRigFile);
  sl_projector::Pattern pattern{ rig.pattern };
  cv::Mat frame = pattern.render();
  Eigen::Isometry3d camera = cameraPoseInWorld(rig);  // platform_edge at the world origin
};

SimSettings noiseless()
{
  SimSettings s;
  s.noise = false;
  return s;
}

RenderOutput render(const SimFixture& setup, const Scene& scene, const SimSettings& settings, uint64_t seed = 0)
{
  Renderer renderer(setup.rig, settings);
  RenderOutput out;
  renderer.render(scene, setup.frame, setup.camera, seed, out);
  return out;
}

double percentile(const cv::Mat& img, double p, const cv::Rect& roi)
{
  std::vector<uint8_t> v;
  for (int y = roi.y; y < roi.y + roi.height; ++y)
    for (int x = roi.x; x < roi.x + roi.width; ++x)
      v.push_back(img.at<uint8_t>(y, x));
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(p / 100.0 * (v.size() - 1))];
}

// The point where the projector ray through projector pixel `pp` meets the plane (world point p0,
// normal n), in the camera frame.
Eigen::Vector3d projectorRayOnPlane(const SimFixture& s, const Eigen::Vector2d& pp, const Eigen::Vector3d& p0_world,
                                    const Eigen::Vector3d& n_world)
{
  Eigen::Vector3d o, d;
  s.rig.projectorRay(pp, o, d);
  const Eigen::Vector3d p0 = s.camera.inverse() * p0_world;
  const Eigen::Vector3d n = s.camera.linear().transpose() * n_world;
  return o + d * (n.dot(p0 - o) / n.dot(d));
}

// Depth (camera z) of the first of the planes (world point, normal) met by the ray of camera pixel px.
double planeDepth(const SimFixture& s, const Eigen::Vector2d& px,
                  const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& planes)
{
  const Eigen::Vector3d r = s.rig.camera.ray(px);
  double best = std::numeric_limits<double>::infinity();
  for (const auto& pl : planes)
  {
    const Eigen::Vector3d p0 = s.camera.inverse() * pl.first;
    const Eigen::Vector3d n = s.camera.linear().transpose() * pl.second;
    const double t = n.dot(p0) / n.dot(r);
    if (t > 0.0)
      best = std::min(best, t);
  }
  return best;
}

// Intensity-weighted centroid of the blob under pixel `at`: weights are the intensity above the
// local background, over the blob's component grown by two pixels (without other blobs' pixels).
bool blobCentroid(const cv::Mat& image, const cv::Mat& labels, const cv::Mat& stats, const Eigen::Vector2d& at,
                  Eigen::Vector2d& centroid)
{
  const int label = labels.at<int>(static_cast<int>(std::lround(at.y())), static_cast<int>(std::lround(at.x())));
  if (label <= 0)
    return false;
  const int grow = 2;
  const int x0 = std::max(0, stats.at<int>(label, cv::CC_STAT_LEFT) - grow);
  const int y0 = std::max(0, stats.at<int>(label, cv::CC_STAT_TOP) - grow);
  const int x1 =
      std::min(image.cols, stats.at<int>(label, cv::CC_STAT_LEFT) + stats.at<int>(label, cv::CC_STAT_WIDTH) + grow);
  const int y1 =
      std::min(image.rows, stats.at<int>(label, cv::CC_STAT_TOP) + stats.at<int>(label, cv::CC_STAT_HEIGHT) + grow);
  const cv::Rect box(x0, y0, x1 - x0, y1 - y0);
  cv::Mat mine = labels(box) == label;
  cv::dilate(mine, mine, cv::Mat::ones(2 * grow + 1, 2 * grow + 1, CV_8U));
  cv::Mat others = (labels(box) != label) & (labels(box) != 0);
  mine.setTo(0, others);
  // Local background: the darkest tenth of the window.
  const cv::Mat window = image(box);
  std::vector<uint8_t> values(window.begin<uint8_t>(), window.end<uint8_t>());
  std::sort(values.begin(), values.end());
  const double background = values[values.size() / 10];
  double sw = 0.0, sx = 0.0, sy = 0.0;
  for (int y = 0; y < box.height; ++y)
    for (int x = 0; x < box.width; ++x)
    {
      if (!mine.at<uint8_t>(y, x))
        continue;
      const double w = std::max(0.0, image.at<uint8_t>(y0 + y, x0 + x) - background);
      sw += w;
      sx += w * (x0 + x);
      sy += w * (y0 + y);
    }
  if (sw <= 0.0)
    return false;
  centroid = Eigen::Vector2d(sx / sw, sy / sw);
  return true;
}

struct BlobStats
{
  int measured = 0;
  int missing = 0;
  double max_error = 0.0;
  double mean_error = 0.0;
};

// Renders the 700 mm plane and compares every blob's centroid with the projection of its
// primitive's centroid through the rig geometry.
BlobStats blobErrors(const SimFixture& s, const SimSettings& settings)
{
  const Scene scene = loadScene(kScenes + "/plane_700.yaml");
  const RenderOutput out = render(s, scene, settings);
  const Eigen::Vector3d p0(0.670, 0.0, 1.0), n(-1.0, 0.0, 0.0);
  // Blobs: pixels brighter than their neighbourhood's mean (the illumination falls off to the sides).
  cv::Mat binary;
  cv::adaptiveThreshold(out.image, binary, 255, cv::ADAPTIVE_THRESH_MEAN_C, cv::THRESH_BINARY, 41, -10);
  cv::Mat labels, stats, centroids;
  cv::connectedComponentsWithStats(binary, labels, stats, centroids, 8, CV_32S);
  BlobStats result;
  double sum = 0.0;
  const sl_projector::PatternConfig& pc = s.rig.pattern;
  for (int r = 0; r < pc.rows; ++r)
    for (int c = 0; c < pc.cols; ++c)
    {
      const cv::Point2d pp = s.pattern.primitiveCentroid(r, c);
      const Eigen::Vector3d P = projectorRayOnPlane(s, Eigen::Vector2d(pp.x, pp.y), p0, n);
      const Eigen::Vector2d px = s.rig.camera.project(P);
      // Whole blobs on the plane only: away from the image border and from the floor.
      if (px.x() < 15 || px.y() < 20 || px.x() > out.image.cols - 16 || px.y() > out.image.rows - 21)
        continue;
      if ((s.camera * P).z() < 0.03)
        continue;
      Eigen::Vector2d measured;
      if (!blobCentroid(out.image, labels, stats, px, measured))
      {
        ++result.missing;
        continue;
      }
      const double e = (measured - px).norm();
      result.max_error = std::max(result.max_error, e);
      sum += e;
      ++result.measured;
    }
  result.mean_error = result.measured ? sum / result.measured : 0.0;
  return result;
}
}  // namespace

TEST(Renderer, BlobsLandWhereTheRigGeometryPutsThem)
{
  const SimFixture s;
  for (bool defocus : { false, true })
  {
    SimSettings settings = noiseless();
    settings.defocus = defocus;
    const BlobStats b = blobErrors(s, settings);
    SCOPED_TRACE(defocus ? "defocus on" : "defocus off");
    EXPECT_GT(b.measured, 500);  // most of the 1024 primitives fall on the plane
    EXPECT_EQ(b.missing, 0);
    EXPECT_LT(b.max_error, 0.3) << "mean " << b.mean_error;
    EXPECT_LT(b.mean_error, 0.06);
    std::printf("[          ] blob centroid error, defocus %s: %d blobs, mean %.3f px, max %.3f px\n",
                defocus ? "on" : "off", b.measured, b.mean_error, b.max_error);
  }
}

TEST(Renderer, DepthAndProjectorCoordinatesAreExactGeometry)
{
  const SimFixture s;
  const Scene scene = loadScene(kScenes + "/plane_700.yaml");
  const RenderOutput out = render(s, scene, noiseless());
  ASSERT_EQ(out.depth.type(), CV_32FC1);
  ASSERT_EQ(out.projector_coords.type(), CV_32FC2);
  const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> planes = {
    { Eigen::Vector3d(0.670, 0, 1), Eigen::Vector3d(-1, 0, 0) }, { Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ() }
  };
  const Eigen::Matrix3d R = s.rig.projector_pose.rotation;
  const Eigen::Vector3d t = s.rig.projector_pose.translation;
  int lit = 0, unlit = 0;
  for (int v = 0; v < out.depth.rows; v += 7)
    for (int u = 0; u < out.depth.cols; u += 11)
    {
      const Eigen::Vector2d px(u, v);
      const double z = planeDepth(s, px, planes);
      const float depth = out.depth.at<float>(v, u);
      ASSERT_TRUE(std::isfinite(depth)) << u << "," << v;
      EXPECT_NEAR(depth, z, 2e-6 * z) << u << "," << v;
      const Eigen::Vector3d P = s.rig.camera.ray(px) * z;
      const Eigen::Vector2d expected = s.rig.projector.project(R.transpose() * (P - t));
      const cv::Vec2f pc = out.projector_coords.at<cv::Vec2f>(v, u);
      if (std::isnan(pc[0]))
      {
        // Unlit only outside the projector frame here (nothing casts a shadow on this plane).
        EXPECT_TRUE(std::isnan(pc[1]));
        EXPECT_FALSE(s.rig.projector.inImage(expected)) << u << "," << v;
        ++unlit;
        continue;
      }
      ++lit;
      EXPECT_NEAR(pc[0], expected.x(), 2e-3) << u << "," << v;
      EXPECT_NEAR(pc[1], expected.y(), 2e-3) << u << "," << v;
      // Triangulating the camera pixel with its projector pixel gives the surface point back.
      Eigen::Vector3d X;
      ASSERT_TRUE(s.rig.triangulate(px, Eigen::Vector2d(pc[0], pc[1]), X));
      EXPECT_NEAR(X.z(), z, 1e-4);
    }
  EXPECT_GT(lit, 2000);
  // Nothing hit (above the horizon of an infinite floor, beyond the plane's edge) is NaN.
  Scene sky;
  sky.objects.push_back(scene.objects[0]);
  const RenderOutput empty = render(s, sky, noiseless());
  EXPECT_TRUE(std::isnan(empty.depth.at<float>(0, 0)));
  EXPECT_TRUE(std::isnan(empty.projector_coords.at<cv::Vec2f>(0, 0)[0]));
  EXPECT_TRUE(std::isfinite(empty.depth.at<float>(empty.depth.rows - 1, 0)));
  EXPECT_LT(empty.image.at<uint8_t>(0, 0), 3);
}

TEST(Renderer, ShadowsFallBehindABoxOnThePredictedSide)
{
  const SimFixture s;
  // A 40 mm square post 500 mm ahead of the camera on the robot's centre line, a wall at 900 mm.
  const Scene scene = parseScene(R"(
objects:
  - {type: plane, name: floor, position: [0, 0, 0], normal: [0, 0, 1], floor: true}
  - {type: plane, name: wall, position: [0.870, 0, 1], normal: [-1, 0, 0], size: [2, 2], albedo: 0.8}
  - {type: box, name: post, position: [0.490, 0, 0.3], size: [0.04, 0.04, 0.6], albedo: 0.8}
)");
  const RenderOutput out = render(s, scene, noiseless());
  const Eigen::Vector3d projector_world = s.camera * s.rig.projectorCentre();
  const SceneObject& post = scene.objects[2];
  for (int v : { 150, 243, 330 })
  {
    SCOPED_TRACE("row " + std::to_string(v));
    // Columns of the post in this row, and for every wall pixel whether the segment from the
    // projector to it passes through the post.
    int post_first = -1, post_last = -1;
    std::vector<int> expected(out.depth.cols, -1);  // -1: not wall, 0: lit, 1: shadow
    for (int u = 0; u < out.depth.cols; ++u)
    {
      const float z = out.depth.at<float>(v, u);
      if (z < 0.6f)
      {
        post_first = post_first < 0 ? u : post_first;
        post_last = u;
        continue;
      }
      if (z < 0.85f)
        continue;
      const Eigen::Vector3d P = s.camera * (s.rig.camera.ray(Eigen::Vector2d(u, v)) * static_cast<double>(z));
      Ray seg;
      seg.origin = projector_world;
      seg.direction = P - projector_world;
      Hit h;
      expected[static_cast<size_t>(u)] = intersectObject(post, seg, 1e-9, 1.0 - 1e-9, h) ? 1 : 0;
    }
    ASSERT_GT(post_first, 0);
    int shadow = 0, mismatches = 0, shadow_left = 0;
    int shadow_first = out.depth.cols, shadow_last = -1;
    for (int u = 1; u + 1 < out.depth.cols; ++u)
    {
      const int e = expected[static_cast<size_t>(u)];
      if (e < 0)
        continue;
      const bool unlit = std::isnan(out.projector_coords.at<cv::Vec2f>(v, u)[0]);
      // Pixels at a shadow edge may go either way.
      const bool edge = expected[static_cast<size_t>(u - 1)] != e || expected[static_cast<size_t>(u + 1)] != e;
      if (!edge && unlit != (e == 1))
        ++mismatches;
      if (e == 1)
      {
        ++shadow;
        shadow_left += u < post_first;
        shadow_first = std::min(shadow_first, u);
        shadow_last = std::max(shadow_last, u);
      }
    }
    EXPECT_EQ(mismatches, 0);
    // The projector is right of the camera, so the visible shadow is left of the post in the image.
    EXPECT_GT(shadow, 5);
    EXPECT_EQ(shadow_left, shadow);
    for (int u = post_last + 1; u < post_last + 20; ++u)
      EXPECT_EQ(expected[static_cast<size_t>(u)], 0) << u;
    // In the shadow only ambient light: dark, while the lit wall shows the pattern (over a band of
    // rows: a single row may fall between two rows of the pattern).
    const cv::Rect in_shadow(shadow_first + 2, v - 12, shadow_last - shadow_first - 3, 25);
    const cv::Rect lit_wall(post_last + 8, v - 12, shadow_last - shadow_first - 3, 25);
    double shadow_max, lit_max;
    cv::minMaxLoc(out.image(in_shadow), nullptr, &shadow_max);
    cv::minMaxLoc(out.image(lit_wall), nullptr, &lit_max);
    EXPECT_LT(shadow_max, 0.2 * lit_max);
    EXPECT_GT(lit_max, 100.0);
  }
  // With shadows off the same wall pixels are all lit.
  SimSettings no_shadows = noiseless();
  no_shadows.shadows = false;
  const RenderOutput open = render(s, scene, no_shadows);
  int wall = 0, unlit = 0;
  for (int v = 100; v < 380; ++v)
    for (int u = 0; u < open.depth.cols; ++u)
      if (open.depth.at<float>(v, u) > 0.85f)
      {
        ++wall;
        unlit += std::isnan(open.projector_coords.at<cv::Vec2f>(v, u)[0]) &&
                 !std::isnan(out.projector_coords.at<cv::Vec2f>(v, u)[0]);
      }
  EXPECT_GT(wall, 1000);
  EXPECT_EQ(unlit, 0);
  // ... and the post's shadow (unlit wall with shadows on) gets the pattern.
  int lit_now = 0;
  for (int v = 100; v < 380; ++v)
    for (int u = 0; u < out.depth.cols; ++u)
      if (out.depth.at<float>(v, u) > 0.85f && std::isnan(out.projector_coords.at<cv::Vec2f>(v, u)[0]))
        lit_now += !std::isnan(open.projector_coords.at<cv::Vec2f>(v, u)[0]);
  EXPECT_GT(lit_now, 100);
}

TEST(Renderer, IrradianceFallsWithDistanceUnlessSwitchedOff)
{
  const SimFixture s;
  // The brightest pattern pixels of a white plane at 500 and at 900 mm: with the falloff the near
  // plane gets (0.9 / 0.5)^2 = 3.2 times the light (exposure lowered so that it does not saturate);
  // without it both get the same.
  SimSettings on = noiseless();
  on.exposure = 0.25;
  on.ambient = 0.0;
  SimSettings off = on;
  off.irradiance_falloff = false;
  const cv::Rect centre(250, 140, 250, 200);
  double peak[2][2];
  for (int f = 0; f < 2; ++f)
    for (int d = 0; d < 2; ++d)
    {
      const Scene scene = loadScene(kScenes + (d == 0 ? "/plane_500.yaml" : "/plane_900.yaml"));
      peak[f][d] = percentile(render(s, scene, f == 0 ? on : off).image, 99.5, centre);
    }
  EXPECT_GT(peak[0][0], 2.3 * peak[0][1]);
  EXPECT_NEAR(peak[1][0] / peak[1][1], 1.0, 0.2);
}

TEST(Renderer, SameSeedSameBytesOtherSeedOtherNoise)
{
  const SimFixture s;
  const Scene scene = loadScene(kScenes + "/room.yaml");
  Renderer a(s.rig), b(s.rig);
  RenderOutput oa, ob, oc;
  a.render(scene, s.frame, s.camera, 7, oa);
  b.render(scene, s.frame, s.camera, 7, ob);
  EXPECT_EQ(cv::countNonZero(oa.image != ob.image), 0);
  const uint8_t* data = oa.image.data;
  const float* depth = oa.depth.ptr<float>(0);
  a.render(scene, s.frame, s.camera, 7, oa);  // again, reusing the buffers
  EXPECT_EQ(cv::countNonZero(oa.image != ob.image), 0);
  EXPECT_EQ(oa.image.data, data);
  EXPECT_EQ(oa.depth.ptr<float>(0), depth);
  a.render(scene, s.frame, s.camera, 8, oc);
  EXPECT_GT(cv::countNonZero(oa.image != oc.image), oa.image.total() / 4);
  // The noise-free parts do not depend on the seed.
  EXPECT_EQ(cv::countNonZero(oa.depth != oc.depth), 0);
  SimSettings quiet = noiseless();
  Renderer q(s.rig, quiet);
  q.render(scene, s.frame, s.camera, 1, oa);
  q.render(scene, s.frame, s.camera, 2, ob);
  EXPECT_EQ(cv::countNonZero(oa.image != ob.image), 0);
}

TEST(Renderer, NoiseHasTheShotAndReadNoiseLevels)
{
  const SimFixture s;
  const Scene scene = loadScene(kScenes + "/plane_700.yaml");
  const RenderOutput clean = render(s, scene, noiseless());
  const RenderOutput noisy = render(s, scene, SimSettings(), 3);
  // Differences to the noise-free image, binned by signal: variance ~ signal / full_well + read^2.
  double dark_sum2 = 0.0, bright_sum2 = 0.0;
  int dark = 0, bright = 0;
  for (int v = 50; v < 400; ++v)
    for (int u = 100; u < 650; ++u)
    {
      const int c = clean.image.at<uint8_t>(v, u);
      const double d = static_cast<double>(noisy.image.at<uint8_t>(v, u)) - c;
      if (c > 10 && c < 25)
      {
        dark_sum2 += d * d;
        ++dark;
      }
      else if (c > 170 && c < 210)
      {
        bright_sum2 += d * d;
        ++bright;
      }
    }
  ASSERT_GT(dark, 1000);
  ASSERT_GT(bright, 1000);
  const double dark_sigma = std::sqrt(dark_sum2 / dark), bright_sigma = std::sqrt(bright_sum2 / bright);
  // Expected: dark ~ sqrt(1.5^2 + 17/255/6000*255^2 + 1/12) ~ 1.9 DN; bright ~ sqrt(190*255/6000 + ...) ~ 3.2 DN.
  EXPECT_GT(dark_sigma, 1.3);
  EXPECT_LT(dark_sigma, 2.6);
  EXPECT_GT(bright_sigma, 2.6);
  EXPECT_LT(bright_sigma, 4.0);
}

TEST(Renderer, BrightnessOfAWhitePlaneAt700mm)
{
  const SimFixture s;
  const Scene scene = loadScene(kScenes + "/plane_700.yaml");
  const RenderOutput out = render(s, scene, SimSettings());
  const cv::Rect centre(150, 80, 450, 280);
  const double peak = percentile(out.image, 99.5, centre), background = percentile(out.image, 25, centre);
  EXPECT_GE(peak, 180);
  EXPECT_LE(peak, 235);
  EXPECT_GE(background, 8);
  EXPECT_LE(background, 32);

  // Ambient light raises the background and lowers the contrast.
  SimSettings bright;
  bright.ambient = 0.4;
  const RenderOutput lit = render(s, scene, bright);
  EXPECT_GT(percentile(lit.image, 25, centre), background + 40);
  // A dark surface gives little signal.
  Scene dark = scene;
  dark.objects[1].material.albedo = 0.1;
  const RenderOutput d = render(s, dark, SimSettings());
  EXPECT_LT(percentile(d.image, 99.5, centre), 0.2 * peak);
  // Vignetting darkens the corners to the set fraction (ambient light only: a black frame).
  SimSettings flat = noiseless(), vignetted = noiseless();
  flat.vignetting = 1.0;
  flat.ambient = vignetted.ambient = 0.5;
  const cv::Mat black(s.frame.size(), CV_8UC1, cv::Scalar(0));
  RenderOutput f, g;
  Renderer(s.rig, flat).render(scene, black, s.camera, 0, f);
  Renderer(s.rig, vignetted).render(scene, black, s.camera, 0, g);
  const cv::Rect corner(0, 0, 12, 12), middle(360, 230, 24, 24);
  EXPECT_NEAR(cv::mean(g.image(corner))[0] / cv::mean(f.image(corner))[0], 0.71, 0.05);
  EXPECT_NEAR(cv::mean(g.image(middle))[0] / cv::mean(f.image(middle))[0], 1.0, 0.02);
}

TEST(Renderer, AShinyMetalBinSaturates)
{
  const SimFixture s;
  Scene scene = loadScene(kScenes + "/shiny_bin_586.yaml");
  const RenderOutput shiny = render(s, scene, SimSettings());
  EXPECT_GT(cv::countNonZero(shiny.image == 255), 2000);
  scene.objects[1].material.specular = 0.0;
  const RenderOutput matte = render(s, scene, SimSettings());
  EXPECT_EQ(cv::countNonZero(matte.image == 255), 0);
}

// The lenses are the rig's (so the decoder, reading the same rig, expects the blur rendered); a
// setting overrides them, defocus_scale scales both defocus blurs.
TEST(Renderer, OpticsComeFromTheRig)
{
  const SimFixture s;
  sl_projector::Rig rig = s.rig;
  rig.camera_optics.focus_distance = 0.5;
  rig.projector_optics.focus_distance = 0.8;
  rig.camera_optics.f_number = 2.8;
  const Renderer r(rig);
  EXPECT_EQ(r.settings().camera_focus_distance, 0.5);
  EXPECT_EQ(r.settings().camera_f_number, 2.8);
  EXPECT_EQ(r.settings().projector_focus_distance, 0.8);
  EXPECT_EQ(r.settings().projector_pixel_size, 7.6e-6);
  EXPECT_NEAR(r.cameraBlurSigma(0.5), 0.3, 1e-9);
  EXPECT_NEAR(r.projectorBlurSigma(0.8), 0.3, 1e-9);
  // sigma = sqrt(base^2 + (diameter / 4)^2), the diameter of the rig's thin lens.
  const double d = rig.camera_optics.defocusDiameter(std::sqrt(rig.camera.fx * rig.camera.fy), 0.35) / 4.0;
  EXPECT_NEAR(r.cameraBlurSigma(0.35), std::sqrt(0.09 + d * d), 1e-9);
  SimSettings settings;
  settings.defocus_scale = 1.5;
  settings.camera_focus_distance = 0.6;
  const Renderer scaled(rig, settings);
  EXPECT_EQ(scaled.settings().camera_focus_distance, 0.6);
  sl_projector::LensOptics at06 = rig.camera_optics;
  at06.focus_distance = 0.6;
  const double d_scaled = 1.5 * at06.defocusDiameter(std::sqrt(rig.camera.fx * rig.camera.fy), 0.35) / 4.0;
  EXPECT_NEAR(scaled.cameraBlurSigma(0.35), std::sqrt(0.09 + d_scaled * d_scaled), 1e-9);
}

TEST(Renderer, DefocusGrowsAwayFromTheFocusDistance)
{
  const SimFixture s;
  Renderer r(s.rig);
  // Thin-lens blur (Gaussian sigma, camera px) for the default f/1.4 camera focused at 675 mm.
  EXPECT_NEAR(r.cameraBlurSigma(0.675), 0.3, 1e-9);
  for (double z : { 0.6, 0.8 })
  {
    EXPECT_GT(r.cameraBlurSigma(z), 0.45) << z;
    EXPECT_LT(r.cameraBlurSigma(z), 0.8) << z;
  }
  EXPECT_GT(r.cameraBlurSigma(0.45), 1.5);
  EXPECT_LT(r.cameraBlurSigma(0.45), 2.5);
  EXPECT_GT(r.cameraBlurSigma(0.95), 1.0);
  EXPECT_GT(r.projectorBlurSigma(0.45), 0.5);
  EXPECT_NEAR(r.projectorBlurSigma(0.675), 0.3, 1e-9);
  // In the images: far from focus the blobs lose their edges, at focus defocus changes little.
  auto sharpness = [&](const std::string& scene_name, bool defocus)
  {
    SimSettings settings = noiseless();
    settings.defocus = defocus;
    const RenderOutput out = render(s, loadScene(kScenes + "/" + scene_name + ".yaml"), settings);
    cv::Mat gx, gy;
    const cv::Mat roi = out.image(cv::Rect(150, 60, 450, 250));
    cv::Sobel(roi, gx, CV_32F, 1, 0);
    cv::Sobel(roi, gy, CV_32F, 0, 1);
    // Gradient energy over the squared contrast: falls as edges spread.
    const cv::Mat energy = gx.mul(gx) + gy.mul(gy);
    double lo, hi;
    cv::minMaxLoc(roi, &lo, &hi);
    return cv::mean(energy)[0] / ((hi - lo) * (hi - lo));
  };
  EXPECT_GT(sharpness("plane_450", false), 2.0 * sharpness("plane_450", true));
  EXPECT_GT(sharpness("plane_950", false), 1.4 * sharpness("plane_950", true));
  EXPECT_LT(sharpness("plane_700", false), 1.12 * sharpness("plane_700", true));
}

TEST(Renderer, RejectsBadSettingsAndPatterns)
{
  const SimFixture s;
  SimSettings bad;
  bad.antialias = 3;
  try
  {
    Renderer r(s.rig, bad);
    FAIL() << "accepted antialias = 3";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_EQ(std::string(e.what()).rfind("antialias:", 0), 0u) << e.what();
  }
  Renderer r(s.rig);
  RenderOutput out;
  const Scene scene = loadScene(kScenes + "/plane_700.yaml");
  EXPECT_THROW(r.render(scene, cv::Mat(10, 10, CV_8UC1, cv::Scalar(0)), s.camera, 0, out), std::invalid_argument);
  cv::Mat colour;
  cv::cvtColor(s.frame, colour, cv::COLOR_GRAY2BGR);
  EXPECT_THROW(r.render(scene, colour, s.camera, 0, out), std::invalid_argument);
  // A different pattern (all white) is picked up: the background between blobs fills in.
  RenderOutput white;
  r.render(scene, cv::Mat(s.frame.size(), CV_8UC1, cv::Scalar(255)), s.camera, 0, white);
  EXPECT_GT(percentile(white.image, 25, cv::Rect(150, 80, 450, 280)), 150);
}

TEST(Renderer, MalformedRigFilesGiveTheDocumentedErrors)
{
  const std::string path = testing::TempDir() + "/sl_sim_bad_rig.yaml";
  std::ifstream in(kRigFile);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string good_k = "K: [1492.0, 0.0, 372.0, 0.0, 1492.0, 243.0, 0.0, 0.0, 1.0]";
  ASSERT_NE(text.find(good_k), std::string::npos);
  text.replace(text.find(good_k), good_k.size(), "K: [1492.0, 0.0]");
  {
    std::ofstream o(path);
    o << text;
  }
  try
  {
    sl_projector::loadRig(path);
    FAIL() << "accepted a bad rig";
  }
  catch (const sl_projector::RigFileError& e)
  {
    EXPECT_NE(std::string(e.what()).find(path + ": camera.K: has 2 numbers, expected 9"), std::string::npos)
        << e.what();
  }
  std::remove(path.c_str());
  EXPECT_THROW(sl_projector::loadRig("/no/such/rig.yaml"), sl_projector::RigFileError);
}

TEST(Renderer, ViewFollowsTheRobotPose)
{
  const SimFixture s;
  const Scene scene = loadScene(kScenes + "/plane_700.yaml");
  Renderer r(s.rig, noiseless());
  RenderOutput near, far;
  // platform_edge 100 mm closer to the plane: 100 mm less depth at the centre.
  Eigen::Isometry3d forward = Eigen::Isometry3d::Identity();
  forward.translation().x() = 0.1;
  r.render(scene, s.frame, cameraPoseInWorld(s.rig, forward), 0, near);
  r.render(scene, s.frame, s.camera, 0, far);
  EXPECT_NEAR(far.depth.at<float>(243, 372) - near.depth.at<float>(243, 372), 0.1 / std::cos(0.03702), 1e-4);
  EXPECT_NEAR(far.depth.at<float>(243, 372), 0.7 / std::cos(0.03702), 2e-3);
}

}  // namespace sl_sim

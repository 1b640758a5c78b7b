// The colour term of registration: on a textured flat wall, where depth alone cannot see sliding
// along the wall or turning about its normal, it recovers a known motion.
#include "olt/registration/photometric.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "olt/registration/registration.h"

using namespace olt;

namespace {

const Intrinsics kCamera{320, 240, 260, 260, 159.5, 119.5, {}};
constexpr double kWallZ = 2.0;  // the wall z = 2 m of the world (the target camera's frame)

double texture(double x, double y) {
  return 0.5 + 0.2 * std::sin(2 * M_PI * x / 0.35) * std::cos(2 * M_PI * y / 0.27) +
         0.1 * std::sin(2 * M_PI * (x + y) / 0.5);
}

struct View {
  cv::Mat color;                        // 8-bit grey
  std::vector<Eigen::Vector3d> points;  // camera frame, one per pixel
};

// What a camera at T_world_camera sees of the wall: exact depth and the texture, per pixel.
View render(const Pose& T_world_camera) {
  View v{cv::Mat(kCamera.height, kCamera.width, CV_8UC1), {}};
  for (int row = 0; row < kCamera.height; ++row)
    for (int col = 0; col < kCamera.width; ++col) {
      const Eigen::Vector3d ray((col - kCamera.cx) / kCamera.fx, (row - kCamera.cy) / kCamera.fy, 1);
      const Eigen::Vector3d dir = T_world_camera.linear() * ray;
      const double s = (kWallZ - T_world_camera.translation().z()) / dir.z();
      const Eigen::Vector3d X = T_world_camera.translation() + s * dir;
      v.color.at<uint8_t>(row, col) = cv::saturate_cast<uint8_t>(255 * texture(X.x(), X.y()));
      v.points.push_back(s * ray);
    }
  return v;
}

}  // namespace

TEST_CASE("the colour term recovers sliding along a textured wall that depth alone cannot see") {
  const Pose T_world_source = pose_from_xyz_ypr_deg({0.03, -0.02, 0.01, 0, 0, 1.5});  // x y z, yaw pitch roll
  const View target_view = render(Pose::Identity()), source_view = render(T_world_source);
  const PointSet target = downsampled_point_set(target_view.points, 0.03, 10);
  const PointSet source = downsampled_point_set(source_view.points, 0.03, 10);
  const KdTree tree(target.points);
  const IntensityImage target_image = make_intensity_image(target_view.color, kCamera, 1);
  const IntensityImage source_image = make_intensity_image(source_view.color, kCamera, 1);
  const PhotometricPoints pixels = select_photometric_points(source_view.points, source_image, Pose::Identity(), 0.005);
  REQUIRE(pixels.points.size() > 10000);
  PhotometricTerm colour{&pixels, &target_image, Pose::Identity(), 10, 0.2};
  RegistrationSetting setting;
  setting.max_iterations = 50;

  const RegistrationResult depth_only = register_point_sets(target, tree, source, Pose::Identity(), setting);
  const RegistrationResult both = register_point_sets(target, tree, source, Pose::Identity(), setting, &colour);

  // Depth alone gets the wall's distance and tilt, but not where along the wall or the roll.
  const Pose depth_error = depth_only.T_target_source.inverse() * T_world_source;
  CHECK(std::abs(depth_only.T_target_source.translation().z() - 0.01) < 0.002);
  CHECK(depth_error.translation().norm() > 0.02);
  // With the colour term: the whole motion.
  const Pose error = both.T_target_source.inverse() * T_world_source;
  CHECK(both.converged);
  CHECK(error.translation().norm() < 0.001);
  CHECK(rotation_angle(error) * 180 / M_PI < 0.05);
  CHECK(both.photometric_points > 10000);
  CHECK(both.photometric_rmse < 0.01);
}

TEST_CASE("a halved intensity image keeps the even pixels: full pixel (100, 60) is reduced (50, 30)") {
  cv::Mat image = cv::Mat::zeros(120, 160, CV_8UC1);
  image.at<uint8_t>(60, 100) = 255;
  const IntensityImage half = make_intensity_image(image, kCamera, 1);
  REQUIRE(half.scale == 2);
  REQUIRE(half.intensity.size() == cv::Size(80, 60));
  cv::Point peak;
  cv::minMaxLoc(half.intensity, nullptr, nullptr, nullptr, &peak);
  CHECK(peak == cv::Point(50, 30));
  // Symmetric around it: the peak is centred on the reduced pixel, not between two.
  CHECK(half.intensity.at<float>(30, 49) == Approx(half.intensity.at<float>(30, 51)));
  CHECK(half.intensity.at<float>(29, 50) == Approx(half.intensity.at<float>(31, 50)));
  CHECK_THROWS_AS(make_intensity_image(cv::Mat::zeros(4, 4, CV_16UC1), kCamera, 1), std::invalid_argument);
}

TEST_CASE("intensity images sample bilinearly and map pixels across reductions") {
  cv::Mat ramp(8, 8, CV_32F);
  for (int r = 0; r < 8; ++r)
    for (int c = 0; c < 8; ++c) ramp.at<float>(r, c) = static_cast<float>(c + 10 * r);
  float value = 0;
  REQUIRE(sample(ramp, {2.25, 3.5}, &value));
  CHECK(value == Approx(2.25 + 35));
  CHECK_FALSE(sample(ramp, {7.0, 1.0}, &value));  // the 2x2 neighbourhood would leave the image
  CHECK_FALSE(sample(ramp, {-0.1, 1.0}, &value));

  IntensityImage half;
  half.camera = kCamera;
  half.scale = 2;
  Eigen::Vector2d uv;
  // A reduction keeps the even pixels: the principal point (159.5, 119.5) is the reduced image's
  // (79.75, 59.75), full pixel 100 is reduced pixel 50.
  REQUIRE(half.pixel({0, 0, 1}, &uv));
  CHECK(uv.x() == Approx(79.75));
  CHECK(uv.y() == Approx(59.75));
  REQUIRE(half.pixel({(100 - 159.5) / 260, 0, 1}, &uv));
  CHECK(uv.x() == Approx(50));
  CHECK_FALSE(half.pixel({0, 0, -1}, &uv));
}

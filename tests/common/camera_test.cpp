// CameraIntrinsics: its keys and limits (visit), YAML out and in, and the renderer's own
// demands on top of the limits (validate).

#include <gtest/gtest.h>

#include <cmath>

#include "canopy/common/camera.h"
#include "canopy/common/error.h"
#include "canopy/common/params.h"

namespace canopy {
namespace {

CameraIntrinsics changed_camera() {
  CameraIntrinsics K;
  K.width_px = 640;
  K.height_px = 480;
  K.fx_px = 0.1 + 600.0;  // not a short decimal: the text must still read back exactly
  K.fy_px = 601.25;
  K.cx_px = 319.5;
  K.cy_px = 241.0;
  K.min_range_m = 0.105;
  K.max_range_m = 3.0;
  K.depth_noise_k = 0.01;
  return K;
}

TEST(CameraIntrinsics, YamlOutReadsBackToTheSameCamera) {
  for (const CameraIntrinsics& K : {CameraIntrinsics{}, changed_camera()}) {
    const std::string text = yaml_text(params_to_yaml(K));
    YamlReader y = YamlReader::load_string(text, "camera.yaml");
    const CameraIntrinsics back = params_from_yaml<CameraIntrinsics>(y);
    y.finish();
    EXPECT_TRUE(same_params(K, back)) << text;
    EXPECT_EQ(back.fx_px, K.fx_px);
    EXPECT_EQ(back.width_px, K.width_px);
    EXPECT_EQ(params_to_json(back), params_to_json(K));
  }
  // JSON keeps the C++ types: whole pixels stay integers.
  const nlohmann::json j = params_to_json(changed_camera());
  EXPECT_TRUE(j["width_px"].is_number_integer());
  EXPECT_TRUE(j["cy_px"].is_number_float());
  EXPECT_EQ(j.size(), 9u);
}

TEST(CameraIntrinsics, LimitsNameKeyAndValue) {
  const std::pair<const char*, const char*> cases[] = {
      {"width_px: 4097", "key 'width_px': value '4097' must be in [1, 4096]"},
      {"height_px: 0", "key 'height_px': value '0' must be in [1, 4096]"},
      {"width_px: 2.5", "key 'width_px': value '2.5' must be a whole number"},
      {"fx_px: 0", "key 'fx_px': value '0' must be > 0"},
      {"cx_px: 401", "key 'cx_px': value '401' must lie in the image (0 to width_px)"},
      {"cy_px: -0.5", "key 'cy_px': value '-0.5' must lie in the image (0 to height_px)"},
      {"min_range_m: 0", "key 'min_range_m': value '0' must be > 0"},
      {"max_range_m: 0.05", "key 'max_range_m': value '0.05' must be > min_range_m"},
      {"depth_noise_k: -0.01", "key 'depth_noise_k': value '-0.01' must be >= 0"},
  };
  for (const auto& [yaml, message] : cases) {
    YamlReader y = YamlReader::load_string(std::string(yaml) + "\n", "c.yaml");
    try {
      params_from_yaml<CameraIntrinsics>(y);
      ADD_FAILURE() << "no error for " << yaml;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), std::string("c.yaml: ") + message);
    }
  }
}

TEST(CameraIntrinsics, ValidateAddsTheRenderersDemands) {
  CameraIntrinsics K;
  EXPECT_NO_THROW(K.validate("w.yaml"));
  K.fx_px = -1.0;  // a limit
  EXPECT_THROW(K.validate("w.yaml"), InputError);
  K = CameraIntrinsics{};
  K.fy_px = 390.0;  // within the limits, but MuJoCo has one field of view
  EXPECT_NO_THROW(validate_params(K, "w.yaml"));
  EXPECT_THROW(K.validate("w.yaml"), InputError);
  K = CameraIntrinsics{};
  K.cx_px = 190.0;  // in the image, but MuJoCo renders no principal-point offset
  EXPECT_NO_THROW(validate_params(K, "w.yaml"));
  EXPECT_THROW(K.validate("w.yaml"), InputError);
  K = CameraIntrinsics{};
  K.width_px = K.height_px = kMaxCameraSidePx + 2;
  K.cx_px = K.cy_px = 0.5 * K.width_px;
  EXPECT_THROW(validate_params(K, "w.yaml"), InputError);
}

TEST(Camera, ProjectUnprojectRoundTripAndConvention) {
  CameraIntrinsics K;
  // x right, y down, z forward: a point right of and below the axis lands right and below
  // the image centre.
  double u = 0, v = 0;
  ASSERT_TRUE(K.project(Vec3(0.1, 0.05, 1.0), &u, &v));
  EXPECT_GT(u, K.cx_px);
  EXPECT_GT(v, K.cy_px);
  const Vec3 p = K.unproject(u, v, 1.0);
  EXPECT_NEAR((p - Vec3(0.1, 0.05, 1.0)).norm(), 0.0, 1e-12);
  EXPECT_FALSE(K.project(Vec3(0, 0, -1), &u, &v));
  EXPECT_NEAR(K.fovy_deg(), 2.0 * std::atan(200.0 / 381.36) * 180.0 / M_PI, 1e-12);
}

TEST(Camera, ValidateRejectsBadValues) {
  CameraIntrinsics K;
  EXPECT_NO_THROW(K.validate("x.yaml"));
  K.fx_px = 0.0;
  EXPECT_THROW(K.validate("x.yaml"), InputError);
  K = CameraIntrinsics();
  K.max_range_m = 0.05;
  EXPECT_THROW(K.validate("x.yaml"), InputError);
}

TEST(Camera, LookAtHasZeroRollAndLooksAtTheTarget) {
  const Vec3 eye(0.3, -0.2, 1.0), target(1.0, 0.5, 0.6);
  const Pose T = look_at(eye, target);
  EXPECT_LT((T.linear().transpose() * T.linear() - Mat3::Identity()).norm(), 1e-12);
  EXPECT_NEAR(T.linear().determinant(), 1.0, 1e-12);
  // The target projects to the image centre, image x is horizontal, image up is world up.
  CameraIntrinsics K;
  double u = 0, v = 0;
  ASSERT_TRUE(K.project(T.inverse() * target, &u, &v));
  EXPECT_NEAR(u, K.cx_px, 1e-9);
  EXPECT_NEAR(v, K.cy_px, 1e-9);
  EXPECT_NEAR(T.linear().col(0).z(), 0.0, 1e-12);
  EXPECT_LT(T.linear().col(1).z(), 0.0);
  // Straight down is still a valid rotation.
  const Pose D = look_at(Vec3(0, 0, 1), Vec3(0, 0, 0));
  EXPECT_NEAR(D.linear().determinant(), 1.0, 1e-12);
}

}  // namespace
}  // namespace canopy

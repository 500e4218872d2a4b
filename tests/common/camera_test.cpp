// CameraIntrinsics: its keys and limits (visit), YAML out and in, and the renderer's own
// demands on top of the limits (validate).

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace canopy

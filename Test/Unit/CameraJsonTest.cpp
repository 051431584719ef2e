// MPEG-I camera JSON: axes, round trips with the VSRS text format, and errors.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "Common/CameraFile.h"
#include "Common/CameraJson.h"
#include "Common/Error.h"
#include "Common/Json.h"
#include "TestPaths.h"

namespace vs {
namespace {

Camera rotatedCamera(const std::string& name, double yaw, double pitch, double roll, Vec3 centre) {
  Camera c;
  c.name = name;
  c.K = Mat3::identity();
  c.K[0][0] = 1000.5;
  c.K[1][1] = 998.25;
  c.K[0][2] = 511.5;
  c.K[1][2] = 383.25;
  c.R = rotationFromYawPitchRoll(yaw, pitch, roll);
  c.t = centre;
  return c;
}

void expectNear(const Camera& a, const Camera& b, double tolerance) {
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(a.K[r][k], b.K[r][k], tolerance * std::max(1.0, std::fabs(a.K[r][k]))) << a.name;
      EXPECT_NEAR(a.R[r][k], b.R[r][k], tolerance) << a.name;
    }
  EXPECT_NEAR(norm(a.t - b.t), 0.0, tolerance * std::max(1.0, norm(a.t))) << a.name;
}

TEST(CameraJson, AxesAreConvertedFromXForwardYLeftZUp) {
  // A JSON camera with zero rotation looks along its +x (forward), i.e. our +z; yaw 90 turns it to
  // JSON +y (left), our -x; pitch 90 (about y left) turns forward to JSON -z (down), our +y.
  const CameraFile file = parseCameraJson(
      R"({"cameras": [
        {"Name": "a", "Position": [1, 2, 3], "Rotation": [0, 0, 0], "Focal": [100, 100], "Principle_point": [50, 40]},
        {"Name": "b", "Position": [0, 0, 0], "Rotation": [90, 0, 0], "Focal": [100, 100], "Principle_point": [50, 40]},
        {"Name": "c", "Position": [0, 0, 0], "Rotation": [0, 90, 0], "Focal": [100, 100], "Principle_point": [50, 40]}]})",
      "axes.json");
  const Camera& a = file.find("a");
  EXPECT_EQ(a.t, Vec3(-2, -3, 1));        // (x', y', z') = (1, 2, 3) -> (-y', -z', x')
  EXPECT_NEAR(a.K[0][2], 49.5, 1e-15);    // the corner-based principal point becomes centre-based
  const Vec3 forwardB = transpose(file.find("b").R) * Vec3(0, 0, 1);
  EXPECT_NEAR(norm(forwardB - Vec3(-1, 0, 0)), 0, 1e-15);
  const Vec3 forwardC = transpose(file.find("c").R) * Vec3(0, 0, 1);
  EXPECT_NEAR(norm(forwardC - Vec3(0, 1, 0)), 0, 1e-15);
}

TEST(CameraJson, TextToJsonToTextIsExactTo1e9) {
  const auto dir = test::scratchDir("camera_json");
  std::vector<Camera> cameras = {rotatedCamera("straight", 0, 0, 0, Vec3(0, 0, 0)),
                                 rotatedCamera("turned", 33.3, -12.5, 4.75, Vec3(1e3, -250.5, 12)),
                                 rotatedCamera("steep", -170, 80, -95, Vec3(-3, 1e6, 0.25))};
  writeCameraFile((dir / "a.txt").string(), cameras);
  const CameraFile text = readCameraFile((dir / "a.txt").string());
  std::vector<CameraInfo> info(cameras.size());
  info[1].hasDepthRange = true;
  info[1].znear = 0.5;
  info[1].zfar = HUGE_VAL;
  info[1].bitDepthDepth = 16;
  writeCameraJson((dir / "a.json").string(), text.cameras(), info);
  const CameraFile json = readCameraFile((dir / "a.json").string());
  writeCameraFile((dir / "b.txt").string(), json.cameras());
  const CameraFile back = readCameraFile((dir / "b.txt").string());
  ASSERT_EQ(back.cameras().size(), cameras.size());
  for (size_t k = 0; k < cameras.size(); ++k) expectNear(text.cameras()[k], back.cameras()[k], 1e-9);
  // The extras travel too; an infinite far plane included.
  EXPECT_TRUE(json.info("turned").hasDepthRange);
  EXPECT_TRUE(std::isinf(json.info("turned").zfar));
  EXPECT_EQ(json.info("turned").bitDepthDepth, 16);
  EXPECT_FALSE(json.info("straight").hasDepthRange);
  // JSON -> text is exact, bit for bit (text is written with round-trip digits), so a JSON camera file
  // and its text conversion describe identical cameras and synthesize identical views.
  for (size_t k = 0; k < cameras.size(); ++k) {
    EXPECT_EQ(back.cameras()[k].R, json.cameras()[k].R);
    EXPECT_EQ(back.cameras()[k].K, json.cameras()[k].K);
    EXPECT_EQ(back.cameras()[k].t, json.cameras()[k].t);
  }
}

// JSON holds a rotation as three angles, so a text R that is a rotation only to 6 digits (open3d's
// odometry, most MPEG files) comes back as the nearest true rotation: equal to within how far R was
// from one. Exact rotations come back to 1e-9.
TEST(CameraJson, RealCameraFilesRoundTrip) {
  VS_REQUIRE_DIR(test::dataDir());
  const auto dir = test::scratchDir("camera_json_real");
  for (const char* file : {"middlebury2005/Art/cam_param.txt", "open3d/RGBD5/cam_param.txt"}) {
    const CameraFile text = readCameraFile((test::dataDir() / file).string());
    writeCameraJson((dir / "x.json").string(), text.cameras(), std::vector<CameraInfo>(text.cameras().size()));
    const CameraFile json = readCameraFile((dir / "x.json").string());
    writeCameraFile((dir / "x.txt").string(), json.cameras());
    const CameraFile back = readCameraFile((dir / "x.txt").string());
    for (size_t k = 0; k < text.cameras().size(); ++k) {
      const Mat3& R = text.cameras()[k].R;
      const double deviation = maxAbs(R * transpose(R) - Mat3::identity());
      expectNear(text.cameras()[k], back.cameras()[k], std::max(1e-9, 2 * std::sqrt(deviation)));
    }
  }
}

TEST(CameraJson, ErrorsNameFileLineAndField) {
  auto error = [](const std::string& text) {
    try {
      parseCameraJson(text, "bad.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error(R"({"cams": []})").find("bad.json:1: an object with a \"cameras\" array was expected"), std::string::npos);
  EXPECT_NE(error("{\"cameras\": [\n{\"Name\": \"v\", \"Position\": [1, 2]}]}").find("bad.json:2: camera 'v' \"Position\" must be an array of 3 numbers"),
            std::string::npos);
  EXPECT_NE(error("{\"cameras\": [{\"Name\": \"v\", \"Position\": [0,0,0], \"Rotation\": [0,0,0], \"Focal\": [0, 1], "
                  "\"Principle_point\": [0,0]}]}")
                .find("focal"),
            std::string::npos);
  EXPECT_NE(error(R"({"cameras": [{"Name": "v", "Projection": "Fisheye"}]})").find("expected \"Perspective\" or \"Equirectangular\""),
            std::string::npos);
  EXPECT_NE(error("{\"cameras\": [\n\n{\"Name\": 3}").find("bad.json:3:"), std::string::npos);
  EXPECT_NE(error("{\"cameras\": [1e999]}").find("not a finite number"), std::string::npos);
  EXPECT_NE(error("[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[").find("nested"), std::string::npos);
}

TEST(Json, ParsesAndEscapes) {
  const JsonValue v = parseJson(R"({"a": [1, -2.5e3, true, null, "x\"\\\n\u00e9"], "b": {}, "c": Infinity})", "t");
  ASSERT_EQ(v.type, JsonValue::Type::Object);
  const JsonValue* a = v.find("a");
  ASSERT_NE(a, nullptr);
  EXPECT_EQ(a->items[1].number, -2500);
  EXPECT_EQ(a->items[4].text, "x\"\\\n\xc3\xa9");
  EXPECT_TRUE(std::isinf(v.find("c")->number));
  for (double x : {0.1, 1870.0, -3.14159265358979, 1e-300, 123456789.125}) EXPECT_EQ(std::strtod(jsonNumber(x).c_str(), nullptr), x);
  EXPECT_EQ(jsonNumber(1870.0), "1870");
  EXPECT_EQ(parseJson(jsonString("q\"\\\t"), "t").text, "q\"\\\t");
}

}  // namespace
}  // namespace vs

namespace vs {
namespace {

// Found by FuzzCameraJson: a Resolution beyond int was converted with undefined behaviour.
TEST(CameraJson, ResolutionMustBeASmallInteger) {
  try {
    parseCameraJson(R"({"cameras": [{"Name": "v", "Position": [0,0,0], "Rotation": [0,0,0], "Focal": [1,1],
                        "Principle_point": [0,0], "Resolution": [2.2e43, 5]}]})",
                    "r.json");
    FAIL() << "a Resolution of 2.2e43 must be refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("\"Resolution\" must hold two integers in 1..65536"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vs

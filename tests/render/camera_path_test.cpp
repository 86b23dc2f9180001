// Camera paths (render/camera_path.h): the deep zoom's geometry, keyframe
// interpolation, the JSON form and its errors on untrusted text.
#include "svo/render/camera_path.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <glm/geometric.hpp>
#include <limits>
#include <random>
#include <string>

#include "svo/render/camera.h"
#include "temp_dir.h"
#include "test_scenes.h"

namespace svo::render {
namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "(no error)";
}

glm::dvec3 dir_of(const Camera& c) { return glm::normalize(glm::dvec3(c.target) - glm::dvec3(c.eye)); }

// ---- The deep zoom on a voxelized sphere (radius 0.7 at the origin).

class DeepZoom : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new test::SphereScene(0.7f);
    voxelizer::VoxelizeOptions options;
    options.resolution = 32;
    tree_ = new octree::Octree(voxelizer::voxelize(*scene_, options));
  }
  static void TearDownTestSuite() {
    delete tree_;
    delete scene_;
  }
  static voxelizer::AnalyticScene* scene_;
  static octree::Octree* tree_;
};
voxelizer::AnalyticScene* DeepZoom::scene_ = nullptr;
octree::Octree* DeepZoom::tree_ = nullptr;

TEST_F(DeepZoom, TargetIsOnTheSurfaceOnTheFarViewsCentreRay) {
  const Camera far = view_preset(*tree_, "far");
  auto target = surface_target(*tree_, far, 1.0f);
  ASSERT_TRUE(target.has_value());
  const float voxel = tree_->voxel_size(tree_->depth_count - 1);
  EXPECT_NEAR(glm::length(*target), 0.7f, 0.5f * voxel);
  // On the centre ray, in front of the eye.
  const glm::dvec3 d = dir_of(far), v = glm::dvec3(*target) - glm::dvec3(far.eye);
  EXPECT_GT(glm::dot(v, d), 0);
  EXPECT_LT(glm::length(v - glm::dot(v, d) * d), 1e-5);
}

TEST_F(DeepZoom, FirstFrameIsTheFarPresetAndTheLastIsZoomTimesNarrower) {
  const Camera far = view_preset(*tree_, "far");
  const glm::vec3 target = *surface_target(*tree_, far, 1.0f);
  const float zoom = 1000;
  const CameraPath path = deep_zoom_path(far, target, zoom, 25);
  const std::vector<Camera> cams = path_cameras(path);
  ASSERT_EQ(cams.size(), 25u);
  EXPECT_EQ(cams.front().eye, far.eye);
  EXPECT_EQ(cams.front().up, far.up);
  EXPECT_EQ(cams.front().fov_deg, far.fov_deg);
  EXPECT_LT(glm::length(dir_of(cams.front()) - dir_of(far)), 1e-6);  // the same view as the preset
  for (const Camera& c : cams) {
    EXPECT_EQ(c.fov_deg, far.fov_deg);  // fixed field of view
    EXPECT_EQ(c.target, target);
    EXPECT_LT(glm::length(dir_of(c) - dir_of(far)), 1e-4);  // moving along the view direction
  }
  // Float eyes near |target| ~ 0.7 carry a rounding of ~|eye| 2^-24 per
  // coordinate: at the last distance that bounds the relative error of a width.
  const double d_last = glm::length(glm::dvec3(cams.back().target) - glm::dvec3(cams.back().eye));
  const double float_tol = 4.0 * std::sqrt(3.0) * 1.0 * std::ldexp(1.0, -24) / d_last;
  const double ratio = double(view_width(cams.front())) / double(view_width(cams.back()));
  EXPECT_NEAR(ratio / zoom, 1.0, float_tol) << "float tolerance " << float_tol;
}

TEST_F(DeepZoom, SilhouetteTargetIsWhereTheRayGrazesTheSphere) {
  const Camera far = view_preset(*tree_, "far");
  auto p = silhouette_target(*tree_, far, 1.0f);
  ASSERT_TRUE(p.has_value());
  const float voxel = tree_->voxel_size(tree_->depth_count - 1);
  EXPECT_NEAR(glm::length(*p), 0.7f, 0.5f * voxel);
  // Grazing: the ray from the eye is perpendicular to the sphere's normal
  // there (|cos| = sqrt(2 delta / R) for a ray delta inside the limb:
  // 0.1 allows delta = 0.0035, a tenth of a voxel here).
  const glm::dvec3 ray = glm::normalize(glm::dvec3(*p) - glm::dvec3(far.eye));
  EXPECT_LT(std::abs(glm::dot(ray, glm::normalize(glm::dvec3(*p)))), 0.1);
  // To the right of the centre, on the horizontal centre line.
  const glm::dvec3 f = dir_of(far), r = glm::normalize(glm::cross(f, glm::dvec3(far.up)));
  EXPECT_GT(glm::dot(ray, r), 0.1);
  EXPECT_LT(std::abs(glm::dot(ray, glm::cross(r, f))), 1e-5);
}

TEST(DeepZoomPath, EveryFrameZoomsByTheSameFactor) {
  // Target at the origin, so that float eyes keep ~1e-7 relative precision
  // all the way in: the path's own accuracy, 1e-6 relative.
  Camera start;
  start.eye = {1.2f, 0.9f, 2.5f};
  start.target = {0, 0, 0};
  const float zoom = 1000;
  const uint32_t n = 31;
  const std::vector<Camera> cams = path_cameras(deep_zoom_path(start, glm::vec3(0), zoom, n));
  ASSERT_EQ(cams.size(), n);
  const double step = std::pow(double(zoom), -1.0 / double(n - 1));
  for (uint32_t f = 1; f < n; ++f) {
    const double r = double(view_width(cams[f])) / double(view_width(cams[f - 1]));
    EXPECT_NEAR(r / step, 1.0, 1e-6) << "frame " << f;
  }
  EXPECT_NEAR(double(view_width(cams.back())) * zoom / double(view_width(cams.front())), 1.0, 1e-6);
}

TEST(DeepZoomPath, RefusesBadArguments) {
  Camera start;
  EXPECT_EQ(error_of([&] { deep_zoom_path(start, glm::vec3(0), 0.5f, 10); }),
            "deep-zoom: zoom 0.5 must be a finite number >= 1");
  EXPECT_EQ(error_of([&] { deep_zoom_path(start, glm::vec3(0), std::nanf(""), 10); }).rfind("deep-zoom: zoom", 0), 0u);
  EXPECT_EQ(error_of([&] { deep_zoom_path(start, glm::vec3(0), 10, 1); }), "deep-zoom: needs at least 2 frames, got 1");
  EXPECT_EQ(error_of([&] { deep_zoom_path(start, glm::vec3(0), 10, kMaxPathFrames + 1); }),
            "deep-zoom: 100001 frames, above the limit of 100000");
  EXPECT_EQ(error_of([&] { path_cameras(deep_zoom_path(start, glm::vec3(0), 10, 2)); }), "(no error)");
  EXPECT_EQ(error_of([&] {
              CameraPath p = deep_zoom_path(start, glm::vec3(0), 10, 2);
              p.frames = 1000000;
              path_cameras(p);
            }),
            "camera path: 1000000 frames, above the limit of 100000");
  EXPECT_EQ(error_of([&] {
              deep_zoom_path(start, start.eye, 10, 10);
            }).rfind("deep-zoom: start camera looking at the target: eye and target are the same point", 0),
            0u);
}

// ---- Keyframes.

std::vector<Camera> three_keys() {
  Camera a, b, c;
  a.eye = {0, 0, 4}, a.target = {0, 0, 0}, a.up = {0, 1, 0}, a.fov_deg = 40;
  b.eye = {2, 1, 1}, b.target = {0.2f, 0.1f, 0}, b.up = {0, 1, 0.2f}, b.fov_deg = 30;
  c.eye = {0.3f, 0.15f, 0.05f}, c.target = {0.25f, 0.1f, 0.02f}, c.up = {0, 0, 1}, c.fov_deg = 20;
  return {a, b, c};
}

void expect_same(const Camera& x, const Camera& y) {
  EXPECT_EQ(x.eye, y.eye);
  EXPECT_EQ(x.target, y.target);
  EXPECT_EQ(x.up, y.up);
  EXPECT_EQ(x.fov_deg, y.fov_deg);
}

TEST(Keyframes, FramesHitTheKeys) {
  const auto keys = three_keys();
  const auto cams = path_cameras({keys, 9});  // K - 1 = 2 divides N - 1 = 8: frames 0, 4, 8 are the keys
  ASSERT_EQ(cams.size(), 9u);
  expect_same(cams[0], keys[0]);
  expect_same(cams[4], keys[1]);
  expect_same(cams[8], keys[2]);
  // Not divisible: the ends are still the first and the last key.
  const auto four = path_cameras({keys, 4});
  expect_same(four.front(), keys.front());
  expect_same(four.back(), keys.back());
}

TEST(Keyframes, DistanceIsGeometricTargetLinearFovLinear) {
  const auto keys = three_keys();
  const Camera mid = sample_path(keys, 1.5);
  const double da = glm::length(glm::dvec3(keys[1].eye) - glm::dvec3(keys[1].target));
  const double db = glm::length(glm::dvec3(keys[2].eye) - glm::dvec3(keys[2].target));
  const double d = glm::length(glm::dvec3(mid.eye) - glm::dvec3(mid.target));
  EXPECT_NEAR(d / std::sqrt(da * db), 1.0, 1e-5);
  const glm::vec3 t = 0.5f * (keys[1].target + keys[2].target);
  EXPECT_LT(glm::length(mid.target - t), 1e-6f);
  EXPECT_NEAR(mid.fov_deg, 25.0f, 1e-5f);
  EXPECT_NEAR(glm::length(mid.up), 1.0f, 1e-5f);
  // The direction lies between the keys' directions (slerp: equal angles).
  const glm::dvec3 ua = glm::normalize(glm::dvec3(keys[1].eye) - glm::dvec3(keys[1].target));
  const glm::dvec3 ub = glm::normalize(glm::dvec3(keys[2].eye) - glm::dvec3(keys[2].target));
  const glm::dvec3 um = glm::normalize(glm::dvec3(mid.eye) - glm::dvec3(mid.target));
  EXPECT_NEAR(std::acos(glm::dot(ua, um)), std::acos(glm::dot(um, ub)), 1e-4);
  // Every frame is a valid camera.
  for (const Camera& c : path_cameras({keys, 50})) EXPECT_NO_THROW(validate_camera(c, "frame"));
}

// ---- JSON.

TEST(CameraPathJson, RoundTrip) {
  CameraPath path{three_keys(), 17};
  const CameraPath back = parse_camera_path(camera_path_json(path), "round-trip");
  EXPECT_EQ(back.frames, 17u);
  ASSERT_EQ(back.keys.size(), 3u);
  for (size_t i = 0; i < 3; ++i) expect_same(back.keys[i], path.keys[i]);

  testing::TempDir dir;
  save_camera_path(dir / "p.json", path);
  const CameraPath loaded = load_camera_path(dir / "p.json");
  EXPECT_EQ(loaded.frames, 17u);
  for (size_t i = 0; i < 3; ++i) expect_same(loaded.keys[i], path.keys[i]);
}

TEST(CameraPathJson, BareListTakesTheDefaultFrames) {
  const CameraPath p = parse_camera_path(
      R"([{"eye":[0,0,3],"target":[0,0,0],"up":[0,1,0],"fov":40,"note":"ignored"},
          {"eye":[0,0,1],"target":[0,0,0],"up":[0,1,0],"fov":40}])",
      "list.json", 12);
  EXPECT_EQ(p.frames, 12u);
  EXPECT_EQ(p.keys[1].eye, glm::vec3(0, 0, 1));
}

TEST(CameraPathJson, ErrorsNameTheFileAndTheProblem) {
  const std::string k = R"({"eye":[0,0,3],"target":[0,0,0],"up":[0,1,0],"fov":40})";
  auto err = [](const std::string& text) { return error_of([&] { parse_camera_path(text, "p.json"); }); };
  EXPECT_EQ(err("{\"keys\": [").rfind("p.json: not a JSON camera path: ", 0), 0u);
  EXPECT_EQ(err("[NaN, 1]").rfind("p.json: not a JSON camera path: ", 0), 0u);
  EXPECT_EQ(err("3"), "p.json: expected a list of cameras or {\"keys\": [...]}");
  EXPECT_EQ(err("{\"frames\": 3}"), "p.json: missing key \"keys\" (a list of cameras)");
  EXPECT_EQ(err("{\"keys\": 5}"), "p.json: \"keys\" must be a list of cameras");
  EXPECT_EQ(err("[" + k + "]"), "p.json: a camera path needs at least 2 keys, got 1");
  EXPECT_EQ(err("[]"), "p.json: a camera path needs at least 2 keys, got 0");
  EXPECT_EQ(err("[" + k + ", {\"target\":[0,0,0],\"up\":[0,1,0],\"fov\":40}]"), "p.json: key 2: missing \"eye\"");
  EXPECT_EQ(err("[" + k + ", {\"eye\":[0,0,1],\"target\":[0,0,0],\"up\":[0,1,0]}]"), "p.json: key 2: missing \"fov\"");
  EXPECT_EQ(err("[" + k + ", {\"eye\":[0,0],\"target\":[0,0,0],\"up\":[0,1,0],\"fov\":40}]"),
            "p.json: key 2: \"eye\" must be an array of 3 numbers");
  EXPECT_EQ(err("[" + k + ", {\"eye\":[0,\"a\",1],\"target\":[0,0,0],\"up\":[0,1,0],\"fov\":40}]"),
            "p.json: key 2: \"eye\" must be a number");
  EXPECT_EQ(err("[" + k + ", {\"eye\":[0,1e39,1],\"target\":[0,0,0],\"up\":[0,1,0],\"fov\":40}]"),
            "p.json: key 2: \"eye\" is not a finite float");
  EXPECT_EQ(err("[" + k + ", {\"eye\":[0,0,1],\"target\":[0,0,0],\"up\":[0,1,0],\"fov\":\"wide\"}]"),
            "p.json: key 2: \"fov\" must be a number");
  EXPECT_EQ(err("[" + k + ", 7]"), "p.json: key 2: expected an object with eye, target, up and fov");
  EXPECT_EQ(err("[" + k + ", {\"eye\":[0,0,1],\"target\":[0,0,1],\"up\":[0,1,0],\"fov\":40}]"),
            "p.json: key 2: eye and target are the same point (0, 0, 1)");
  EXPECT_EQ(err("[" + k + ", {\"eye\":[0,0,1],\"target\":[0,0,0],\"up\":[0,0,1],\"fov\":40}]")
                .rfind("p.json: key 2: up (0, 0, 1) is parallel to the view direction", 0),
            0u);
  EXPECT_EQ(err("{\"frames\": 1, \"keys\": [" + k + "," + k + "]}"),
            "p.json: \"frames\" must be an integer from 2 to 100000");
  EXPECT_EQ(err("{\"frames\": 2.5, \"keys\": [" + k + "," + k + "]}"),
            "p.json: \"frames\" must be an integer from 2 to 100000");
  // Issue 22: at most kMaxPathFrames, as --frames.
  EXPECT_EQ(err("{\"frames\": 1000000, \"keys\": [" + k + "," + k + "]}"),
            "p.json: \"frames\" is 1000000, above the limit of 100000 frames");
  EXPECT_EQ(err("{\"frames\": 18446744073709551615, \"keys\": [" + k + "," + k + "]}"),
            "p.json: \"frames\" is 18446744073709551615, above the limit of 100000 frames");
  EXPECT_EQ(err("{\"frames\": -5, \"keys\": [" + k + "," + k + "]}"),
            "p.json: \"frames\" must be an integer from 2 to 100000");
  EXPECT_EQ(parse_camera_path("{\"frames\": 100000, \"keys\": [" + k + "," + k + "]}", "p.json").frames,
            kMaxPathFrames);
  EXPECT_EQ(error_of([] { load_camera_path("/no/such/path.json"); }),
            "/no/such/path.json: does not exist");
}

// Mutated path files: every outcome is a parsed path or one of the two
// documented exceptions (a crash or another exception fails the test).
TEST(CameraPathJson, MutatedTextNeverEscapesTheErrorPolicy) {
  const std::string valid = camera_path_json({three_keys(), 9});
  std::mt19937 rng(7);
  const std::string alphabet = "{}[],:\"0123456789.-eE+ atrufnl";
  int parsed = 0;
  for (int i = 0; i < 3000; ++i) {
    std::string text = valid;
    const int edits = 1 + int(rng() % 4);
    for (int e = 0; e < edits && !text.empty(); ++e) {
      const size_t at = rng() % text.size();
      switch (rng() % 3) {
        case 0:
          text[at] = alphabet[rng() % alphabet.size()];
          break;
        case 1:
          text.erase(at, 1 + rng() % 8);
          break;
        default:
          text.insert(at, 1, alphabet[rng() % alphabet.size()]);
          break;
      }
    }
    try {
      const CameraPath p = parse_camera_path(text, "m.json");
      for (const Camera& c : p.keys) validate_camera(c, "parsed key");
      EXPECT_GE(p.frames, 2u);
      ++parsed;
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).rfind("m.json: ", 0), 0u) << e.what();
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("m.json: ", 0), 0u) << e.what();
    }
  }
  EXPECT_GT(parsed, 0);  // some mutations (inside numbers) still parse
}

}  // namespace
}  // namespace svo::render

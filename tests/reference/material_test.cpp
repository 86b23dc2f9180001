// Paper Fig. 9 as a test: on a Gaussian height field coloured by height,
// Eq. 17 (from the field's statistics) follows the averaged high-resolution
// ground truth within 1% from 0 to 70 degrees; the plain mean colour (MIP)
// does not. Beyond 70 degrees the ground truth shows more of the crests'
// colour than Eq. 17 (2.1% at 80 degrees on this field, 4.3% on the rougher
// built-in scene; Smith's approximation of masking is the likely cause, not
// yet established): docs/RESULTS.md.
#include "svo/reference/material.h"

#include <glm/common.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

namespace svo::reference {
namespace {

float relative(glm::vec3 a, glm::vec3 b) {
  glm::vec3 e = glm::abs(a - b) / glm::max(b, glm::vec3(1e-6f));
  return std::max(e.x, std::max(e.y, e.z));
}

TEST(Material, Eq17FollowsTheGroundTruthUpTo70DegreesAndMipDoesNot) {
  // The built-in scene's waves and colours at a moderate roughness.
  voxelizer::HeightfieldScene field(64, 0.08f, 0.25f, 0.0075f, 5, glm::vec3(0.45f, 0.4f, 0.3f), glm::vec3(0.3f, 0.2f, 0.15f));
  MaterialOptions o;
  o.degrees = {0, 10, 20, 30, 40, 50, 60, 70};
  std::vector<MaterialPoint> curve = material_curve(field, o);
  ASSERT_EQ(curve.size(), o.degrees.size());
  float mip_worst = 0;
  for (const auto& p : curve) {
    float e17 = relative(p.eq17, p.truth), em = relative(p.mip, p.truth);
    std::printf("%4.0f deg: truth %.4f %.4f %.4f  eq17 %.4f %.4f %.4f (%.2f%%)  mip (%.2f%%)\n", p.degrees, p.truth.x,
                p.truth.y, p.truth.z, p.eq17.x, p.eq17.y, p.eq17.z, 100 * e17, 100 * em);
    EXPECT_LT(e17, 0.01f) << p.degrees << " degrees";
    mip_worst = std::max(mip_worst, em);
  }
  EXPECT_GT(mip_worst, 0.01f) << "MIP colour should miss the view dependence";
}

// The paper's claim at every angle, 0 to 85 degrees: on the same waves at
// slope variance 0.01 per axis (the paper's Fig. 9 surface is of this kind:
// its colour shift appears only at grazing angles), Eq. 17 stays within 1%
// of the ground truth, and MIP colour, blind to the view, is off by more
// (4.3% at 85 degrees).
TEST(Material, Eq17FollowsTheGroundTruthAtEveryAngleOnASmootherField) {
  voxelizer::HeightfieldScene field(64, 0.08f, 0.25f, 0.0029f, 5, glm::vec3(0.45f, 0.4f, 0.3f), glm::vec3(0.3f, 0.2f, 0.15f));
  ASSERT_NEAR(field.slope_variance().x, 0.0099f, 0.0005f);
  MaterialOptions o;
  o.degrees = {0, 15, 30, 45, 60, 70, 75, 80, 85};
  std::vector<MaterialPoint> curve = material_curve(field, o);
  float mip_worst = 0;
  for (const auto& p : curve) {
    float e17 = relative(p.eq17, p.truth), em = relative(p.mip, p.truth);
    std::printf("%4.0f deg: eq17 %.2f%%, mip %.2f%%\n", p.degrees, 100 * e17, 100 * em);
    EXPECT_LT(e17, 0.01f) << p.degrees << " degrees";
    mip_worst = std::max(mip_worst, em);
  }
  EXPECT_GT(mip_worst, 0.02f) << "MIP colour should miss the view dependence";
}

TEST(Material, RefusesAPatchLargerThanTheField) {
  auto scene = voxelizer::make_scene("heightfield");
  MaterialOptions o;
  o.patch = 2.5f;
  EXPECT_THROW(material_curve(dynamic_cast<const voxelizer::HeightfieldScene&>(*scene), o), std::invalid_argument);
}

}  // namespace
}  // namespace svo::reference

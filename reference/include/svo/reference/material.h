// Paper Fig. 9: the colour of a Gaussian height field whose colour is a
// function of height, seen from angles 0 to 85 degrees, lighting off and
// Lambda(l) = 0 (an ambient light of radiance 1, no specular): the average of
// a high-resolution reference render against Eq. 17 evaluated from the
// field's known statistics, and against the plain mean colour (MIP).
#pragma once

#include <glm/vec3.hpp>

#include <cstdint>
#include <functional>
#include <vector>

#include "svo/render/renderer.h"
#include "svo/voxelizer/scenes.h"

namespace svo::reference {

struct MaterialOptions {
  std::vector<float> degrees{0, 10, 20, 30, 40, 50, 60, 70, 80};
  uint32_t size = 64;      // reference pixels along y (along x: size cos(angle), the same ground area per pixel)
  uint32_t spp = 4;        // reference samples per pixel
  float patch = 1.6f;      // side of the square of the field the image spans at every angle, scene units
  float distance = 20.0f;  // camera distance: nearly orthographic
  std::function<void(double)> progress;  // fraction of the angles done; may be empty
};

struct MaterialPoint {
  float degrees = 0;
  glm::vec3 truth{0};  // mean radiance of the reference render over its covered pixels
  glm::vec3 eq17{0};   // abar + a_s Lambda(v) / (Lambda(v) + 2), the field's own sigma and colour statistics
  glm::vec3 mip{0};    // abar
};

// The camera and lighting of one angle: looking at the field's centre from
// (sin, 0, cos) x distance, lights off, ambient 1, no specular, black
// background. The image spans the patch on the field: `height` pixels along
// y and height x cos(angle) (at least 1) along x, where the view stretches
// the ground by 1 / cos(angle).
render::RenderSettings material_view(float degrees, uint32_t height, const MaterialOptions& options);

// The three curves over options.degrees. Throws std::invalid_argument for an
// angle outside [0, 90) or a patch larger than the field.
std::vector<MaterialPoint> material_curve(const voxelizer::HeightfieldScene& field, const MaterialOptions& options);

// What Eq. 17 and MIP need of a surface: its slope variances along x and y
// and its colour's abar and a_s (DESIGN section 6).
struct MaterialStatistics {
  glm::vec2 slope_variance{0};
  glm::vec3 abar{0}, a_s{0};
};

// The same curves for any surface around the plane z = 0 over [-1, 1]^2 with
// mean normal +z (a height map, HeightmapScene), Eq. 17 and MIP from
// `statistics` (measured over the patch the images span). Same throws.
std::vector<MaterialPoint> material_curve(const voxelizer::AnalyticScene& surface, const MaterialStatistics& statistics,
                                          const MaterialOptions& options);

}  // namespace svo::reference

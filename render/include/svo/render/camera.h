// Cameras and lights for the renderer's callers: view presets from an
// octree's bounds, and the command-line and JSON forms of cameras and lights.
// Every parser here takes untrusted text and reports a bad value as one line
// (std::invalid_argument) that names the value and what was expected.
#pragma once

#include <glm/vec3.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "svo/octree/octree.h"
#include "svo/render/renderer.h"

namespace svo::render {

// Names accepted by view_preset: "far", "mid", "close".
std::vector<std::string> view_preset_names();

// Where a preset looks from: the direction from the target towards the
// eye by azimuth (degrees about +y, 0 along +z) and elevation (degrees above
// the horizontal), and the distance from the target in object sizes
// (object_size; 0: the preset's own).
struct PresetOptions {
  float azimuth_deg = 35;
  float elevation_deg = 30;
  float distance = 0;
  // far frames the whole domain cube (its bounding sphere) and mid is 3
  // times closer, aimed at the surface's centre: the presets the far-view
  // accuracy tests were calibrated on, where a far pixel covers many voxels.
  bool whole_domain = false;
};

// A camera placed from the octree alone (fov 40 degrees, world +y up), with
// the direction of `options` (default: azimuth 35, elevation 30 degrees):
//   far   the object (the bounds of the finest level's bricks, where the
//         surface is; the domain cube when there is none) framed: the box's
//         eight corners inside 90% of the narrower field of view;
//   mid   the same target, 2 times closer;
//   close aimed at a surface point found by marching the mid view's rays
//         through the finest level's signed distance hbar (where it changes
//         sign), from close_distance away, along a direction 60 degrees from
//         the surface normal (less when that direction runs into the
//         surface).
// options.distance > 0 puts the eye that many object sizes from the target
// instead. `aspect` (width / height) keeps the far view's box inside the
// narrower field of view.
// @throw std::invalid_argument naming `name` and the valid names for an
//        unknown preset, or for an elevation outside (-90, 90) or a negative distance.
// @throw std::runtime_error when the octree has no surface (no finest brick),
//        or, for close, when no ray of the mid view meets the surface.
Camera view_preset(const octree::Octree& tree, std::string_view name, float aspect = 1.0f,
                   const PresetOptions& options = {});

// How far the close preset's eye is from its target: where the finest voxel
// spans 1/64 of the narrower field of view (8 pixels of a 512-pixel image:
// each voxel's shading visible, not a blur of interpolated voxels dozens of
// pixels wide), or half the mid view's distance when that is closer (a
// coarse octree); with procedural detail octaves, which hold detail finer
// than any voxel, max(8 finest voxels, 2% of the size), the deep zoom.
float close_distance(const octree::Octree& tree, float aspect = 1.0f, const PresetOptions& options = {});

// What presets frame: the bounds of the finest level's bricks (where the
// surface is), or the domain cube when there is none.
std::pair<glm::vec3, glm::vec3> object_bounds(const octree::Octree& tree);

// The object's size: the diagonal of the finest level's bricks' bounds (the
// domain cube's when there is none). Depth of field and --distance are
// measured in it.
float object_size(const octree::Octree& tree);

// The default lights of a view: a key light (irradiance 3) from the camera's
// upper left, a little behind it, and a dim fill (irradiance 0.6) from the
// right, so that the side the key does not reach still shows its shape.
std::vector<Light> default_lights(const Camera& camera);

// The first point along origin + t dir (t >= 0, dir need not be unit) where
// the finest level's trilinear hbar changes sign from outside to inside,
// inside the domain cube, found in half-voxel steps and refined by
// bisection (what the close preset uses); nullopt when the ray meets none.
std::optional<glm::vec3> march_to_surface(const octree::Octree& tree, glm::vec3 origin, glm::vec3 dir);

// Checks a camera as parse_camera and load_camera_json do: finite numbers,
// eye and target coordinates within +-1e18 and apart by more than float
// precision, up not parallel to the view direction, fov in (0, 180)
// degrees, aperture >= 0 and, with an aperture, focus > 0.
// @throw std::invalid_argument "<where>: <what is wrong>".
void validate_camera(const Camera& camera, const std::string& where);

// "ex,ey,ez,tx,ty,tz,ux,uy,uz,fov": eye, target, up, vertical field of view
// in degrees (pinhole).
// @throw std::invalid_argument "--camera '<text>': <what is wrong>" (count of
//        numbers, a value that is not a finite number, and validate_camera's checks).
Camera parse_camera(std::string_view text);

// A camera file: {"eye": [x, y, z], "target": [x, y, z], "up": [x, y, z],
// "fov": degrees, "aperture": lens radius (optional, default 0), "focus":
// focus distance (optional; required when aperture > 0)}. Unknown keys are
// ignored.
// @throw std::runtime_error "<path>: <what is wrong>" for a file that cannot
//        be read (missing, not a regular file, over 1 MiB) or is not JSON; std::invalid_argument "<path>: <what is
//        wrong>" for a missing key, a wrong type and validate_camera's checks.
Camera load_camera_json(const std::string& path);

// The same from the file's text; `path` names it in messages.
Camera parse_camera_json(std::string_view text, const std::string& path);

// Writes `camera` in the form load_camera_json reads, atomically (temporary
// file in the same directory, fsync, rename).
// @throw std::runtime_error "<path>: cannot write: <reason>".
void save_camera_json(const std::string& path, const Camera& camera);

// A light from its command-line form:
//   dir:X,Y,Z[,IRRADIANCE[,ANGLE]]      directional, (X, Y, Z) towards the light,
//                                       irradiance at normal incidence (default 3),
//                                       angular radius in radians (default 0.02)
//   point:X,Y,Z[,INTENSITY[,RADIUS]]    point light at (X, Y, Z), irradiance =
//                                       intensity / distance^2 (default: 3 at
//                                       `scene_centre`), radius in scene units
//                                       (default 1% of the distance to `scene_centre`)
// @throw std::invalid_argument "--light '<text>': <what is wrong>".
Light parse_light(std::string_view text, glm::vec3 scene_centre);

}  // namespace svo::render

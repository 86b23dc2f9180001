// Camera paths for flythroughs (issue 6): the deep zoom from a whole-object
// view to a surface point, keyframe interpolation, and the JSON form of a
// path. The parsers take untrusted text: every problem is one line that
// names the source and what is wrong (std::invalid_argument or
// std::runtime_error), never a crash.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "svo/octree/octree.h"
#include "svo/render/renderer.h"

namespace svo::render {

// The most frames a path may ask for: path files, --frames and deep zooms
// (a flythrough writes one image per frame).
inline constexpr uint32_t kMaxPathFrames = 100000;

// A path: keyframes (pinhole cameras, validate_camera's rules) and the
// number of frames to render along it, in [2, kMaxPathFrames]. Frame f of N sits at key parameter
// u = f (K - 1) / (N - 1) (K keys): frames are spread evenly over the
// segments, and the keys are frames whenever K - 1 divides N - 1.
struct CameraPath {
  std::vector<Camera> keys;  // at least 2
  uint32_t frames = 60;      // at least 2
};

// The width of the view at the target's distance: 2 |target - eye| tan(fov / 2), scene units.
float view_width(const Camera& camera);

// The camera at key parameter u in [0, K - 1] (clamped). Between keys a and
// b = a + 1, with s = u - a in [0, 1] (the rule is the same for every pair,
// and gives each key back exactly at s = 0 and s = 1):
//   target    linear: (1 - s) a.target + s b.target;
//   distance  |eye - target| geometric: d_a^(1 - s) d_b^s, so that a zoom
//             along a segment shrinks the view by the same factor per frame;
//   direction from target to eye: spherical linear interpolation of the unit
//             vectors (linear and renormalised when they are within 1e-6);
//   eye       target + distance * direction;
//   up        spherical linear interpolation of the unit up vectors (the
//             key's own length is dropped);
//   fov       linear.
// Keys must have passed validate_camera. Opposite view directions or up
// vectors between two keys have no unique slerp: the rule turns about an
// arbitrary perpendicular axis then.
Camera sample_path(const std::vector<Camera>& keys, double u);

// The N cameras of `path` (sample_path at u = f (K - 1) / (N - 1)).
// @throw std::invalid_argument for fewer than 2 keys, fewer than 2 frames or
//        more than kMaxPathFrames.
std::vector<Camera> path_cameras(const CameraPath& path);

// A deep zoom: `frames` cameras from `start` (frame 0 keeps start's eye, up
// and fov and looks at `target`) towards `target` along the view direction,
// the eye's distance to the target shrinking geometrically by `zoom` over
// the path, so that the view width shrinks by the same factor zoom^(1/(N-1))
// from one frame to the next and the last view is `zoom` times narrower than
// the first. The field of view stays fixed. Returned as a two-key path
// (sample_path reproduces it exactly).
// @throw std::invalid_argument "deep-zoom: <why>" for zoom not finite or
//        < 1, frames outside [2, kMaxPathFrames], or a start camera that validate_camera refuses
//        with `target` as its target.
CameraPath deep_zoom_path(const Camera& start, glm::vec3 target, float zoom, uint32_t frames);

// The default deep-zoom target of an octree: the first surface point (where
// the finest level's hbar changes sign) along the centre ray of `camera`;
// when the centre ray meets none, along rays in rings further out in the
// image (as the close preset searches). nullopt when none meets the surface.
std::optional<glm::vec3> surface_target(const octree::Octree& tree, const Camera& camera, float aspect);

// A deep-zoom target on the silhouette: along the horizontal line through
// the centre of `camera`'s image, the outermost ray (to the right of the
// centre) that still meets the finest level's surface, found by bisection
// on the image coordinate to 2^-40 of the half width; the point where that
// grazing ray meets the surface. A zoom towards it keeps the silhouette at
// the centre of every frame. nullopt when the centre ray meets no surface
// or the line leaves the image before the surface ends.
std::optional<glm::vec3> silhouette_target(const octree::Octree& tree, const Camera& camera, float aspect);

// A path file:
//   {"frames": N (optional, in [2, kMaxPathFrames]), "keys": [KEY, KEY, ...]}   or   [KEY, KEY, ...]
// with KEY = {"eye": [x, y, z], "target": [x, y, z], "up": [x, y, z],
// "fov": degrees} (the camera file's form, pinhole only; unknown keys are
// ignored). `frames` is left at `default_frames` when the file has none.
// Safe for untrusted input.
// @throw std::runtime_error "<source_name>: not a JSON camera path: <why>"
//        for text that is not JSON; std::invalid_argument "<source_name>:
//        <what is wrong>" for a wrong shape, a missing key ("key 2: missing
//        \"eye\""), a value that is not a finite number, fewer than 2 keys,
//        a key that validate_camera refuses, frames < 2, or frames above
//        kMaxPathFrames ("<source_name>: \"frames\" is N, above the limit of
//        100000 frames"), refused before any camera is made.
CameraPath parse_camera_path(std::string_view json, const std::string& source_name, uint32_t default_frames = 60);

// Reads `path` and parses it (parse_camera_path with the path as source name).
// @throw svo::files::FileError for a missing file, one that is not a regular file (a FIFO, a
//        device) or one larger than 64 MiB; what parse_camera_path throws.
CameraPath load_camera_path(const std::string& path, uint32_t default_frames = 60);

// The JSON text parse_camera_path reads ({"frames": N, "keys": [...]}),
// each float written as the shortest decimal that reads back as the same float.
std::string camera_path_json(const CameraPath& path);

// Writes camera_path_json(path) to `file` atomically (temporary file, fsync, rename).
// @throw std::runtime_error "<file>: cannot write: <reason>".
void save_camera_path(const std::string& file, const CameraPath& path);

}  // namespace svo::render

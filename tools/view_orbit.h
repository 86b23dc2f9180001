// The camera of `svo view`: an orbit around a target point, with the
// distance changed by factors so that zooming from the whole model down to a
// single voxel takes a number of steps proportional to the logarithm of the
// scale, not to the scale.
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec3.hpp>

#include "svo/render/renderer.h"

namespace svo::tools {

class Orbit {
 public:
  // Takes over `camera`'s eye, target, up (the orbit's pole) and field of view.
  // `scene_size` bounds the distance to [1e-6, 100] x scene_size.
  Orbit(const render::Camera& camera, float scene_size) : fov_deg_(camera.fov_deg), scene_size_(scene_size) {
    pole_ = glm::normalize(camera.up);
    glm::vec3 any = std::abs(pole_.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    e1_ = glm::normalize(any - pole_ * glm::dot(any, pole_));
    e2_ = glm::cross(pole_, e1_);
    look_at(camera.eye, camera.target);
  }

  // Keeps the eye where it is and turns to orbit around `target` from now on.
  void look_at(glm::vec3 eye, glm::vec3 target) {
    target_ = target;
    glm::vec3 offset = eye - target;
    distance_ = clamp_distance(glm::length(offset));
    glm::vec3 dir = glm::length(offset) > 0 ? offset / glm::length(offset) : pole_;
    pitch_ = clamp_pitch(std::asin(std::clamp(glm::dot(dir, pole_), -1.0f, 1.0f)));
    yaw_ = std::atan2(glm::dot(dir, e2_), glm::dot(dir, e1_));
  }

  // A drag of (dx, dy) window pixels in a window `height` pixels high turns
  // the model with the cursor: half a turn per window height.
  void rotate(double dx, double dy, double height) {
    float radians_per_pixel = float(M_PI / std::max(height, 1.0));
    yaw_ -= float(dx) * radians_per_pixel;
    pitch_ = clamp_pitch(pitch_ + float(dy) * radians_per_pixel);
  }

  // Moves the target so that the point under the cursor at the target's
  // depth follows the cursor.
  void pan(double dx, double dy, double height) {
    float per_pixel = 2 * distance_ * std::tan(glm::radians(fov_deg_) / 2) / float(std::max(height, 1.0));
    glm::vec3 forward = -direction();
    glm::vec3 right = glm::normalize(glm::cross(forward, pole_));
    glm::vec3 up = glm::cross(right, forward);
    target_ += (-right * float(dx) + up * float(dy)) * per_pixel;
  }

  // Multiplies the distance to the target by `factor` (< 1 comes closer).
  void zoom(double factor) { distance_ = clamp_distance(distance_ * float(factor)); }

  render::Camera camera() const {
    render::Camera c;
    c.eye = target_ + direction() * distance_;
    c.target = target_;
    c.up = pole_;
    c.fov_deg = fov_deg_;
    return c;
  }
  float distance() const { return distance_; }

 private:
  glm::vec3 direction() const {  // unit vector from the target to the eye
    return std::cos(pitch_) * (std::cos(yaw_) * e1_ + std::sin(yaw_) * e2_) + std::sin(pitch_) * pole_;
  }
  static float clamp_pitch(float pitch) {
    const float limit = glm::radians(89.5f);  // the pole itself has no "right"
    return std::clamp(pitch, -limit, limit);
  }
  float clamp_distance(float d) const { return std::clamp(d, 1e-6f * scene_size_, 100.0f * scene_size_); }

  glm::vec3 pole_, e1_, e2_;  // orthonormal: the up axis and two directions across it
  glm::vec3 target_{0};
  float distance_ = 1, yaw_ = 0, pitch_ = 0;
  float fov_deg_ = 40;
  float scene_size_ = 1;
};

}  // namespace svo::tools

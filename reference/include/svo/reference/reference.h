// Ground truth (DESIGN section 9): the source geometry ray traced with
// stratified supersampling over each pixel's cone footprint, shaded with the
// micro-BRDF alone and the same camera, lights and shadows as the cone tracer
// (render::RenderSettings), so that `svo compare` can judge the tracer's
// frames against it.
#pragma once

#include <cstdint>
#include <functional>

#include "svo/reference/geometry.h"
#include "svo/render/renderer.h"

namespace svo::reference {

struct ReferenceSettings {
  // Image size, camera (thin lens included), lights, shadows, ambient,
  // background and specular weight as for the cone tracer; mode, gbuffer and
  // max_steps are ignored.
  render::RenderSettings render;
  // Samples per pixel, >= 1: a stratified a x b grid with a * b = spp (a the
  // largest divisor of spp not above sqrt(spp): a square grid when spp is a
  // perfect square), jittered, mapped to the footprint disk by the
  // concentric mapping (Shirley & Chiu 1997).
  uint32_t spp = 64;
  uint64_t seed = 1;  // the same seed gives the same image, whatever the threads
  // Light-field luminaires (render.luminaire.luminaires; the sampling
  // options there are ignored): each hit of the surface is lit by dense
  // quadrature of the light-field integral, luminaire_quadrature^2 points
  // per texel of plane S (their centres), >= 1; see render_reference.
  uint32_t luminaire_quadrature = 1;
  // Called from worker threads with the fraction of rows done; may be empty.
  std::function<void(double)> progress;
};

// Renders the reference frame. Per pixel, spp rays through the pixel's cone
// footprint: the cone of the tracer (render/src/trace_setup.cpp) has its apex
// at the eye, its axis through the pixel centre and a disk of the pixel's
// area (radius pixel side / sqrt(pi)) as cross-section at unit distance; each
// ray's direction is a stratified point of that disk. With an aperture A, the
// ray starts at a stratified point of the lens disk (radius A, spanned by the
// camera's right and up vectors; its points paired with the footprint's by a
// random permutation) and passes through the point where the footprint ray
// meets the focus plane, perpendicular to the view axis at distance `focus`
// from the eye (thin lens; Camera::focus is "along the view axis"). On the
// axis the bundle's radius at distance t is then A |t - focus| / focus beside
// the footprint, the tracer's r(t); off the axis the tracer measures t along
// the pixel's ray, which puts its sharp surface on a sphere, not this plane.
//
// Shading mirrors svo_shade (shaders/common/tracer.glsl) with the
// micro-BRDF alone: true normal n, colour a at the hit, slope variance
// sigma_rho^2 (svo_total_slope_variance(0, sigma_rho^2)), Lambda = 0 so that
// abar(v, l) = a:
//   L = ambient a + sum_lights E (a / pi + specular svo_specular_brdf(v, l)) (n . l) V
// With shadows, V is one shadow ray per sample and light towards a
// stratified point of the light's extent (directional: the cone of angular
// radius `size`; point: the sphere of radius `size`, through the solid angle
// it subtends), the strata paired with the pixel samples by a random
// permutation. A sample that meets nothing takes the background; the pixel
// is the mean of its samples, alpha the fraction that met the surface.
//
// Light-field luminaires (render.luminaire, render/include/svo/render/
// luminaire.h) add to that, for each hit point p at height Delta > 0 above
// plane S (nothing behind S), the quadrature of
//   sum over texels t of S, points s of t:
//     L(u -> s) f(v, l) (n . l) V(p, s) Delta / r^3 (texel area / k^2)
// with L(u -> s) = sum_m C_m(s) Phi_m(u) (u where the line from p through s
// crosses U; only the texels of the box of S that the basis functions'
// supports reach from p, Eq. 7), r = |s - p|, l = (s - p) / r, f the
// material's BRDF (svo_material_brdf of shaders/common, as the environment
// path) and V one exact shadow ray from p (offset as the lights' shadow
// rays are) to s, traced only where the rest is not 0: the same integral as
// svo_luminaire_quadrature (shaders/common/luminaire.glsl) with exact
// visibility. The lights still shine; svo reference drops them with
// luminaires, as svo render does.
//
// @throw std::invalid_argument "<what>: <why>" for bad settings (size 0,
//        spp 0, more than render::kMaxLights lights, a light that is not
//        finite, a camera that render::validate_camera refuses, a
//        luminaire without a field or with at == aim, more than
//        LuminaireOptions::kMaxLuminaires luminaires, quadrature 0).
render::Frame render_reference(const Geometry& geometry, const ReferenceSettings& settings);

}  // namespace svo::reference

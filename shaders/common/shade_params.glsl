// The parameters of the shading passes (environment, material, sampling),
// laid out identically in C++ and in the shaders' std430 block: vec4 and
// uvec4 members only. The environment's texels, its sampling distribution and
// a measured BRDF's tables live in the shading tables (distribution.glsl's
// host accessor svo_table) at the offsets given here.
#ifndef SVO_SHADE_PARAMS_GLSL
#define SVO_SHADE_PARAMS_GLSL
#include "prelude.glsl"

// Material kinds (render::BrdfKind).
SVO_CONST uint SVO_BRDF_LAMBERT = 0u;
SVO_CONST uint SVO_BRDF_BECKMANN = 1u;
SVO_CONST uint SVO_BRDF_GGX = 2u;
SVO_CONST uint SVO_BRDF_PHONG = 3u;
SVO_CONST uint SVO_BRDF_MERL = 4u;

// Sampling flags (SvoShadeParams::sampling.z).
SVO_CONST uint SVO_SHADE_ENV_SHADOWS = 1u;    // environment samples see visibility cones through the octree
SVO_CONST uint SVO_SHADE_LIGHT_SHADOWS = 2u;  // so do the lights
SVO_CONST uint SVO_SHADE_PRECONVOLVED = 4u;   // the environment looked up pre-convolved (forward.glsl), no samples
// The environment's light sampled from the BRDF alone (Bagher et al.'s
// sampling), no sample of the map and no multiple importance sampling.
SVO_CONST uint SVO_SHADE_BRDF_SAMPLING = 8u;

struct SvoShadeParams {
  uvec4 env;       // x: width, y: height (0: no environment), z: table offset of the rgb texels, w: of the distribution
  vec4 env_xform;  // x: rotation about +Y (radians), y: radiance scale, z: table offset of the pre-convolved
                   // maps (uint bits; environment.glsl, svo_env_preconvolved), w: table offset of a
                   // measured BRDF's SG fit (uint bits; 0: none; lobe_filter.glsl)
  uvec4 material;  // x: kind (SVO_BRDF_*), y: table offset of a measured BRDF's values, z: of its sampling tables,
                   // w: the scene's materials in the table (0: this one alone; svo_scene_material)
  vec4 diffuse;    // rgb: diffuse albedo, tinted by the voxels' abar; w: roughness alpha (Beckmann, GGX)
  vec4 specular;   // rgb: Fresnel reflectance at normal incidence f0; w: Phong exponent
  uvec4 sampling;  // x: samples per pixel, y: seed, z: flags (SVO_SHADE_*), w: table offset of the scene's materials
  // A textured area light (area_light.glsl): x, y its texels' width and
  // height (y 0: none), w the table offset of their distribution; the
  // centre's w the table offset of the rgb texels (uint bits).
  uvec4 area;
  vec4 area_centre;
  vec4 area_u;  // xyz: the edge vector along the texture's rows
  vec4 area_v;  // xyz: the edge vector towards row 0
};

// A material as the shading kernels read it (material.glsl).
struct SvoMaterial {
  uint kind;           // SVO_BRDF_*
  vec3 diffuse;        // diffuse albedo (times abar where a voxel shades)
  vec3 f0;             // Fresnel reflectance at normal incidence
  vec2 alpha2;         // squared roughness per axis of the frame (Beckmann: 2 sigma^2; GGX: alpha^2)
  float exponent;      // Phong NDF exponent
  uint merl;           // table offset of a measured BRDF's values
  uint merl_sampling;  // and of its sampling tables
  uint sg_fit;         // and of its SG fit (svo_material_lobes; 0: none)
};

// Floats per material of the scene's table: kind, MERL values and sampling
// offsets (uint bits), exponent, diffuse rgb, roughness alpha, f0 rgb, the
// MERL SG fit's offset (uint bits).
SVO_CONST uint SVO_MATERIAL_FLOATS = 12u;

SVO_FN SvoMaterial svo_material_of(SvoShadeParams sp) {
  SvoMaterial m;
  m.kind = sp.material.x;
  m.diffuse = vec3(sp.diffuse);
  m.f0 = vec3(sp.specular);
  m.alpha2 = vec2(sp.diffuse.w * sp.diffuse.w);
  m.exponent = sp.specular.w;
  m.merl = sp.material.y;
  m.merl_sampling = sp.material.z;
  m.sg_fit = floatBitsToUint(sp.env_xform.w);
  return m;
}

#endif

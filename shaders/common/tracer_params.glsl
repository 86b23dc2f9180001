// The parameters of one trace, laid out identically in C++ and in the
// shader's std430 block: vec4 and uvec4 members only, so that no member
// needs padding on either side.
#ifndef SVO_TRACER_PARAMS_GLSL
#define SVO_TRACER_PARAMS_GLSL
#include "prelude.glsl"

SVO_CONST uint SVO_ABSENT = 0xFFFFFFFFu;  // channel offset of a channel the file lacks
SVO_CONST uint SVO_MAX_LIGHTS = 4u;

// Modes (render::Mode).
SVO_CONST uint SVO_MODE_PREFILTERED = 0u;
SVO_CONST uint SVO_MODE_NEAREST = 1u;
SVO_CONST uint SVO_MODE_ALPHA = 2u;
SVO_CONST uint SVO_MODE_MIP = 3u;
SVO_CONST uint SVO_MODE_RAYMARCH = 4u;

// Flags (image.w).
SVO_CONST uint SVO_FLAG_SHADOWS = 1u;
SVO_CONST uint SVO_FLAG_GBUFFER = 2u;
SVO_CONST uint SVO_FLAG_CURVED_MASKS = 4u;  // prefiltered and alpha: masks bend with the surface along the cone
SVO_CONST uint SVO_FLAG_FRONT_FACING = 8u;  // prefiltered and alpha: a mean normal never faces away from the eye
SVO_CONST uint SVO_FLAG_ELEMENT_NORMALS = 16u;  // prefiltered and alpha: wide cones' elements shade half with their own normal
SVO_CONST uint SVO_FLAG_COVERED_PART = 32u;  // prefiltered: an element shades the part of the footprint its fresh bits cover
SVO_CONST uint SVO_FLAG_DETAIL = 64u;  // a feature bit of SVO_SPEC_FLAGS only: the file's detail octaves may be drawn
SVO_CONST uint SVO_FLAG_CREASE_SPLIT = 128u;  // prefiltered: a part across which the normal turns fast is shaded as two halves
// A feature bit of SVO_SPEC_FLAGS only: some element of the frame may be
// wider than the finest level reads (render::cones_may_blend), so that
// svo_step may blend two levels' distances and normals.
SVO_CONST uint SVO_FLAG_LEVEL_BLEND = 256u;
// A feature bit of SVO_SPEC_FLAGS only: the octree stores shading normals
// (the shading_normal channel, open edges' caps).
SVO_CONST uint SVO_FLAG_SHADING_NORMAL = 512u;

// Specialisation (the host contract in tracer.glsl): SVO_SPEC_MODE is the
// mode every pixel of a kernel traces, or SVO_SPEC_ANY to read it from
// params; SVO_SPEC_FLAGS masks the flags (and SVO_FLAG_DETAIL) a kernel may
// see. A Vulkan host makes a pipeline per combination, so that its compiler
// drops the code a frame cannot reach (lavapipe runs every branch of a
// SIMD group, taken or not); the native host leaves both open.
SVO_CONST uint SVO_SPEC_ANY = 0xFFFFFFFFu;

// Parts of a voxel svo_fetch decodes (tracer.glsl).
SVO_CONST uint SVO_PART_DISTANCE = 1u;
SVO_CONST uint SVO_PART_NORMAL = 2u;
SVO_CONST uint SVO_PART_SHADING = 4u;
SVO_CONST uint SVO_PART_HEIGHT = 8u;

SVO_CONST uint SVO_MASK_BINS = 256u;     // the mask table is SVO_MASK_BINS x SVO_MASK_BINS over (theta, v)
SVO_CONST uint SVO_SHADOW_STEPS = 512u;  // cone elements per shadow cone at most

// Encodings of the channels that have more than one (octree::Encoding values).
SVO_CONST uint SVO_ENC_F32 = 1u;
SVO_CONST uint SVO_ENC_U8_LOG_RELATIVE = 3u;
SVO_CONST uint SVO_ENC_U8_LOG_SLOPE = 4u;

struct SvoTraceParams {
  vec4 eye;        // xyz: camera position; w: cone radius per unit distance (pixel footprint)
  vec4 cam_u;      // xyz: right * tan(fov / 2) * aspect
  vec4 cam_v;      // xyz: up * tan(fov / 2)
  vec4 cam_w;      // xyz: unit view direction; w: lens radius (0: pinhole)
  vec4 lens;       // x: focus distance; y: rays per pixel (raymarch mode, n x n); z, w: first row and rows of them to trace
  vec4 domain;     // xyz: origin of the cube; w: its side
  vec4 material;   // x: sigma_rho^2; y: specular weight; z: finest voxel size; w: footprint spread weight
  vec4 constant_colour;  // abar when the file has no colour
  vec4 ambient;    // rgb
  vec4 background;  // rgb
  uvec4 image;     // width, height, mode, flags
  uvec4 tree;      // brick_size, depth_count, max_steps, light_count
  uvec4 pool;      // bytes per brick (all channels), bricks per pool chunk
  uvec4 offsets_a;  // byte offset in a brick of: distance, normal, height_dev, slope_dev (SVO_ABSENT)
  uvec4 offsets_b;  // slope_cov, colour, colour_slope, material
  uvec4 offsets_c;  // x: shading_normal (SVO_ABSENT); yzw: unused
  uvec4 encodings;  // encoding of: height_dev, slope_dev; z: materials in the scene (>= 1); w: unused
  vec4 detail;         // detail octaves (detail.glsl): x: amplitude, y: wavelength, z: gain
  vec4 detail_colour;  // xyz: colour per unit of detail height; w: footprint radius the finest level holds (voxel / sqrt(2))
  uvec4 detail_u;      // x: octaves (0: none); y: seed
  vec4 light_vector[4];    // xyz: direction towards the light, or position; w: 1 point, 0 directional
  vec4 light_radiance[4];  // rgb: irradiance (directional) or intensity (point); w: size
  vec4 shading;            // x: voxel size of the level prefiltered shading reads, in cone radii; y: 1 where the octree draws two-sided shells (svo_turn_to_eye); zw: unused
};

#endif

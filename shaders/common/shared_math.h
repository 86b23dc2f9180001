// C++ entry to the math of shaders/common/: the same source the shaders
// include, compiled as C++ with GLM (the dialect is described in prelude.glsl).
// Everything lands in namespace svo::math.
#pragma once

#include <glm/glm.hpp>

namespace svo::math {
using namespace glm;
#include "bandwidth_ops.glsl"
#include "beckmann.glsl"
#include "cone_mask.glsl"
#include "detail.glsl"
#include "display.glsl"
#include "erf.glsl"
#include "frame.glsl"
#include "gbuffer.glsl"
#include "lobe_filter_types.glsl"
#include "prelude.glsl"
#include "probe.glsl"
#include "sg.glsl"
#include "shade_params.glsl"
#include "voxel_codec.glsl"
#include "smith.glsl"
#include "trig.glsl"
#include "tracer_params.glsl"
}  // namespace svo::math

// The octree as a compute kernel reads it (the host contract of
// common/tracer.glsl): parameters, nodes, the mask table and the brick
// pools, from binding SVO_OCTREE_BINDING on, in the order of
// render::OctreeAccess::bind. Bricks lie in one or more buffers of whole
// bricks each, read three ways, chosen before including this file:
//   SVO_POOL_SINGLE   one storage buffer (fits maxStorageBufferRange; any device)
//   SVO_POOL_ADDRESS  up to SVO_POOL_SLOTS buffers through device addresses
//   (neither)         up to SVO_POOL_SLOTS storage buffers, a switch per read
//                     (devices without buffer device addresses; lavapipe
//                     runs it 2.7x slower than the others)
#ifndef SVO_OCTREE_BINDINGS_GLSL
#define SVO_OCTREE_BINDINGS_GLSL
#include "common/tracer_params.glsl"

#define SVO_POOL_SLOTS 8

// What this pipeline traces (tracer_params.glsl, "Specialisation").
layout(constant_id = 0) const uint SVO_SPEC_MODE = SVO_SPEC_ANY;
layout(constant_id = 1) const uint SVO_SPEC_FLAGS = SVO_SPEC_ANY;

layout(std430, set = 0, binding = SVO_OCTREE_BINDING) readonly restrict buffer ParamsBlock { SvoTraceParams params; };
layout(std430, set = 0, binding = SVO_OCTREE_BINDING + 1) readonly restrict buffer Nodes { uvec2 nodes[]; };
layout(std430, set = 0, binding = SVO_OCTREE_BINDING + 2) readonly restrict buffer Masks { uvec4 masks[]; };
#if defined(SVO_POOL_SINGLE)
layout(std430, set = 0, binding = SVO_OCTREE_BINDING + 3) readonly restrict buffer Pool { uint words[]; } pool;
#elif defined(SVO_POOL_ADDRESS)
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer SvoWords { uint w[]; };
layout(std430, set = 0, binding = SVO_OCTREE_BINDING + 3) readonly restrict buffer PoolAddresses { uvec2 pool_address[]; };
#else
layout(std430, set = 0, binding = SVO_OCTREE_BINDING + 3) readonly restrict buffer Pool0 { uint pool0[]; };
layout(std430, set = 0, binding = SVO_OCTREE_BINDING + 4) readonly restrict buffer Pool1 { uint pool1[]; };
layout(std430, set = 0, binding = SVO_OCTREE_BINDING + 5) readonly restrict buffer Pool2 { uint pool2[]; };
layout(std430, set = 0, binding = SVO_OCTREE_BINDING + 6) readonly restrict buffer Pool3 { uint pool3[]; };
layout(std430, set = 0, binding = SVO_OCTREE_BINDING + 7) readonly restrict buffer Pool4 { uint pool4[]; };
layout(std430, set = 0, binding = SVO_OCTREE_BINDING + 8) readonly restrict buffer Pool5 { uint pool5[]; };
layout(std430, set = 0, binding = SVO_OCTREE_BINDING + 9) readonly restrict buffer Pool6 { uint pool6[]; };
layout(std430, set = 0, binding = SVO_OCTREE_BINDING + 10) readonly restrict buffer Pool7 { uint pool7[]; };
#endif

uvec2 svo_node(uint index) { return nodes[index]; }

uvec4 svo_mask(uint cell) { return masks[cell]; }

uint svo_pool_word(uint slot, uint i) {
#if defined(SVO_POOL_SINGLE)
  return pool.words[i];
#elif defined(SVO_POOL_ADDRESS)
  return SvoWords(pool_address[slot]).w[i];
#else
  switch (slot) {
    case 0u: return pool0[i];
    case 1u: return pool1[i];
    case 2u: return pool2[i];
    case 3u: return pool3[i];
    case 4u: return pool4[i];
    case 5u: return pool5[i];
    case 6u: return pool6[i];
    default: return pool7[i];
  }
#endif
}

uint svo_brick_bytes(uint brick, uint offset) {
  uint slot = brick / params.pool.y;
  uint at = (brick - slot * params.pool.y) * params.pool.x + offset;
  return svo_pool_word(slot, at >> 2u) >> ((at & 3u) * 8u);
}

#endif

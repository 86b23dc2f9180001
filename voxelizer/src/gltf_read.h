// glTF 2.0 (.gltf, .glb) to mesh arrays through tinygltf (gltf_read.cpp),
// for read_mesh. The file, its buffers and images are untrusted.
#pragma once

#include <cstdint>
#include <string>

#include "svo/voxelizer/mesh.h"

namespace svo::voxelizer::gltf {

// Largest .gltf or .glb file, and all of its external buffers and images
// together: tinygltf takes 32-bit lengths.
inline constexpr uint64_t kMaxGltfBytes = 1ull << 30;
// Deepest JSON nesting (tinygltf's JSON parser recurses) and node hierarchy
// (a cycle of nodes is refused as too deep), and most node visits (a
// hierarchy that instances a node exponentially often).
inline constexpr int kMaxJsonDepth = 64;
inline constexpr int kMaxNodeDepth = 64;
inline constexpr uint64_t kMaxNodeVisits = 1u << 20;

// Whether `path` names glTF (".gltf" or ".glb", any case).
bool is_gltf_path(const std::string& path);

// Reads the default scene (else the first; without scenes, every root node)
// of a glTF 2.0 file: triangles, triangle strips and fans of every mesh
// instance, placed by its nodes' transforms (matrix or TRS; a mirroring
// transform flips the winding); per-vertex colour = the material's
// baseColorFactor times COLOR_0 (options.colour or 0.8 grey without a
// material); a baseColorTexture (PNG or JPEG, read by read_texture with the
// texture budgets of `options`, decoded from sRGB) through TEXCOORD_0,
// multiplied by baseColorFactor. Points and lines are skipped with a warning.
// Every accessor, buffer view and buffer range is checked before a byte of
// it is read.
// @throw std::runtime_error "<path>: <problem>" (one line): not a regular
//        file or above kMaxGltfBytes; a malformed GLB container or JSON;
//        nesting deeper than kMaxJsonDepth; a required extension (Draco,
//        KHR_texture_transform, ...; KHR_mesh_quantization is read); sparse
//        accessors; a baseColorTexture on TEXCOORD_1 or above; an accessor,
//        view, buffer, node, mesh, material, texture or image index out of
//        range; an accessor range beyond its view or buffer; an index naming
//        no vertex; more than kMaxMeshTriangles triangles or vertices; an
//        external buffer or image that is not a regular file.
MeshArrays read_gltf(const std::string& path, const MeshOptions& options);

}  // namespace svo::voxelizer::gltf

namespace svo::voxelizer {
// Pixels of a texture image from its header, checked as read_texture checks
// it (mesh_read.cpp). @throw what read_texture throws.
double texture_header_pixels(const std::string& file, const std::string& mesh_path, double max_pixels);
}  // namespace svo::voxelizer

// Pre-checks of untrusted image files, in front of the image libraries
// (OpenImageIO and the format libraries under it), for the two readers of
// images: mesh textures (voxelizer) and `svo compare`'s inputs (render).
// Here because svo_octree is the one library both link; no OpenImageIO here.
#pragma once

#include <cstdint>
#include <string>

namespace svo::octree {

// OpenEXR allocates tables from the header's data window before it reads a
// pixel: a 500-byte file claiming 2^28 lines took 1.9 GiB in OpenEXR 3.1.5
// (found by the texture fuzz target). For a file that starts with the
// OpenEXR magic number, reads every part's header and checks that each has
// a data window of at most `max_pixels` pixels.
// Returns "" when the file is not OpenEXR or passes, else the problem
// ("OpenEXR data window of 1x268435456 pixels, more than the limit of ...",
// "OpenEXR image of 40 channels, ...", "OpenEXR header truncated or malformed").
// Each side is at most kMaxExrEdge pixels and the image has at most
// kMaxExrChannels channels: OpenEXR allocates a block of up to 256 lines of
// every channel before it reads one (a 432-byte file 4194308 pixels wide
// took 1.1 GiB and 5 s).
std::string check_exr_header(const std::string& path, double max_pixels);
inline constexpr int64_t kMaxExrEdge = 16384;
inline constexpr int kMaxExrChannels = 32;

// OpenImageIO 2.4's PNG reader leaks its error text when libpng's read
// callback meets the end of the file (libpng longjmps over it; found by the
// texture fuzz target). For a file that starts with the PNG signature,
// checks that its chunks lie within the file up to an IEND chunk, so that
// libpng never reads past the end. Returns "" when the file is not PNG or
// passes, else the problem ("PNG truncated ...").
std::string check_png_chunks(const std::string& path);

}  // namespace svo::octree

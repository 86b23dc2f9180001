// Checks of a command's outputs made before any work: the file name's
// extension says what is written there, and no two outputs of one command
// name the same file (the second would replace the first).
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace svo::tools {

// Refuses `path` unless its extension (case-insensitive) is one of
// `extensions` (".svo"), so that `voxelize -o pic.png` cannot replace a
// picture with an octree.
// @throw std::invalid_argument "<option> <path>: expected a .svo file name (<what>)".
void require_extension(const std::string& option, const std::string& path, const std::vector<std::string>& extensions,
                       const std::string& what);

// Refuses two of `outputs` ((option, path) pairs; empty paths skipped) that
// name one file: the same path once made absolute and normal, or two names
// of one existing file (a link, a hard link).
// @throw std::invalid_argument "<option A> and <option B> both name <path>: give each output its own file".
void check_distinct_outputs(const std::vector<std::pair<std::string, std::string>>& outputs);

}  // namespace svo::tools

#include "output_checks.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <stdexcept>

namespace svo::tools {

namespace fs = std::filesystem;

void require_extension(const std::string& option, const std::string& path, const std::vector<std::string>& extensions,
                       const std::string& what) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (std::find(extensions.begin(), extensions.end(), ext) != extensions.end()) return;
  std::string names;
  for (const auto& e : extensions) names += (names.empty() ? "" : " or ") + e;
  throw std::invalid_argument(option + " " + path + ": expected a " + names + " file name (" + what + ")");
}

namespace {

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::absolute(a, ec).lexically_normal() == fs::absolute(b, ec).lexically_normal()) return true;
  return fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec) && !ec;
}

}  // namespace

void check_distinct_outputs(const std::vector<std::pair<std::string, std::string>>& outputs) {
  for (size_t i = 0; i < outputs.size(); ++i) {
    for (size_t j = i + 1; j < outputs.size(); ++j) {
      const auto& [option_a, a] = outputs[i];
      const auto& [option_b, b] = outputs[j];
      if (a.empty() || b.empty() || !same_file(a, b)) continue;
      throw std::invalid_argument(option_a + " and " + option_b + " both name " + b +
                                  ": give each output its own file");
    }
  }
}

}  // namespace svo::tools

// Host memory for the commands' limits (--max-memory of voxelize and render).
#pragma once

#include <fstream>
#include <string>

namespace svo::tools {

// MemAvailable from /proc/meminfo, in MiB (0 if unknown).
inline double available_memory_mb() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key, unit;
  double kb = 0;
  while (meminfo >> key >> kb >> unit) {
    if (key == "MemAvailable:") return kb / 1024.0;
  }
  return 0;
}

}  // namespace svo::tools

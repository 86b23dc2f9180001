// Reliability round two (issue 22): limits cases through the svo executable.
#include <gtest/gtest.h>

#include "reliability/run_svo.h"
#include "render/temp_dir.h"

namespace {

namespace fs = std::filesystem;
using svo::testing::run_svo;

}  // namespace

// svo_image_check IMAGE WIDTH HEIGHT: exit 0 when IMAGE has that size and
// holds a picture: at least 5% of the pixels differ from the top-left
// (background) pixel by more than 0.02 in some channel. Prints what it found.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "svo/render/image_io.h"

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: svo_image_check IMAGE WIDTH HEIGHT\n");
    return 2;
  }
  try {
    svo::render::Image image = svo::render::read_image(argv[1]);
    int width = std::atoi(argv[2]), height = std::atoi(argv[3]);
    if (image.width != width || image.height != height) {
      std::printf("%s: %d x %d pixels, expected %d x %d\n", argv[1], image.width, image.height, width, height);
      return 1;
    }
    int channels = std::min<int>(3, int(image.channels.size()));
    long differing = 0;
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        bool differs = false;
        for (int c = 0; c < channels; ++c) differs |= std::abs(image.at(x, y, c) - image.at(0, 0, c)) > 0.02f;
        differing += differs;
      }
    }
    double fraction = double(differing) / (double(width) * height);
    std::printf("%s: %d x %d, %.1f%% of the pixels differ from the background\n", argv[1], width, height,
                100 * fraction);
    return fraction >= 0.05 ? 0 : 1;
  } catch (const std::exception& e) {
    std::printf("%s\n", e.what());
    return 1;
  }
}

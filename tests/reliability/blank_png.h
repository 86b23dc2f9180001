// A PNG that is small on disk and huge when decoded: width x height black
// RGB pixels, deflated row by row without ever holding the image (zlib), for
// the tests of image budgets (a forged-looking but valid file).
#pragma once

#include <zlib.h>

#include <cstdint>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace svo::testing {

inline void write_blank_png(const std::string& path, uint32_t width, uint32_t height) {
  std::ofstream out(path, std::ios::binary);
  auto be32 = [](std::vector<uint8_t>& v, uint32_t x) {
    for (int s = 24; s >= 0; s -= 8) v.push_back(uint8_t(x >> s));
  };
  auto chunk = [&](const char* type, const std::vector<uint8_t>& data) {
    std::vector<uint8_t> head;
    be32(head, uint32_t(data.size()));
    out.write(reinterpret_cast<const char*>(head.data()), 4);
    std::vector<uint8_t> body(type, type + 4);
    body.insert(body.end(), data.begin(), data.end());
    out.write(reinterpret_cast<const char*>(body.data()), std::streamsize(body.size()));
    std::vector<uint8_t> crc;
    be32(crc, uint32_t(::crc32(0, body.data(), uInt(body.size()))));
    out.write(reinterpret_cast<const char*>(crc.data()), 4);
  };
  out.write("\x89PNG\r\n\x1a\n", 8);
  std::vector<uint8_t> ihdr;
  be32(ihdr, width);
  be32(ihdr, height);
  ihdr.insert(ihdr.end(), {8, 2, 0, 0, 0});  // 8-bit RGB, deflate, no filter, no interlace
  chunk("IHDR", ihdr);
  z_stream z{};
  if (deflateInit(&z, 9) != Z_OK) throw std::runtime_error("deflateInit failed");
  const std::vector<uint8_t> row(size_t(width) * 3 + 1, 0);  // filter byte 0, then black
  std::vector<uint8_t> idat, buffer(1 << 16);
  for (uint32_t y = 0; y < height; ++y) {
    z.next_in = const_cast<Bytef*>(row.data());
    z.avail_in = uInt(row.size());
    const int flush = y + 1 == height ? Z_FINISH : Z_NO_FLUSH;
    do {
      z.next_out = buffer.data();
      z.avail_out = uInt(buffer.size());
      deflate(&z, flush);
      idat.insert(idat.end(), buffer.data(), buffer.data() + (buffer.size() - z.avail_out));
    } while (z.avail_out == 0 || (flush == Z_FINISH && z.avail_in > 0));
  }
  deflateEnd(&z);
  chunk("IDAT", idat);
  chunk("IEND", {});
  if (!out.flush()) throw std::runtime_error("cannot write " + path);
}

}  // namespace svo::testing

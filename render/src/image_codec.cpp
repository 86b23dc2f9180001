// PNG, JPEG and OpenEXR writers on the format libraries themselves (see
// image_codec.h). libpng and libjpeg report errors by longjmp: the two
// encoders keep no C++ object with a destructor between setjmp and the
// calls that may jump, and write into a vector through a callback that
// never throws.
#include "image_codec.h"

// clang-format off
#include <cstdio>  // before jpeglib.h, which uses FILE
#include <jpeglib.h>
// clang-format on
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <png.h>

#include <csetjmp>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <thread>

namespace svo::render::codec {

namespace {

// A byte sink for the C libraries: appends, and remembers a failed
// allocation instead of throwing through C frames.
struct Sink {
  std::vector<uint8_t>* out;
  bool failed;
};

void append(Sink& sink, const void* data, size_t size) {
  if (sink.failed) return;
  try {
    const auto* bytes = static_cast<const uint8_t*>(data);
    sink.out->insert(sink.out->end(), bytes, bytes + size);
  } catch (...) {
    sink.failed = true;
  }
}

// libpng's error and warning handlers: the message into the error buffer, then back to setjmp.
struct PngState {
  Sink sink;
  char error[200];
};

void png_on_error(png_structp png, png_const_charp message) {
  auto* state = static_cast<PngState*>(png_get_error_ptr(png));
  std::snprintf(state->error, sizeof state->error, "%s", message);
  png_longjmp(png, 1);
}
void png_on_warning(png_structp, png_const_charp) {}
void png_on_write(png_structp png, png_bytep data, size_t size) {
  append(static_cast<PngState*>(png_get_io_ptr(png))->sink, data, size);
}
void png_on_flush(png_structp) {}

struct JpegError {
  jpeg_error_mgr manager;  // first: libjpeg casts the pointer back
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

void jpeg_on_error(j_common_ptr info) {
  auto* error = reinterpret_cast<JpegError*>(info->err);
  (*info->err->format_message)(info, error->message);
  std::longjmp(error->jump, 1);
}

}  // namespace

std::string encode_png(uint32_t width, uint32_t height, const uint8_t* rgb, const std::string& description,
                       std::vector<uint8_t>& out) {
  PngState state{{&out, false}, ""};
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &state, png_on_error, png_on_warning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    return "libpng: out of memory";
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return std::string("libpng: ") + state.error;
  }
  png_set_write_fn(png, &state, png_on_write, png_on_flush);
  png_set_IHDR(png, info, width, height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_text text[2] = {};
  text[0].compression = text[1].compression = PNG_TEXT_COMPRESSION_NONE;
  text[0].key = const_cast<char*>("Software");
  text[0].text = const_cast<char*>("svo");
  text[1].key = const_cast<char*>("Description");
  text[1].text = const_cast<char*>(description.c_str());
  png_set_text(png, info, text, description.empty() ? 1 : 2);
  png_write_info(png, info);
  for (uint32_t y = 0; y < height; ++y) png_write_row(png, rgb + size_t(y) * width * 3);
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return state.sink.failed ? "out of memory" : "";
}

std::string encode_jpeg(uint32_t width, uint32_t height, const uint8_t* rgb, const std::string& description,
                        int quality, std::vector<uint8_t>& out) {
  jpeg_compress_struct info{};
  JpegError error{};
  unsigned char* memory = nullptr;
  unsigned long size = 0;
  info.err = jpeg_std_error(&error.manager);
  error.manager.error_exit = jpeg_on_error;
  if (setjmp(error.jump)) {
    jpeg_destroy_compress(&info);
    std::free(memory);
    return std::string("libjpeg: ") + error.message;
  }
  jpeg_create_compress(&info);
  jpeg_mem_dest(&info, &memory, &size);
  info.image_width = width;
  info.image_height = height;
  info.input_components = 3;
  info.in_color_space = JCS_RGB;
  jpeg_set_defaults(&info);
  jpeg_set_quality(&info, quality, TRUE);
  for (int c = 0; c < 3; ++c) info.comp_info[c].h_samp_factor = info.comp_info[c].v_samp_factor = 1;  // 4:4:4
  jpeg_start_compress(&info, TRUE);
  if (!description.empty()) {
    jpeg_write_marker(&info, JPEG_COM, reinterpret_cast<const JOCTET*>(description.data()),
                      unsigned(description.size()));
  }
  while (info.next_scanline < info.image_height) {
    JSAMPROW row = const_cast<JSAMPROW>(rgb + size_t(info.next_scanline) * width * 3);
    jpeg_write_scanlines(&info, &row, 1);
  }
  jpeg_finish_compress(&info);
  jpeg_destroy_compress(&info);
  Sink sink{&out, false};
  append(sink, memory, size);
  std::free(memory);
  return sink.failed ? "out of memory" : "";
}

namespace {

// OpenEXR writes through this into the OutputFile. The library's
// OutputFile swallows errors in its destructor (where it writes the line
// offset table), so the first failure is also kept here.
class ExrStream final : public Imf::OStream {
 public:
  ExrStream(files::OutputFile& file) : Imf::OStream(file.temporary().c_str()), file_(file) {}
  void write(const char c[], int n) override {
    if (!failure.empty()) throw files::FileError(failure);
    try {
      file_.write_at(c, size_t(n), position_);
    } catch (const files::FileError& e) {
      failure = e.what();
      throw;
    }
    position_ += uint64_t(n);
  }
  uint64_t tellp() override { return position_; }
  void seekp(uint64_t position) override { position_ = position; }
  std::string failure;

 private:
  files::OutputFile& file_;
  uint64_t position_ = 0;
};

}  // namespace

void write_exr(files::OutputFile& file, const std::string& path, uint32_t width, uint32_t height,
               const std::vector<std::string>& channels, const float* data) {
  ExrStream stream(file);
  try {
    Imf::Header header{int(width), int(height)};
    header.compression() = Imf::ZIP_COMPRESSION;
    for (const std::string& name : channels) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    header.insert("Software", Imf::StringAttribute("svo"));
    const size_t n = channels.size();
    Imf::FrameBuffer frame;
    for (size_t c = 0; c < n; ++c) {
      frame.insert(channels[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(data + c)),
                                           sizeof(float) * n, sizeof(float) * n * width));
    }
    Imf::OutputFile exr(stream, header, int(std::thread::hardware_concurrency()));
    exr.setFrameBuffer(frame);
    exr.writePixels(int(height));
  } catch (const std::exception& e) {
    throw ImageError(stream.failure.empty() ? path + ": cannot write: " + one_line(e.what()) : stream.failure);
  }
  if (!stream.failure.empty()) throw ImageError(stream.failure);
}

}  // namespace svo::render::codec

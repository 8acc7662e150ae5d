#include "studies/png_image.hpp"

#include <zlib.h>

#include <stdexcept>

#include "dem/atomic_file.hpp"

namespace grainscale::studies {

Image::Image(int width, int height, Rgb background)
    : w_(width), h_(height), pixels_(static_cast<std::size_t>(width) * height, background) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("Image: width and height must be positive");
}

void Image::paste(const Image& other, int x0, int y0) {
  for (int y = 0; y < other.h_; ++y)
    for (int x = 0; x < other.w_; ++x) {
      if (x0 + x >= 0 && x0 + x < w_ && y0 + y >= 0 && y0 + y < h_) at(x0 + x, y0 + y) = other.at(x, y);
    }
}

namespace {

void put_u32(std::string& out, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<char>((v >> s) & 0xff));
}

/// One PNG chunk: length, type, data, CRC-32 of type + data (PNG spec, Sec. 5.3).
void chunk(std::string& out, const char* type, const std::string& data) {
  put_u32(out, static_cast<std::uint32_t>(data.size()));
  const std::string body = std::string(type, 4) + data;
  out += body;
  put_u32(out, static_cast<std::uint32_t>(crc32(0, reinterpret_cast<const Bytef*>(body.data()), body.size())));
}

}  // namespace

std::string Image::encode_png() const {
  // Raw scanlines, each prefixed with filter type 0 (None).
  std::string raw;
  raw.reserve(static_cast<std::size_t>(h_) * (1 + 3 * w_));
  for (int y = 0; y < h_; ++y) {
    raw.push_back('\0');
    for (int x = 0; x < w_; ++x) {
      const Rgb& p = at(x, y);
      raw.push_back(static_cast<char>(p.r));
      raw.push_back(static_cast<char>(p.g));
      raw.push_back(static_cast<char>(p.b));
    }
  }
  uLongf size = compressBound(raw.size());
  std::string z(size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(z.data()), &size, reinterpret_cast<const Bytef*>(raw.data()), raw.size(), 6) != Z_OK) {
    throw std::runtime_error("PNG encoding: zlib compression failed");
  }
  z.resize(size);

  std::string png("\x89PNG\r\n\x1a\n", 8);
  std::string ihdr;
  put_u32(ihdr, static_cast<std::uint32_t>(w_));
  put_u32(ihdr, static_cast<std::uint32_t>(h_));
  ihdr += std::string("\x08\x02\x00\x00\x00", 5);  // 8 bits, truecolour, deflate, filter 0, no interlace
  chunk(png, "IHDR", ihdr);
  chunk(png, "IDAT", z);
  chunk(png, "IEND", "");
  return png;
}

void Image::write_png(const std::string& path) const { dem::write_file_atomically(path, encode_png()); }

}  // namespace grainscale::studies

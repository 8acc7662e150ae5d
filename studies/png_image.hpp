#pragma once
// An RGB raster and its PNG encoding (8-bit truecolour, zlib-compressed, no other dependency than
// zlib, which HDF5 already needs). Studies write their figures through this.
#include <cstdint>
#include <string>
#include <vector>

namespace grainscale::studies {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
};

class Image {
 public:
  Image(int width, int height, Rgb background = {255, 255, 255});
  int width() const { return w_; }
  int height() const { return h_; }
  Rgb& at(int x, int y) { return pixels_[static_cast<std::size_t>(y) * w_ + x]; }
  const Rgb& at(int x, int y) const { return pixels_[static_cast<std::size_t>(y) * w_ + x]; }
  /// Copy `other` into this image with its top-left corner at (x0, y0).
  void paste(const Image& other, int x0, int y0);

  /// PNG file contents.
  std::string encode_png() const;
  /// Write atomically (tmp + rename); throws std::runtime_error naming the path on failure.
  void write_png(const std::string& path) const;

 private:
  int w_, h_;
  std::vector<Rgb> pixels_;
};

}  // namespace grainscale::studies

// PNG output: the file is a valid PNG (signature, chunk CRCs) whose pixels decode back exactly.
#include <zlib.h>

#include <catch2/catch.hpp>
#include <cstdint>
#include <string>

#include "studies/png_image.hpp"

using namespace grainscale::studies;

namespace {
std::uint32_t u32(const std::string& s, std::size_t at) {
  return (std::uint32_t(std::uint8_t(s[at])) << 24) | (std::uint32_t(std::uint8_t(s[at + 1])) << 16) |
         (std::uint32_t(std::uint8_t(s[at + 2])) << 8) | std::uint32_t(std::uint8_t(s[at + 3]));
}
}  // namespace

TEST_CASE("A PNG round-trips its pixels through zlib and carries valid chunk CRCs", "[studies][png]") {
  Image img(7, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 7; ++x) img.at(x, y) = {std::uint8_t(30 * x), std::uint8_t(80 * y), std::uint8_t(x + y)};
  const std::string png = img.encode_png();
  REQUIRE(png.substr(0, 8) == std::string("\x89PNG\r\n\x1a\n", 8));

  std::string idat;
  std::size_t at = 8;
  int chunks = 0;
  while (at < png.size()) {
    const std::uint32_t len = u32(png, at);
    const std::string type = png.substr(at + 4, 4);
    const std::string body = png.substr(at + 4, 4 + len);
    CHECK(u32(png, at + 8 + len) == crc32(0, reinterpret_cast<const Bytef*>(body.data()), body.size()));
    if (type == "IHDR") {
      CHECK(u32(png, at + 8) == 7);
      CHECK(u32(png, at + 12) == 3);
    }
    if (type == "IDAT") idat += png.substr(at + 8, len);
    at += 12 + len;
    ++chunks;
  }
  CHECK(chunks == 3);
  std::string raw(3 * (1 + 3 * 7), '\0');
  uLongf size = raw.size();
  REQUIRE(uncompress(reinterpret_cast<Bytef*>(raw.data()), &size, reinterpret_cast<const Bytef*>(idat.data()), idat.size()) == Z_OK);
  REQUIRE(size == raw.size());
  for (int y = 0; y < 3; ++y) {
    CHECK(raw[y * 22] == 0);  // filter type None
    for (int x = 0; x < 7; ++x) {
      CHECK(std::uint8_t(raw[y * 22 + 1 + 3 * x]) == img.at(x, y).r);
      CHECK(std::uint8_t(raw[y * 22 + 2 + 3 * x]) == img.at(x, y).g);
      CHECK(std::uint8_t(raw[y * 22 + 3 + 3 * x]) == img.at(x, y).b);
    }
  }
}

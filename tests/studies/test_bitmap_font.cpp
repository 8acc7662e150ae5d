// The built-in font: every printable ASCII character has its own glyph, and text stays inside the
// box text_size() promises, in both directions and at any scale.
#include <catch2/catch.hpp>

#include <set>
#include <string>

#include "studies/bitmap_font.hpp"

using namespace grainscale::studies;

namespace {

struct Ink {
  int left = 1 << 30, top = 1 << 30, right = -1, bottom = -1, count = 0;
};

Ink ink_of(const Image& img, Rgb background) {
  Ink k;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) {
      const Rgb p = img.at(x, y);
      if (p.r == background.r && p.g == background.g && p.b == background.b) continue;
      k.left = std::min(k.left, x);
      k.right = std::max(k.right, x);
      k.top = std::min(k.top, y);
      k.bottom = std::max(k.bottom, y);
      ++k.count;
    }
  return k;
}

}  // namespace

TEST_CASE("Every printable ASCII character has a distinct glyph", "[studies][plot][font]") {
  std::set<Glyph> seen;
  for (char32_t c = 32; c <= 126; ++c) {
    INFO("character " << static_cast<int>(c));
    CHECK(has_glyph(c));
    for (std::uint8_t row : glyph(c)) CHECK(row < (1u << kGlyphWidth));
    CHECK(seen.insert(glyph(c)).second);
  }
  CHECK(!has_glyph(U'\u20ac'));  // euro: drawn as the box
  CHECK(glyph(U'\u20ac') == glyph(0x7f));
  CHECK(has_glyph(U'\u00b2'));
}

TEST_CASE("Text renders inside its box, horizontal and rotated", "[studies][plot][font]") {
  const Rgb white{255, 255, 255}, ink{10, 20, 30};
  for (int scale : {1, 2, 3}) {
    for (TextDirection dir : {TextDirection::horizontal, TextDirection::up}) {
      const std::string text = "Hg(x) = 0.25 m^2/s, chi2 ~ 1 | σ²";
      Image img(700, 700, white);
      const TextSize box = text_size(text, scale, dir);
      draw_text(img, 13, 9, text, ink, scale, dir);
      const Ink k = ink_of(img, white);
      INFO("scale " << scale << (dir == TextDirection::up ? " up" : " horizontal"));
      REQUIRE(k.count > 0);
      CHECK(k.left >= 13);
      CHECK(k.top >= 9);
      CHECK(k.right < 13 + box.width);
      CHECK(k.bottom < 9 + box.height);
      // The box is tight: the first glyph ('H') and the last ('²') reach its edges.
      if (dir == TextDirection::horizontal) {
        CHECK(k.left == 13);
        CHECK(k.top == 9);
      } else {
        CHECK(k.bottom == 9 + box.height - 1);  // the text starts at the bottom
        CHECK(k.left == 13);
      }
    }
  }
  // 33 code points (σ and ² are two bytes each): 33 * 6 - 1 pixels wide at scale 1.
  CHECK(text_size("Hg(x) = 0.25 m^2/s, chi2 ~ 1 | σ²").width == 33 * kGlyphAdvance - 1);
  CHECK(text_size("").width == 0);
}

TEST_CASE("Text is clipped at the image edge and malformed UTF-8 draws boxes", "[studies][plot][font]") {
  Image img(20, 10);
  REQUIRE_NOTHROW(draw_text(img, -7, -3, "clipped text", {0, 0, 0}, 2));
  REQUIRE_NOTHROW(draw_text(img, 15, 5, std::string("\xff\xc3", 2), {0, 0, 0}, 1));
  CHECK(text_size(std::string("\xff\xc3", 2)).width == 2 * kGlyphAdvance - 1);
}

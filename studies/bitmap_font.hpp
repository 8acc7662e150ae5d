#pragma once
// A built-in 5 x 7 pixel font, so figures carry their own text without a font file or library.
// Covers ASCII 32-126 and a few symbols the labels need (² ° ± γ κ μ σ χ); any other character is
// drawn as a hollow box, so missing glyphs show instead of silently vanishing. Text is one line,
// UTF-8, scaled by whole pixels (no smoothing: the same text gives the same pixels).
#include <array>
#include <cstdint>
#include <string_view>

#include "studies/png_image.hpp"

namespace grainscale::studies {

constexpr int kGlyphWidth = 5, kGlyphHeight = 7;
/// Horizontal advance per character (glyph + 1 px gap), in unscaled pixels.
constexpr int kGlyphAdvance = kGlyphWidth + 1;

/// Rows top to bottom; bit 4 is the leftmost column.
using Glyph = std::array<std::uint8_t, kGlyphHeight>;

/// The glyph of a Unicode code point (the hollow box if there is none).
const Glyph& glyph(char32_t code_point);
/// Whether `code_point` has a glyph of its own.
bool has_glyph(char32_t code_point);

enum class TextDirection {
  horizontal,
  up,  // rotated 90 degrees counter-clockwise: reads bottom to top (y-axis labels)
};

struct TextSize {
  int width = 0, height = 0;  // of the box the text's pixels lie in, as drawn
};

/// Size of the drawn box at `scale` in `direction` (an empty text has width 0).
TextSize text_size(std::string_view utf8, int scale = 1, TextDirection direction = TextDirection::horizontal);

/// Draw `utf8` with its box's top-left corner at (x, y); pixels outside the image are clipped.
void draw_text(Image& image, int x, int y, std::string_view utf8, Rgb colour, int scale = 1,
               TextDirection direction = TextDirection::horizontal);

}  // namespace grainscale::studies

#pragma once
/// \file A 5 x 7 pixel font for the labels of plots: digits, lower-case letters (upper case drawn
/// as lower case) and the punctuation of numbers and structure specs. Our own glyphs.

#include <string_view>

namespace vf::render_detail {

/// Glyph width and height in font pixels; characters advance by kGlyphWidth + 1.
inline constexpr int kGlyphWidth = 5, kGlyphHeight = 7;

/// The 35 cells of `c`'s glyph, row by row, '#' for ink ("?" box for characters it lacks).
std::string_view glyph(char c);

}  // namespace vf::render_detail

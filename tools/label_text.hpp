// Text in the tools' PNG figures: the labels of colour bars and panels, drawn with a fixed 5x7
// pixel font (upper case, digits, a few signs) so that a figure says what it shows without a
// font library. Lower case is drawn as upper case; a character the font lacks as a blank.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace msmcl::tools {

constexpr int kGlyphHeight = 7;  ///< rows of a character
constexpr int kGlyphAdvance = 6; ///< columns from one character to the next (5 + 1 blank)

/// Columns the text takes (the last character's blank column not counted).
int text_width(const std::string& text);

/// Draws `text` with its top-left corner at (x, y) into an image of `channels` (1 or 3) floats
/// per pixel, row by row; a 1-channel image takes colour[0]. Pixels outside are skipped.
void draw_text(std::vector<float>& image, int width, int height, int channels, int x, int y, const std::string& text,
               const std::array<float, 3>& colour);

} // namespace msmcl::tools

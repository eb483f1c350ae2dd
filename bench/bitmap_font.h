// Labels on the pictures the tool writes: a 5x7 pixel font (upper case, digits, a little
// punctuation), drawn into 8-bit RGB pixels.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

namespace probefilter {

// Draws `text` (lower case is drawn as upper case; characters the font lacks as blanks) with its
// top-left corner at (x, y), each font pixel `scale` x `scale` image pixels, clipped to the image.
void drawText(std::vector<std::uint8_t>& rgb, int width, int height, int x, int y, std::string_view text, int scale,
              std::array<std::uint8_t, 3> colour);

// Width in image pixels of `text` drawn at `scale`.
int textWidth(std::string_view text, int scale);

} // namespace probefilter

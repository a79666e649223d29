// A tiny built-in 3x5 pixel font for the viewer's stats line, so the viewer needs no font
// library or file. Upper-case letters, digits and a few signs; lower case draws as upper case,
// anything else as a space.
#pragma once

#include <cstdint>
#include <string>

#include "encode/image.h"

namespace ddgi::client {

// Draws `text` with its top-left corner at (x, y), each font pixel `scale` x `scale` image
// pixels, white on a dark band; clipped to the image.
void draw_text(encode::ImageRgba8& image, int x, int y, const std::string& text, int scale);

// Width in pixels of `text` drawn at `scale`.
int text_width(const std::string& text, int scale);

}  // namespace ddgi::client

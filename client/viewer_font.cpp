#include "viewer_font.h"

#include <cctype>

namespace ddgi::client {
namespace {

constexpr int kGlyphWidth = 3, kGlyphHeight = 5, kAdvance = 4;

// Rows top to bottom; each row's three bits left to right.
const char* glyph(char c) {
  switch (std::toupper(static_cast<unsigned char>(c))) {
    case '0':
      return "111101101101111";
    case '1':
      return "010110010010111";
    case '2':
      return "111001111100111";
    case '3':
      return "111001111001111";
    case '4':
      return "101101111001001";
    case '5':
      return "111100111001111";
    case '6':
      return "111100111101111";
    case '7':
      return "111001001001001";
    case '8':
      return "111101111101111";
    case '9':
      return "111101111001111";
    case '.':
      return "000000000000010";
    case ',':
      return "000000000010100";
    case ':':
      return "000010000010000";
    case '/':
      return "001001010100100";
    case '-':
      return "000000111000000";
    case '#':
      return "101111101111101";
    case '=':
      return "000111000111000";
    case 'A':
      return "010101111101101";
    case 'B':
      return "110101110101110";
    case 'C':
      return "011100100100011";
    case 'D':
      return "110101101101110";
    case 'E':
      return "111100110100111";
    case 'F':
      return "111100110100100";
    case 'G':
      return "011100101101011";
    case 'H':
      return "101101111101101";
    case 'I':
      return "111010010010111";
    case 'J':
      return "001001001101010";
    case 'K':
      return "101101110101101";
    case 'L':
      return "100100100100111";
    case 'M':
      return "101111111101101";
    case 'N':
      return "110101101101101";
    case 'O':
      return "010101101101010";
    case 'P':
      return "110101110100100";
    case 'Q':
      return "010101101110011";
    case 'R':
      return "110101110101101";
    case 'S':
      return "011100010001110";
    case 'T':
      return "111010010010010";
    case 'U':
      return "101101101101111";
    case 'V':
      return "101101101101010";
    case 'W':
      return "101101111111101";
    case 'X':
      return "101101010101101";
    case 'Y':
      return "101101010010010";
    case 'Z':
      return "111001010100111";
    default:
      return nullptr;
  }
}

void put(encode::ImageRgba8& image, int x, int y, uint8_t r, uint8_t g, uint8_t b) {
  if (x < 0 || y < 0 || x >= int(image.width) || y >= int(image.height)) return;
  uint8_t* p = &image.pixels[(size_t(y) * image.width + size_t(x)) * 4];
  p[0] = r;
  p[1] = g;
  p[2] = b;
  p[3] = 255;
}

}  // namespace

int text_width(const std::string& text, int scale) {
  return int(text.size()) * kAdvance * scale;
}

void draw_text(encode::ImageRgba8& image, int x, int y, const std::string& text, int scale) {
  // A dark band behind the text keeps it readable on any frame.
  const int band_height = (kGlyphHeight + 2) * scale;
  for (int by = y - scale; by < y - scale + band_height; ++by) {
    for (int bx = x - scale; bx < x + text_width(text, scale); ++bx) {
      if (bx < 0 || by < 0 || bx >= int(image.width) || by >= int(image.height)) continue;
      uint8_t* p = &image.pixels[(size_t(by) * image.width + size_t(bx)) * 4];
      for (int c = 0; c < 3; ++c) p[c] = static_cast<uint8_t>(p[c] / 4);
    }
  }
  for (size_t i = 0; i < text.size(); ++i) {
    const char* bits = glyph(text[i]);
    if (bits == nullptr) continue;
    for (int row = 0; row < kGlyphHeight; ++row) {
      for (int column = 0; column < kGlyphWidth; ++column) {
        if (bits[row * kGlyphWidth + column] != '1') continue;
        for (int sy = 0; sy < scale; ++sy) {
          for (int sx = 0; sx < scale; ++sx) {
            put(image, x + (int(i) * kAdvance + column) * scale + sx, y + row * scale + sy, 255,
                255, 255);
          }
        }
      }
    }
  }
}

}  // namespace ddgi::client

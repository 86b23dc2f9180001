// Labels drawn into frames: a built-in 5x7-pixel bitmap font, so that a
// picture that carries numbers (a diff's colour bar, a contact sheet's
// captions) needs no font file on the machine.
//
// Characters: digits, A-Z (a-z drawn as capitals), space and . , : ; - + = %
// / ( ) _ ' ? # < > *; any other character is drawn as '?'. Each character
// is 5 x 7 cells and advances 6 cells; a cell is `scale` x `scale` pixels.
#pragma once

#include <glm/vec3.hpp>
#include <string_view>

#include "svo/render/renderer.h"

namespace svo::render {

inline constexpr int kGlyphWidth = 5, kGlyphHeight = 7, kGlyphAdvance = 6;

// Width in pixels of `text` at `scale` (no trailing gap): 0 for "".
int text_width(std::string_view text, int scale = 1);

// Draws `text` into frame.colour with its top-left corner at pixel (x, y),
// in `colour` (linear RGB, alpha 1). Pixels outside the frame are skipped,
// so a label may run off an edge. scale < 1 draws nothing.
void draw_text(Frame& frame, int x, int y, std::string_view text, glm::vec3 colour, int scale = 1);

}  // namespace svo::render

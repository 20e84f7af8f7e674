// Where each thing drawn over a rendered frame goes, so none covers another:
//
//   +--------------------------------------------+
//   | overlay lines              colour bar panel |   top-left: scene, integrator, dt, t
//   | (top-left)                 title   [ ]  hi  |   right edge, from the top: the field's
//   |                                    [ ]      |   legend (below the overlay lines when
//   |                                    [ ]  lo  |   they are too wide to share the top)
//   |                                             |
//   |                              +-----------+  |
//   |                              | inset     |  |   bottom-right: the series inset
//   |                              +-----------+  |
//   | tile label (render/video/tiling: bottom-left, drawn later by the compositor)
//   +--------------------------------------------+
//
// The bottom band a tile label may cover is kept clear on the right too, so a long label
// never runs under the inset. The banner (DIVERGED ...) is centred and drawn over everything,
// on two lines in a tile too narrow for one.
// Pure arithmetic on the frame's content and the image size: tests check the boxes.
#pragma once

#include <vector>

#include "colormap.h"
#include "image.h"
#include "text.h"
#include "view/render_frame.h"

namespace clothsim::render {

// A rectangle of image pixels, top-down (row 0 at the top), half-open: [x, x+w) x [y, y+h).
struct ImageBox {
  int x = 0, y = 0, w = 0, h = 0;
  bool empty() const { return w <= 0 || h <= 0; }
  int right() const { return x + w; }
  int bottom() const { return y + h; }
  bool overlaps(const ImageBox& o) const {
    return !empty() && !o.empty() && x < o.right() && o.x < right() && y < o.bottom() && o.y < bottom();
  }
  bool contains(int px, int py) const { return px >= x && px < right() && py >= y && py < bottom(); }
};

struct OverlayLayout {
  int scale = 1;       // text scale: text_scale_for_height(image height)
  int margin = 4;      // pixels from the image edges: 4 x scale
  ImageBox text;       // the overlay lines with their backdrop (empty without lines)
  std::vector<std::string> lines;  // the overlay lines as drawn: wrapped at spaces to the image's
                                   // width (a DIVERGED reason is long for a small tile)

  ImageBox color_bar;  // the colour bar's panel (dark backdrop): title, tick labels, bar
  ImageBox bar;        // the gradient inside it, hi at the top row, lo at the bottom row
  int title_y = 0;     // top of the title's glyphs (the scale's label), right-aligned in the panel
  std::vector<ScaleTick> ticks;

  // The banner (DIVERGED, NOT CONVERGED): centred in the picture left of the colour bar's
  // panel, so it hides no tick, at the text scale (smaller only where not even its first two
  // phrases fit that width on two lines); across the picture where it does not fit there. Its
  // phrases on one line, else on two (each line centred in the box), the last phrases left
  // off where two lines cannot hold them or where only fewer clear the overlay lines.
  ImageBox banner;                        // the lines' glyphs (the backdrop reaches 2 scale past)
  int banner_scale = 1;
  std::vector<std::string> banner_lines;  // as drawn, top to bottom

  ImageBox inset;      // the series inset's panel (dark backdrop)
  int inset_scale = 1; // its text scale: the overlay's, smaller only for a label over a third of the width
  ImageBox plot;       // the graph area inside the inset
};

// Fills `box` (clipped to the image) with one colour.
void fill_box(Image& image, const ImageBox& box, Rgba8 color);

// Rows at the bottom of a tile that its label covers (render/video/tiling.h draw_tile_label,
// at text scale `scale`): kept clear of the inset.
int tile_label_band(int scale);

// Lays out what `frame` draws over an image of width x height: the colour bar when
// cloth_field is set and color_scale.show_bar, the inset when inset.show.
OverlayLayout layout_overlay(const RenderFrame& frame, int width, int height);

// The colour bar of a grid (compare's clip, still, sheet): one legend for every tile, in a strip
// of its own at the grid's right, so it covers no tile. The width such a strip needs at text
// scale `scale` for a scale titled `label` (ticks of up to six characters, "1.5e-5").
int color_bar_strip_width(std::string_view label, int scale);
// The colour bar's panel in `strip` (only color_bar, bar, title_y, ticks and scale are set):
// the panel as wide as the strip less its margins, vertically centred, its bar half the strip high.
OverlayLayout layout_color_bar_strip(const ColorScale& scale, const ImageBox& strip, int text_scale);

}  // namespace clothsim::render

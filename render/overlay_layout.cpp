#include "overlay_layout.h"

#include <algorithm>
#include <cmath>
#include <optional>


namespace clothsim::render {

namespace {

int line_height(int scale) { return text_glyph_height() * scale; }  // glyph cell: 7 cap + 3

// `text` broken at spaces into pieces no wider than `max_width` at `scale`, the first after
// `indent`, continuation lines indented; a single word wider than that stays whole (and is
// clipped at the image's edge).
void wrap_words(const std::string& text, int max_width, int scale, std::vector<std::string>& out,
                const std::string& indent = "") {
  std::string current = indent;
  bool first = true;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find(' ', start);
    if (end == std::string::npos) end = text.size();
    const std::string word = text.substr(start, end - start);
    const std::string joined = first ? current + word : current + " " + word;
    if (!first && text_width(joined, scale) > max_width) {
      out.push_back(current);
      current = "  " + word;  // continuation lines indented
    } else {
      current = joined;
    }
    first = false;
    start = end + 1;
  }
  out.push_back(current);
}

// `line` wrapped to `max_width`, breaking first where its parts are two spaces apart (a cost
// line's passes and CPU, a label's name and step) so no part is split while whole ones fit.
void wrap_into(const std::string& line, int max_width, int scale, std::vector<std::string>& out) {
  std::vector<std::string> parts;
  for (std::size_t start = 0;;) {
    const std::size_t end = line.find("  ", start);
    parts.push_back(line.substr(start, end == std::string::npos ? std::string::npos : end - start));
    if (end == std::string::npos) break;
    start = end + 2;
  }
  std::string current = parts.front(), indent;
  for (std::size_t i = 1; i < parts.size(); ++i) {
    const std::string joined = current + "  " + parts[i];
    if (text_width(indent + joined, scale) <= max_width) {
      current = joined;
      continue;
    }
    wrap_words(current, max_width, scale, out, indent);
    current = parts[i];
    indent = "  ";
  }
  wrap_words(current, max_width, scale, out, indent);
}

// The inset's panel, bottom-right above the tile label band: about a quarter of the width,
// wider if its label needs it at the overlay's text scale (one text size in a picture); the
// label's text steps down only where it would take more than a third of the width.
void place_inset(const RenderFrame& frame, int width, int height, OverlayLayout& l) {
  const int quarter = width / 4;
  int s = l.scale;
  while (s > 1 && text_width(frame.inset.label, s) + 4 * s > width / 3) --s;
  l.inset_scale = s;
  const int pad = 2 * s;
  const int w = std::min(std::max(quarter, text_width(frame.inset.label, s) + 2 * pad), width - 2 * l.margin);
  // The graph keeps room for its two value labels (top and bottom) and about 1:3 proportions.
  const int plot_h = std::max(2 * line_height(s) + 2 * s, static_cast<int>(std::lround(0.35 * w)));
  const int title_h = frame.inset.label.empty() ? 0 : line_height(s) + s;
  const int h = pad + title_h + plot_h + s + line_height(s) + pad;  // ... + time axis labels
  l.inset = {width - l.margin - w, height - tile_label_band(l.scale) - l.margin - h, w, h};
  l.plot = {l.inset.x + pad, l.inset.y + pad + title_h, w - 2 * pad, plot_h};
}

// The colour bar's panel parts for a bar of height bar_h whose panel's top-right corner is
// (right, top), its tick labels chosen for that height (a tick label per line and a gap).
void fit_bar_panel(const ColorScale& scale, int right, int top, int bar_h, OverlayLayout& l) {
  const int s = l.scale, pad = 2 * s;
  const int bar_w = 6 * s, tick_len = 2 * s, gap = s;
  const int half_label = 4 * s;  // a tick label centred on its tick reaches this far past it
  const int title_h = scale.label.empty() ? 0 : line_height(s) + s;
  l.ticks = scale_ticks(scale, std::max(2, bar_h / (line_height(s) + 2 * s) + 1));
  int label_w = 0;
  for (const ScaleTick& t : l.ticks) label_w = std::max(label_w, text_width(t.text, s));
  const int w = std::max(text_width(scale.label, s), label_w + gap + tick_len + bar_w) + 2 * pad;
  l.color_bar = {right - w, top, w, 2 * pad + title_h + 2 * half_label + bar_h};
  l.bar = {l.color_bar.right() - pad - bar_w, top + pad + title_h + half_label, bar_w, bar_h};
  l.title_y = top + pad;
}

// The colour bar's panel at the right edge, from the top (or below the overlay lines if they
// reach across), its bar about 40 % of the image high or what is left above the inset.
void place_color_bar(const RenderFrame& frame, int width, int height, OverlayLayout& l) {
  const int s = l.scale;
  const int title_h = frame.color_scale.label.empty() ? 0 : line_height(s) + s;
  const int overhead = 4 * s + title_h + 8 * s;  // pads, title, half a tick label each end
  int bottom_limit = l.inset.empty() ? height - tile_label_band(s) - l.margin : l.inset.y - l.margin;

  const auto fit = [&](int top) {
    const int bar_h = std::max(std::min(static_cast<int>(std::lround(0.4 * height)), bottom_limit - top - overhead),
                               line_height(s));
    fit_bar_panel(frame.color_scale, width - l.margin, top, bar_h, l);
  };
  fit(l.margin);
  if (l.color_bar.overlaps(l.text)) fit(l.text.bottom() + s);  // under long overlay lines
  // Squeezed between long overlay lines and the inset (a small tile), the bar would be a few
  // pixels with its tick labels on each other: it takes the height down to the label band,
  // and the inset moves left of it, where the inset then clears the text and the image's
  // left edge (else the layout stays as it was).
  const int min_bar = 3 * (line_height(s) + 2 * s);
  if (l.bar.h < min_bar && !l.inset.empty()) {
    const OverlayLayout before = l;
    bottom_limit = height - tile_label_band(s) - l.margin;
    fit(l.color_bar.y);
    const int dx = l.color_bar.x - l.margin - l.inset.right();
    l.inset.x += dx;
    l.plot.x += dx;
    if (l.inset.x < l.margin || l.inset.overlaps(l.text) || l.inset.overlaps(l.color_bar)) l = before;
  }
}


// `phrases[0, count)` joined by spaces into lines no wider than `room` at `scale`, a phrase
// starting a line where it does not fit after the last (one wider than `room` alone on its line).
std::vector<std::string> pack_phrases(const std::vector<std::string>& phrases, std::size_t count, int room, int scale) {
  std::vector<std::string> lines;
  for (std::size_t i = 0; i < count; ++i) {
    if (!lines.empty() && text_width(lines.back() + " " + phrases[i], scale) <= room)
      lines.back() += " " + phrases[i];
    else
      lines.push_back(phrases[i]);
  }
  return lines;
}

bool lines_fit(const std::vector<std::string>& lines, int room, int scale) {
  for (const std::string& line : lines)
    if (text_width(line, scale) > room) return false;
  return lines.size() <= 2;
}

struct BannerChoice {
  std::vector<std::string> lines;
  int scale = 1;
};

// Where a phrase is wider than `room` at `scale` (WRONG's reason), every phrase broken at
// spaces, if that takes at most three lines that fit.
std::optional<BannerChoice> phrases_broken_at_spaces(const std::vector<std::string>& phrases, int room, int scale) {
  const auto fits = [&](const std::string& line) { return text_width(line, scale) <= room; };
  if (std::all_of(phrases.begin(), phrases.end(), fits)) return std::nullopt;
  BannerChoice words{{}, scale};
  for (const std::string& phrase : phrases) wrap_words(phrase, room, scale, words.lines);
  for (std::string& line : words.lines) line.erase(0, line.find_first_not_of(' '));
  if (words.lines.size() > 3 || !std::all_of(words.lines.begin(), words.lines.end(), fits)) return std::nullopt;
  return words;
}

// Every way to write the banner in `room`, best first: at the text's own scale (one text size
// in a picture), its phrases on one line, else on two; then the same without the last phrase,
// and so on down to the first two (never fewer); then, where a phrase is too long for a line,
// every phrase broken at spaces on at most three lines; only then the same at smaller scales;
// last (a tile narrower than a phrase) the first two wrapped at spaces.
std::vector<BannerChoice> banner_choices(const std::vector<std::string>& phrases, int room, int text_scale) {
  std::vector<BannerChoice> out;
  const std::size_t kept = std::min<std::size_t>(2, phrases.size());
  for (int b = text_scale; b >= 1; --b) {
    for (std::size_t count = phrases.size(); count >= std::max<std::size_t>(kept, 1); --count) {
      std::string one_line;
      for (std::size_t i = 0; i < count; ++i) one_line += (i ? " " : "") + phrases[i];
      if (text_width(one_line, b) <= room) out.push_back({{one_line}, b});
      std::vector<std::string> lines = pack_phrases(phrases, count, room, b);
      if (lines.size() == 2 && lines_fit(lines, room, b)) out.push_back({lines, b});
    }
    if (const auto words = phrases_broken_at_spaces(phrases, room, b)) out.push_back(*words);
  }
  BannerChoice wrapped;
  for (std::size_t i = 0; i < kept; ++i) wrap_words(phrases[i], room, 1, wrapped.lines);
  for (std::string& line : wrapped.lines)  // (the phrase is what is read, not wrap_words' indent)
    line.erase(0, line.find_first_not_of(' '));
  out.push_back(wrapped);
  return out;
}

// The banner: left of the colour bar where it fits there on two lines at scale 1 or more; else
// across the picture, as a tile too narrow for both must show the banner over the bar rather
// than cut it. Centred, or below the overlay text where centring would cover it (a DIVERGED
// reason is several lines in a small tile), if there is room above the label band; where only
// a shorter banner has that room (the step left off), the shorter one, so that the text stays
// readable; where none has, the first choice over the text.
void place_banner(const RenderFrame& frame, int width, int height, OverlayLayout& l) {
  const int s = l.scale;
  const int right = l.color_bar.empty() ? width - l.margin : l.color_bar.x - l.margin;
  int room = std::max(right - l.margin, 1);
  if (!lines_fit(pack_phrases(frame.banner, frame.banner.size(), room, 1), room, 1)) room = std::max(width - 2 * l.margin, 1);
  const std::vector<BannerChoice> choices = banner_choices(frame.banner, room, s);
  // Where `c` goes, and whether it leaves the overlay text uncovered.
  const auto place = [&](const BannerChoice& c, bool& clear) {
    int w = 0;
    for (const std::string& line : c.lines) w = std::max(w, text_width(line, c.scale));
    const int h = static_cast<int>(c.lines.size()) * text_glyph_height() * c.scale;
    int y = (height - h) / 2;
    clear = l.text.empty() || y >= l.text.bottom() + s;
    if (!clear && l.text.bottom() + s + h <= height - tile_label_band(s)) {
      y = l.text.bottom() + s;
      clear = true;
    }
    return ImageBox{l.margin + std::max(0, (room - w) / 2), y, w, h};
  };
  const BannerChoice* chosen = &choices.front();
  for (const BannerChoice& c : choices) {
    bool clear = false;
    place(c, clear);
    if (clear) {
      chosen = &c;
      break;
    }
  }
  bool clear = false;
  l.banner = place(*chosen, clear);
  l.banner_lines = chosen->lines;
  l.banner_scale = chosen->scale;
}
}  // namespace

void fill_box(Image& image, const ImageBox& box, Rgba8 color) {
  for (int y = std::max(box.y, 0); y < std::min(box.bottom(), image.height); ++y)
    for (int x = std::max(box.x, 0); x < std::min(box.right(), image.width); ++x)
      std::copy(color.begin(), color.end(), image.pixel(x, y));
}

int tile_label_band(int scale) {
  // draw_tile_label: glyphs 3 s above the tile's bottom edge, backdrop 2 s around them.
  return 3 * scale + line_height(scale) + 2 * scale;
}

OverlayLayout layout_overlay(const RenderFrame& frame, int width, int height) {
  OverlayLayout l;
  l.scale = text_scale_for_height(height);
  l.margin = 4 * l.scale;
  const int s = l.scale;
  for (const std::string& line : frame.overlay_lines) wrap_into(line, width - 2 * l.margin, s, l.lines);
  if (!l.lines.empty()) {  // as draw_text_block draws them at (margin, margin)
    int w = 0;
    for (const std::string& line : l.lines) w = std::max(w, text_width(line, s));
    const int lines = static_cast<int>(l.lines.size());
    if (w > 0) l.text = {l.margin - 2 * s, l.margin - 2 * s, w + 4 * s, lines * line_height(s) + 3 * s};
  }
  if (frame.inset.show) place_inset(frame, width, height, l);
  if (!frame.cloth_field.empty() && frame.color_scale.show_bar) place_color_bar(frame, width, height, l);
  if (!frame.banner.empty()) place_banner(frame, width, height, l);
  return l;
}

int color_bar_strip_width(std::string_view label, int scale) {
  const int s = scale;  // as fit_bar_panel: pads, bar, tick mark, gap, the widest tick label; margins
  return std::max(text_width(label, s), text_width("1.5e-5", s) + s + 2 * s + 6 * s) + 4 * s + 2 * (4 * s);
}

OverlayLayout layout_color_bar_strip(const ColorScale& scale, const ImageBox& strip, int text_scale) {
  OverlayLayout l;
  l.scale = text_scale;
  l.margin = 4 * text_scale;
  const int s = text_scale;
  const int title_h = scale.label.empty() ? 0 : line_height(s) + s;
  const int bar_h = std::max(strip.h / 2, line_height(s));
  const int panel_h = 4 * s + title_h + 8 * s + bar_h;
  fit_bar_panel(scale, strip.right() - l.margin, strip.y + std::max(0, (strip.h - panel_h) / 2), bar_h, l);
  return l;
}

}  // namespace clothsim::render

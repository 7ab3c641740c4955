// Text for panel titles, colour-bar tick labels and the caption line (SPEC §3 "text
// labels"): FreeType renders DejaVu Sans glyphs into an R8 atlas texture, and all text
// queued for a frame is drawn as one instanced batch of glyph quads (one texel per pixel).
#pragma once
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "render/context/shader_program.hpp"
#include "render/layers/colormap.hpp"
#include "render/layers/gl_buffer.hpp"

namespace grainflow::render {

// The font file: $GRAINFLOW_FONT when set, else DejaVuSans.ttf in the usual system
// folders (Debian's fonts-dejavu-core first). Throws grainflow::Error naming the places
// looked in and the package to install.
std::string find_default_font();

enum class TextAlign { left, centre, right };
// Vertical anchor of the y coordinate: the top of the line (ascender), its middle
// (half the cap height above the baseline), the baseline, or the bottom (descender).
enum class TextAnchor { top, middle, baseline, bottom };

// Text broken at spaces into lines of at most `max_width` pixels at `px` pixels per em:
// the fewest lines (up to max_lines), as even in width as that count allows; when they do
// not fit, px shrinks (down to min_px, then the text is left as wide as it is). Text that
// fits on one line comes back as written, its spaces kept. `measure` gives a string's
// width at a size (TextRenderer::measure).
struct FittedText {
  std::vector<std::string> lines;
  int px = 0;
};
FittedText fit_text(std::string_view utf8, float max_width, int px, int max_lines,
                    const std::function<float(std::string_view, int)>& measure, int min_px = 6);

class TextRenderer {
public:
  // Loads the font now (throws grainflow::Error if it cannot be opened or parsed).
  explicit TextRenderer(const GlApi& gl, const std::string& font_path = find_default_font());
  ~TextRenderer();
  TextRenderer(const TextRenderer&) = delete;
  TextRenderer& operator=(const TextRenderer&) = delete;

  // Advance width of a UTF-8 string at `px` pixels per em, in pixels (kerning included).
  float measure(std::string_view utf8, int px);
  // Queues a string; (x, y) in frame pixels from the top-left corner. Pen positions are
  // rounded to whole pixels so the same text always yields the same pixels.
  void add(std::string_view utf8, float x, float y, int px, Rgb colour, TextAlign align = TextAlign::left,
           TextAnchor anchor = TextAnchor::baseline, float alpha = 1.0f);
  // Draws everything queued into the current framebuffer (viewport set here to the whole
  // width × height frame) in one instanced call, then empties the queue.
  void draw(int width, int height);
  void clear() { quads_.clear(); }
  std::size_t queued_glyphs() const { return quads_.size(); }

private:
  struct Glyph {
    int x = 0, y = 0, w = 0, h = 0;  // in the atlas
    int left = 0, top = 0;           // bitmap offset from the pen on the baseline
    int advance = 0;                 // whole pixels (hinted)
    unsigned index = 0;              // glyph index, for kerning
  };
  struct Quad {
    float rect[4];
    float uv[4];
    float rgba[4];
  };
  struct Face;

  const Glyph& glyph(char32_t c, int px);
  void set_size(int px);
  void grow_atlas();

  const GlApi& gl_;
  std::unique_ptr<Face> face_;
  ShaderProgram program_;
  GlVertexArray vao_;
  GlBuffer buffer_;
  GlTexture atlas_texture_;
  std::map<std::pair<char32_t, int>, Glyph> glyphs_;
  std::vector<std::uint8_t> atlas_;  // R8, row 0 first
  int atlas_w_ = 1024, atlas_h_ = 512;
  int shelf_x_ = 0, shelf_y_ = 0, shelf_h_ = 0;
  bool atlas_dirty_ = true;
  int current_px_ = 0;
  std::vector<Quad> quads_;
};

}  // namespace grainflow::render

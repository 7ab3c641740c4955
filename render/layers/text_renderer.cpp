#include "render/layers/text_renderer.hpp"

#include <ft2build.h>
#include FT_FREETYPE_H

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "engine/core/error.hpp"

namespace grainflow::render {

std::string find_default_font() {
  if (const char* env = std::getenv("GRAINFLOW_FONT"); env && *env) {
    if (!std::filesystem::exists(env))
      throw Error(std::string("GRAINFLOW_FONT = '") + env + "' does not exist; set it to a TrueType font file");
    return env;
  }
  const char* candidates[] = {
      "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",  // Debian, Ubuntu: fonts-dejavu-core
      "/usr/share/fonts/dejavu/DejaVuSans.ttf",           // Fedora, Arch
      "/usr/share/fonts/TTF/DejaVuSans.ttf",
      "/usr/local/share/fonts/DejaVuSans.ttf",
      "/usr/local/share/fonts/dejavu/DejaVuSans.ttf",
      "/opt/homebrew/share/fonts/DejaVuSans.ttf",
  };
  std::string looked;
  for (const char* c : candidates) {
    if (std::filesystem::exists(c)) return c;
    looked += std::string(looked.empty() ? "" : ", ") + c;
  }
  throw Error("font DejaVuSans.ttf not found (looked in " + looked +
              "); install the Debian package fonts-dejavu-core or set GRAINFLOW_FONT to a .ttf file");
}

struct TextRenderer::Face {
  FT_Library library = nullptr;
  FT_Face face = nullptr;
  ~Face() {
    if (face) FT_Done_Face(face);
    if (library) FT_Done_FreeType(library);
  }
};

namespace {
// Decodes UTF-8; malformed bytes become U+FFFD so bad labels never stop a run.
std::u32string decode_utf8(std::string_view s) {
  std::u32string out;
  for (std::size_t i = 0; i < s.size();) {
    const auto b = static_cast<unsigned char>(s[i]);
    int n = b < 0x80 ? 0 : (b >> 5) == 6 ? 1 : (b >> 4) == 14 ? 2 : (b >> 3) == 30 ? 3 : -1;
    if (n < 0) {
      out.push_back(0xFFFD);
      ++i;
      continue;
    }
    char32_t c = n == 0 ? b : b & (0x3F >> n);
    bool ok = true;
    for (int k = 1; k <= n; ++k) {
      if (i + k >= s.size()) { ok = false; break; }
      const auto cb = static_cast<unsigned char>(s[i + k]);
      if ((cb >> 6) != 2) { ok = false; break; }
      c = (c << 6) | (cb & 0x3F);
    }
    if (!ok) {
      out.push_back(0xFFFD);
      ++i;
      continue;
    }
    out.push_back(c);
    i += static_cast<std::size_t>(n) + 1;
  }
  return out;
}
}  // namespace

TextRenderer::TextRenderer(const GlApi& gl, const std::string& font_path)
    : gl_(gl),
      face_(std::make_unique<Face>()),
      program_(gl, "text.vert", "text.frag"),
      vao_(gl),
      buffer_(gl),
      atlas_texture_(gl) {
  atlas_.assign(static_cast<std::size_t>(atlas_w_) * atlas_h_, 0);
  if (FT_Init_FreeType(&face_->library) != 0) throw Error("FreeType does not initialise");
  if (FT_New_Face(face_->library, font_path.c_str(), 0, &face_->face) != 0)
    throw Error("font '" + font_path + "' cannot be opened as a TrueType/OpenType font");
}

TextRenderer::~TextRenderer() = default;

void TextRenderer::set_size(int px) {
  if (px == current_px_) return;
  if (FT_Set_Pixel_Sizes(face_->face, 0, static_cast<FT_UInt>(px)) != 0)
    throw Error("font size " + std::to_string(px) + " px is not available");
  current_px_ = px;
}

void TextRenderer::grow_atlas() {
  if (atlas_h_ >= 8192) throw Error("text atlas full (8192 rows): too many glyph sizes in one frame");
  atlas_.resize(static_cast<std::size_t>(atlas_w_) * atlas_h_ * 2, 0);
  atlas_h_ *= 2;
  atlas_dirty_ = true;
}

const TextRenderer::Glyph& TextRenderer::glyph(char32_t c, int px) {
  const auto key = std::pair{c, px};
  if (auto it = glyphs_.find(key); it != glyphs_.end()) return it->second;
  set_size(px);
  FT_Face f = face_->face;
  Glyph g;
  g.index = FT_Get_Char_Index(f, c);
  if (g.index == 0 && c != U'?') {
    const Glyph& q = glyph(U'?', px);  // a character the font lacks: shown as '?'
    return glyphs_.emplace(key, q).first->second;
  }
  set_size(px);
  if (FT_Load_Glyph(f, g.index, FT_LOAD_RENDER | FT_LOAD_TARGET_NORMAL) != 0)
    throw Error("FreeType cannot render character U+" + std::to_string(static_cast<unsigned>(c)));
  const FT_Bitmap& bm = f->glyph->bitmap;
  g.w = static_cast<int>(bm.width);
  g.h = static_cast<int>(bm.rows);
  g.left = f->glyph->bitmap_left;
  g.top = f->glyph->bitmap_top;
  g.advance = static_cast<int>((f->glyph->advance.x + 32) >> 6);
  if (g.w > 0 && g.h > 0) {
    if (g.w + 1 > atlas_w_) throw Error("glyph wider than the text atlas: font size " + std::to_string(px) + " px");
    if (shelf_x_ + g.w + 1 > atlas_w_) {  // next shelf
      shelf_y_ += shelf_h_ + 1;
      shelf_x_ = 0;
      shelf_h_ = 0;
    }
    while (shelf_y_ + g.h + 1 > atlas_h_) grow_atlas();
    g.x = shelf_x_;
    g.y = shelf_y_;
    for (int r = 0; r < g.h; ++r) {
      const unsigned char* src = bm.buffer + static_cast<std::ptrdiff_t>(r) * bm.pitch;
      std::copy(src, src + g.w, atlas_.begin() + static_cast<std::ptrdiff_t>(g.y + r) * atlas_w_ + g.x);
    }
    shelf_x_ += g.w + 1;
    shelf_h_ = std::max(shelf_h_, g.h);
    atlas_dirty_ = true;
  }
  return glyphs_.emplace(key, g).first->second;
}

namespace {
// Greedy breaking at spaces: each line takes words while it stays within `width`.
std::vector<std::string> break_greedy(const std::vector<std::string>& words, float width, int px,
                                      const std::function<float(std::string_view, int)>& measure) {
  std::vector<std::string> lines;
  for (const std::string& w : words) {
    if (!lines.empty() && measure(lines.back() + " " + w, px) <= width) lines.back() += " " + w;
    else lines.push_back(w);
  }
  return lines;
}
}  // namespace

FittedText fit_text(std::string_view utf8, float max_width, int px, int max_lines,
                    const std::function<float(std::string_view, int)>& measure, int min_px) {
  std::vector<std::string> words;
  std::size_t pos = 0;
  while (pos < utf8.size()) {
    const std::size_t end = std::min(utf8.find(' ', pos), utf8.size());
    if (end > pos) words.emplace_back(utf8.substr(pos, end - pos));
    pos = end + 1;
  }
  if (words.empty()) return {{}, px};
  auto widest = [&](const std::vector<std::string>& lines, int size) {
    float w = 0;
    for (const auto& l : lines) w = std::max(w, measure(l, size));
    return w;
  };
  for (int size = px;; --size) {
    // Text that fits on one line is kept as written (a caption spaces its fields with
    // runs of spaces, which a break at spaces would close up), so one line fits only so.
    if (measure(utf8, size) <= max_width) return {{std::string(utf8)}, size};
    std::vector<std::string> lines = break_greedy(words, max_width, size, measure);
    const bool fits = lines.size() > 1 && int(lines.size()) <= max_lines && widest(lines, size) <= max_width;
    if (fits || size <= min_px) {
      // Even out the lines: narrow the width while the line count stays (the last line of
      // a greedy break is otherwise left short).
      if (fits)
        for (;;) {
          auto narrower = break_greedy(words, widest(lines, size) - 1.0f, size, measure);
          if (narrower.size() != lines.size() || widest(narrower, size) >= widest(lines, size)) break;
          lines = std::move(narrower);
        }
      return {std::move(lines), size};
    }
  }
}

float TextRenderer::measure(std::string_view utf8, int px) {
  const std::u32string text = decode_utf8(utf8);
  int pen = 0;
  unsigned prev = 0;
  const bool kerning = FT_HAS_KERNING(face_->face);
  for (char32_t c : text) {
    const Glyph& g = glyph(c, px);
    if (kerning && prev && g.index) {
      set_size(px);
      FT_Vector k;
      if (FT_Get_Kerning(face_->face, prev, g.index, FT_KERNING_DEFAULT, &k) == 0) pen += static_cast<int>(k.x >> 6);
    }
    pen += g.advance;
    prev = g.index;
  }
  return static_cast<float>(pen);
}

void TextRenderer::add(std::string_view utf8, float x, float y, int px, Rgb colour, TextAlign align,
                       TextAnchor anchor, float alpha) {
  if (px < 1) throw Error("font size " + std::to_string(px) + " px is not allowed; allowed: ≥ 1");
  const std::u32string text = decode_utf8(utf8);
  const float width = measure(utf8, px);
  set_size(px);
  const FT_Size_Metrics& m = face_->face->size->metrics;
  const float ascender = float(m.ascender) / 64.0f, descender = float(m.descender) / 64.0f;
  float baseline = y;
  switch (anchor) {
    case TextAnchor::top: baseline = y + ascender; break;
    case TextAnchor::middle: baseline = y + 0.36f * float(px); break;  // ≈ half DejaVu's cap height
    case TextAnchor::baseline: break;
    case TextAnchor::bottom: baseline = y + descender; break;
  }
  float start = x;
  if (align == TextAlign::centre) start = x - 0.5f * width;
  if (align == TextAlign::right) start = x - width;
  const int base_y = static_cast<int>(std::lround(baseline));
  int pen = static_cast<int>(std::lround(start));
  unsigned prev = 0;
  const bool kerning = FT_HAS_KERNING(face_->face);
  for (char32_t c : text) {
    const Glyph g = glyph(c, px);  // copy: glyph() may rehash the map
    if (kerning && prev && g.index) {
      set_size(px);
      FT_Vector k;
      if (FT_Get_Kerning(face_->face, prev, g.index, FT_KERNING_DEFAULT, &k) == 0) pen += static_cast<int>(k.x >> 6);
    }
    if (g.w > 0 && g.h > 0) {
      const float x0 = float(pen + g.left), y0 = float(base_y - g.top);
      quads_.push_back({{x0, y0, x0 + float(g.w), y0 + float(g.h)},
                        {float(g.x), float(g.y), float(g.x + g.w), float(g.y + g.h)},
                        {colour.r, colour.g, colour.b, alpha}});
    }
    pen += g.advance;
    prev = g.index;
  }
}

void TextRenderer::draw(int width, int height) {
  if (quads_.empty()) return;
  gl_.ActiveTexture(GL_TEXTURE0);
  gl_.BindTexture(GL_TEXTURE_2D, atlas_texture_.id());
  if (atlas_dirty_) {
    gl_.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl_.TexImage2D(GL_TEXTURE_2D, 0, GL_R8, atlas_w_, atlas_h_, 0, GL_RED, GL_UNSIGNED_BYTE, atlas_.data());
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    atlas_dirty_ = false;
  }
  vao_.bind();
  buffer_.upload(quads_.data(), quads_.size() * sizeof(Quad));
  const GLsizei stride = sizeof(Quad);
  for (GLuint loc = 0; loc < 3; ++loc) {
    gl_.EnableVertexAttribArray(loc);
    gl_.VertexAttribPointer(loc, 4, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(loc * 4 * sizeof(float)));
    gl_.VertexAttribDivisor(loc, 1);
  }
  program_.use();
  gl_.Uniform1i(program_.uniform("u_atlas"), 0);
  gl_.Uniform2f(program_.uniform("u_viewport"), float(width), float(height));
  gl_.Viewport(0, 0, width, height);
  gl_.Enable(GL_BLEND);
  gl_.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  gl_.Disable(GL_DEPTH_TEST);
  gl_.DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(quads_.size()));
  gl_.Disable(GL_BLEND);
  quads_.clear();
}

}  // namespace grainflow::render

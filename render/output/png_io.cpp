#include "render/output/png_io.hpp"

#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "engine/io/atomic_file.hpp"
#include "engine/core/error.hpp"

namespace grainflow::render {

namespace {

// libpng reports errors through a callback that must not return. We longjmp back to the
// setjmp in the small C-style functions below; they hold only trivially destructible
// locals, and everything with a destructor lives in their callers, so no C++ destructor is
// ever skipped and no local modified after setjmp is read after the jump.
struct PngErrorSink {
  char message[256] = {0};
};

extern "C" void on_png_error(png_structp png, png_const_charp msg) {
  auto* sink = static_cast<PngErrorSink*>(png_get_error_ptr(png));
  std::snprintf(sink->message, sizeof(sink->message), "%s", msg ? msg : "unknown libpng error");
  png_longjmp(png, 1);
}

extern "C" void on_png_warning(png_structp, png_const_charp) {
  // Warnings (e.g. an unknown ancillary chunk, an iCCP profile libpng dislikes) do not
  // affect the pixels we read; staying quiet keeps batch output clean.
}

// Closes the FILE* on every path out of the caller.
struct FileCloser {
  std::FILE* f = nullptr;
  ~FileCloser() {
    if (f) std::fclose(f);
  }
};

bool write_rows(png_structp png, png_infop info, std::FILE* f, const Image& image, const PngOptions& options,
                bool opaque, png_bytep* rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_init_io(png, f);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.width), static_cast<png_uint_32>(image.height), 8,
               opaque ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_RGBA, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, options.compression_level);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, options.filters ? PNG_ALL_FILTERS : PNG_FILTER_NONE);
  png_write_info(png, info);
  if (opaque) png_set_filler(png, 0, PNG_FILLER_AFTER);  // drop the alpha byte while writing
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  return true;
}

struct PngHeader {
  png_uint_32 width = 0;
  png_uint_32 height = 0;
  std::size_t rowbytes = 0;
};

bool read_header(png_structp png, png_infop info, std::FILE* f, PngHeader* out) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_init_io(png, f);
  png_set_sig_bytes(png, 8);
  png_read_info(png, info);
  const int color_type = png_get_color_type(png, info);
  const int bit_depth = png_get_bit_depth(png, info);
  const bool has_trns = png_get_valid(png, info, PNG_INFO_tRNS) != 0;
  if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (color_type == PNG_COLOR_TYPE_GRAY && bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (has_trns) png_set_tRNS_to_alpha(png);
  if (bit_depth == 16) png_set_scale_16(png);
  if (color_type == PNG_COLOR_TYPE_GRAY || color_type == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(png);
  if ((color_type & PNG_COLOR_MASK_ALPHA) == 0 && !has_trns) png_set_filler(png, 0xff, PNG_FILLER_AFTER);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  out->width = png_get_image_width(png, info);
  out->height = png_get_image_height(png, info);
  out->rowbytes = png_get_rowbytes(png, info);
  return true;
}

bool read_rows(png_structp png, png_infop info, png_bytep* rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_image(png, rows);
  png_read_end(png, info);  // checks the CRCs of chunks after the image data too
  return true;
}

// Rendered frames are opaque; storing them as RGB deflates 25% less data (~15% less CPU,
// ~10% smaller files at level 1) and reads back identical (alpha 255).
bool all_opaque(const Image& image) {
  for (std::size_t i = 3; i < image.rgba.size(); i += 4)
    if (image.rgba[i] != 255) return false;
  return true;
}

std::vector<png_bytep> row_pointers(const Image& image) {
  std::vector<png_bytep> rows(static_cast<std::size_t>(image.height));
  for (int y = 0; y < image.height; ++y) rows[static_cast<std::size_t>(y)] = const_cast<png_bytep>(image.pixel(0, y));
  return rows;
}

}  // namespace

void write_png(const std::filesystem::path& path, const Image& image, const PngOptions& options) {
  const std::string where = "PNG '" + path.string() + "'";
  if (image.empty()) throw Error(where + ": cannot write an empty image (" + std::to_string(image.width) + "x" +
                                 std::to_string(image.height) + ")");
  if (image.rgba.size() != static_cast<std::size_t>(image.width) * image.height * 4)
    throw Error(where + ": image buffer holds " + std::to_string(image.rgba.size()) + " bytes, expected " +
                std::to_string(static_cast<std::size_t>(image.width) * image.height * 4));
  if (options.compression_level < 0 || options.compression_level > 9)
    throw Error(where + ": compression level " + std::to_string(options.compression_level) +
                " is out of range (allowed 0..9)");

  io::AtomicFile out(path);
  PngErrorSink errors;
  {
    FileCloser file{std::fopen(out.path().c_str(), "wb")};
    if (!file.f) throw Error("cannot open " + where + " for writing: " + std::strerror(errno));
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &errors, on_png_error, on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!png || !info) {
      png_destroy_write_struct(&png, &info);
      throw Error(where + ": libpng could not allocate its write structures");
    }
    std::vector<png_bytep> rows = row_pointers(image);
    const bool ok = write_rows(png, info, file.f, image, options, all_opaque(image), rows.data());
    png_destroy_write_struct(&png, &info);
    if (!ok) throw Error("cannot write " + where + ": " + errors.message);
    std::FILE* f = file.f;
    file.f = nullptr;
    // fclose flushes the last buffer; a full disk shows up here, not in libpng.
    if (std::fflush(f) != 0 || std::ferror(f)) {
      const int err = errno;
      std::fclose(f);
      throw Error("cannot write " + where + ": " + std::strerror(err));
    }
    if (std::fclose(f) != 0) throw Error("cannot write " + where + ": " + std::strerror(errno));
  }
  out.commit();
}

Image read_png(const std::filesystem::path& path) {
  const std::string where = "PNG '" + path.string() + "'";
  FileCloser file{std::fopen(path.c_str(), "rb")};
  if (!file.f) throw Error("cannot open " + where + ": " + std::strerror(errno));
  png_byte signature[8] = {0};
  const std::size_t got = std::fread(signature, 1, sizeof(signature), file.f);
  if (got != sizeof(signature) || png_sig_cmp(signature, 0, sizeof(signature)) != 0)
    throw Error("'" + path.string() + "' is not a PNG file (no PNG signature)");

  PngErrorSink errors;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &errors, on_png_error, on_png_warning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw Error(where + ": libpng could not allocate its read structures");
  }
  // Destroys the libpng structures on every path out, including exceptions.
  struct ReadGuard {
    png_structp* png;
    png_infop* info;
    ~ReadGuard() { png_destroy_read_struct(png, info, nullptr); }
  } guard{&png, &info};

  PngHeader header;
  if (!read_header(png, info, file.f, &header)) throw Error("corrupt " + where + ": " + errors.message);
  if (header.rowbytes != static_cast<std::size_t>(header.width) * 4)
    throw Error(where + ": internal conversion to RGBA8 gave " + std::to_string(header.rowbytes) +
                " bytes per row for width " + std::to_string(header.width));
  if (header.width > 1u << 16 || header.height > 1u << 16)
    throw Error(where + ": image size " + std::to_string(header.width) + "x" + std::to_string(header.height) +
                " exceeds the supported 65536x65536");

  Image image(static_cast<int>(header.width), static_cast<int>(header.height));
  std::vector<png_bytep> rows = row_pointers(image);
  if (!read_rows(png, info, rows.data())) throw Error("corrupt " + where + ": " + errors.message);
  return image;
}

std::pair<int, int> png_size(const std::filesystem::path& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw Error("cannot open '" + path.string() + "': " + std::strerror(errno));
  unsigned char h[24];
  const bool whole = std::fread(h, 1, sizeof h, f) == sizeof h;
  std::fclose(f);
  static constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (!whole || std::memcmp(h, kSignature, 8) != 0)
    throw Error("'" + path.string() + "' is not a PNG file (no PNG signature)");
  if (std::memcmp(h + 12, "IHDR", 4) != 0) throw Error("corrupt PNG '" + path.string() + "': no IHDR chunk first");
  auto be32 = [&](int at) {
    return (std::uint32_t(h[at]) << 24) | (std::uint32_t(h[at + 1]) << 16) | (std::uint32_t(h[at + 2]) << 8) | h[at + 3];
  };
  const std::uint32_t w = be32(16), ht = be32(20);
  if (w == 0 || ht == 0 || w > (1u << 30) || ht > (1u << 30))
    throw Error("corrupt PNG '" + path.string() + "': size " + std::to_string(w) + "x" + std::to_string(ht));
  return {int(w), int(ht)};
}

}  // namespace grainflow::render

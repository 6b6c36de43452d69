#include "cover/io/png.h"

#include <png.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

#include "cover/io/atomic_file.h"
#include "cover/solid/errors.h"

namespace cover {
namespace {

struct FileCloser {
  void operator()(FILE* f) const {
    if (f) std::fclose(f);
  }
};

/// Writes rows through libpng into `tmp`; returns false on any libpng or I/O error, with the
/// I/O error's errno in `os_error` (0 when none).
bool encode(const std::filesystem::path& tmp, int width, int height, int bit_depth, int color,
            const std::vector<std::vector<uint8_t>>& rows, int& os_error) {
  errno = 0;
  std::unique_ptr<FILE, FileCloser> file(std::fopen(tmp.c_str(), "wb"));
  if (!file) {
    os_error = errno;
    return false;
  }
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {  // libpng reports errors by longjmp
    os_error = std::ferror(file.get()) ? errno : 0;
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_init_io(png, file.get());
  png_set_IHDR(png, info, width, height, bit_depth, color, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (const auto& row : rows) png_write_row(png, const_cast<png_bytep>(row.data()));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (std::fflush(file.get()) == 0 && !std::ferror(file.get())) return true;
  os_error = errno;
  return false;
}

void write_atomic(const std::filesystem::path& path, int width, int height, int bit_depth,
                  int color, const std::vector<std::vector<uint8_t>>& rows) {
  check_png_path(path);
  if (width <= 0 || height <= 0) throw InputError(path.string() + ": empty image");
  int os_error = 0;
  try {
    write_atomically(
        path,
        [&](const std::filesystem::path& tmp) {
          return encode(tmp, width, height, bit_depth, color, rows, os_error);
        },
        "PNG");
  } catch (const InputError& e) {
    if (os_error == 0) throw;
    throw InputError(std::string(e.what()) + " (" + std::strerror(os_error) + ")");
  }
}

}  // namespace

void check_png_path(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  if (ext != ".png")
    throw InputError(path.string() + ": unsupported image format '" + path.extension().string() +
                     "' (expected .png)");
}

void write_png_rgb(const std::filesystem::path& path, int width, int height,
                   std::span<const uint8_t> rgb) {
  std::vector<std::vector<uint8_t>> rows(static_cast<size_t>(std::max(0, height)));
  for (int y = 0; y < height; ++y)
    rows[y].assign(rgb.begin() + 3L * y * width, rgb.begin() + 3L * (y + 1) * width);
  write_atomic(path, width, height, 8, PNG_COLOR_TYPE_RGB, rows);
}

void write_png_gray16(const std::filesystem::path& path, int width, int height,
                      std::span<const uint16_t> values) {
  std::vector<std::vector<uint8_t>> rows(static_cast<size_t>(std::max(0, height)));
  for (int y = 0; y < height; ++y) {
    rows[y].resize(2 * static_cast<size_t>(width));
    for (int x = 0; x < width; ++x) {  // PNG stores 16-bit samples big-endian
      const uint16_t v = values[static_cast<size_t>(y) * width + x];
      rows[y][2 * x] = static_cast<uint8_t>(v >> 8);
      rows[y][2 * x + 1] = static_cast<uint8_t>(v & 0xff);
    }
  }
  write_atomic(path, width, height, 16, PNG_COLOR_TYPE_GRAY, rows);
}

PngImage read_png(const std::filesystem::path& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str()))
    throw InputError(path.string() + ": cannot read PNG");
  PngImage out;
  out.width = static_cast<int>(image.width);
  out.height = static_cast<int>(image.height);
  const bool gray16 =
      (image.format & PNG_FORMAT_FLAG_COLOR) == 0 && (image.format & PNG_FORMAT_FLAG_LINEAR) != 0;
  // The simplified API converts; for 16-bit grey we ask for linear 16-bit grey samples.
  image.format = gray16 ? PNG_FORMAT_LINEAR_Y : PNG_FORMAT_RGB;
  out.channels = gray16 ? 1 : 3;
  out.bit_depth = gray16 ? 16 : 8;
  std::vector<uint8_t> buffer(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, buffer.data(), 0, nullptr)) {
    png_image_free(&image);
    throw InputError(path.string() + ": cannot decode PNG");
  }
  if (gray16) {
    out.values.resize(buffer.size() / 2);
    std::memcpy(out.values.data(), buffer.data(), buffer.size());
  } else {
    out.values.assign(buffer.begin(), buffer.end());
  }
  return out;
}

}  // namespace cover

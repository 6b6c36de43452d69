#pragma once
// PNG output: rows deflated by zlib in parallel bands (the bytes do not depend on the thread
// count), chunks written by libpng (Debian libpng-dev); io/png.cpp has the details. Files are
// written atomically: a temporary file in the same folder, then rename; a failure leaves no
// partial file and throws InputError.

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace cover {

/// Throws InputError "PATH: unsupported image format '.jpg' (expected .png)" unless the extension
/// is .png (any case). The writers check it; commands call it before doing any work.
void check_png_path(const std::filesystem::path& path);

/// 8-bit RGB, 3·width·height bytes, rows from the top.
void write_png_rgb(const std::filesystem::path& path, int width, int height,
                   std::span<const uint8_t> rgb);

/// The bytes write_png_rgb() writes for the same image, in memory (a viewer's frame).
std::vector<uint8_t> encode_png_rgb(int width, int height, std::span<const uint8_t> rgb);

/// 16-bit grey, width·height values, rows from the top.
void write_png_gray16(const std::filesystem::path& path, int width, int height,
                      std::span<const uint16_t> values);

/// Reads a PNG back (tests): channels = 3 for RGB8 or 1 for GRAY16; values widened to uint16.
struct PngImage {
  int width = 0, height = 0, channels = 0, bit_depth = 0;
  std::vector<uint16_t> values;
};
PngImage read_png(const std::filesystem::path& path);

}  // namespace cover

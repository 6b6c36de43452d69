// io/png.h: write_png_rgb and write_png_gray16 round-trip bit-exactly through libpng (read_png)
// for sizes of one band, of many bands and of rows wider than a band, for random bytes (stored
// bands), smooth gradients (deflated bands) and both in one image; the file is one valid zlib
// stream (every chunk CRC and the adler32 checked here with zlib); the bytes do not depend on the
// thread count; a failed write throws InputError and leaves no file.
#include "cover/io/png.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"
#include "helpers.h"

namespace cover {
namespace {

struct Size {
  int width, height;
};

// 1×1, a few rows, one band and many; widths not a multiple of any band's rows, rows of more
// than a band (40000·3 bytes), a single column.
const std::vector<Size> kSizes = {{1, 1},     {3, 7},   {1024, 1024}, {1023, 77},
                                  {40000, 3}, {1, 999}, {257, 511}};

/// Top half random, bottom half a gradient: bands of both kinds in one stream.
std::vector<uint8_t> rgb_image(Size s, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<uint8_t> rgb(3 * static_cast<size_t>(s.width) * s.height);
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const size_t i = 3 * (static_cast<size_t>(y) * s.width + x) + c;
        rgb[i] = y < s.height / 2 ? static_cast<uint8_t>(rng())
                                  : static_cast<uint8_t>(x * (c + 1) + 3 * y);
      }
  return rgb;
}

std::vector<uint16_t> gray16_image(Size s, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<uint16_t> v(static_cast<size_t>(s.width) * s.height);
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x)
      v[static_cast<size_t>(y) * s.width + x] =
          y < s.height / 2 ? static_cast<uint16_t>(rng()) : static_cast<uint16_t>(257 * x + 31 * y);
  return v;
}

uint32_t be32(const std::string& s, size_t at) {
  return static_cast<uint32_t>(static_cast<uint8_t>(s[at])) << 24 |
         static_cast<uint32_t>(static_cast<uint8_t>(s[at + 1])) << 16 |
         static_cast<uint32_t>(static_cast<uint8_t>(s[at + 2])) << 8 |
         static_cast<uint32_t>(static_cast<uint8_t>(s[at + 3]));
}

/// Checks the file's chunks (signature, IHDR first, IEND last, every CRC) and inflates the IDAT
/// stream with zlib (which checks the adler32); returns the filtered bytes.
std::string check_chunks(const std::filesystem::path& path, size_t filtered_size) {
  const std::string f = test::read_file(path);
  EXPECT_EQ(f.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  std::string idat, names;
  size_t at = 8;
  while (at + 12 <= f.size()) {
    const uint32_t length = be32(f, at);
    const std::string name = f.substr(at + 4, 4);
    if (at + 12 + length > f.size()) break;
    const auto* bytes = reinterpret_cast<const Bytef*>(f.data() + at + 4);
    EXPECT_EQ(crc32(0, bytes, 4 + length), be32(f, at + 8 + length)) << name;
    if (name == "IDAT") idat += f.substr(at + 8, length);
    if (names.empty() || names.substr(names.size() - 4) != name) names += name;
    at += 12 + length;
  }
  EXPECT_EQ(at, f.size());
  EXPECT_EQ(names, "IHDRIDATIEND");
  std::string filtered(filtered_size + 1, '\0');  // one spare byte: longer data must fail
  uLongf n = filtered.size();
  EXPECT_EQ(uncompress(reinterpret_cast<Bytef*>(filtered.data()), &n,
                       reinterpret_cast<const Bytef*>(idat.data()), idat.size()),
            Z_OK);
  EXPECT_EQ(n, filtered_size);
  filtered.resize(n);
  return filtered;
}

TEST(Png, RgbRoundTripsBitExactly) {
  const auto dir = test::temp_dir("png");
  for (const Size s : kSizes) {
    SCOPED_TRACE(std::to_string(s.width) + "x" + std::to_string(s.height));
    const std::vector<uint8_t> rgb = rgb_image(s, 7 * s.width + s.height);
    write_png_rgb(dir / "a.png", s.width, s.height, rgb);
    const PngImage back = read_png(dir / "a.png");
    EXPECT_EQ(back.width, s.width);
    EXPECT_EQ(back.height, s.height);
    EXPECT_EQ(back.channels, 3);
    EXPECT_EQ(back.bit_depth, 8);
    EXPECT_EQ(back.values, std::vector<uint16_t>(rgb.begin(), rgb.end()));
    check_chunks(dir / "a.png", (3 * static_cast<size_t>(s.width) + 1) * s.height);
  }
  std::filesystem::remove_all(dir);
}

TEST(Png, Gray16RoundTripsBitExactly) {
  const auto dir = test::temp_dir("png");
  for (const Size s : kSizes) {
    SCOPED_TRACE(std::to_string(s.width) + "x" + std::to_string(s.height));
    const std::vector<uint16_t> v = gray16_image(s, 5 * s.width + s.height);
    write_png_gray16(dir / "a.png", s.width, s.height, v);
    const PngImage back = read_png(dir / "a.png");
    EXPECT_EQ(back.width, s.width);
    EXPECT_EQ(back.height, s.height);
    EXPECT_EQ(back.channels, 1);
    EXPECT_EQ(back.bit_depth, 16);
    EXPECT_EQ(back.values, v);
    check_chunks(dir / "a.png", (2 * static_cast<size_t>(s.width) + 1) * s.height);
  }
  std::filesystem::remove_all(dir);
}

TEST(Png, SmoothImagesCompress) {
  // A gradient deflates: far below the 3 MiB of raw samples (random bytes are stored).
  const auto dir = test::temp_dir("png");
  std::vector<uint8_t> rgb(3 * 1024 * 1024);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<uint8_t>(i / 3 % 1024 / 4);
  write_png_rgb(dir / "a.png", 1024, 1024, rgb);
  EXPECT_LT(std::filesystem::file_size(dir / "a.png"), 100000u);
  EXPECT_EQ(read_png(dir / "a.png").values, std::vector<uint16_t>(rgb.begin(), rgb.end()));
  std::filesystem::remove_all(dir);
}

TEST(Png, BytesDoNotDependOnThreads) {
  const auto dir = test::temp_dir("png");
  const Size s{1023, 1031};
  const std::vector<uint8_t> rgb = rgb_image(s, 1);
  const std::vector<uint16_t> v = gray16_image(s, 2);
  std::string rgb_bytes[3], gray_bytes[3];
  for (int t : {1, 2, 0}) {  // 0: all cores
    ThreadLimit limit(t);
    write_png_rgb(dir / "a.png", s.width, s.height, rgb);
    write_png_gray16(dir / "b.png", s.width, s.height, v);
    rgb_bytes[t] = test::read_file(dir / "a.png");
    gray_bytes[t] = test::read_file(dir / "b.png");
  }
  EXPECT_GT(rgb_bytes[1].size(), 1000u);
  EXPECT_TRUE(rgb_bytes[1] == rgb_bytes[2]);
  EXPECT_TRUE(rgb_bytes[1] == rgb_bytes[0]);
  EXPECT_TRUE(gray_bytes[1] == gray_bytes[2]);
  EXPECT_TRUE(gray_bytes[1] == gray_bytes[0]);
  std::filesystem::remove_all(dir);
}

TEST(Png, FailedWritesLeaveNoFile) {
  const auto dir = test::temp_dir("png");
  const std::vector<uint8_t> rgb(3 * 16 * 16, 100);
  const std::vector<uint16_t> v(16 * 16, 1000);
  EXPECT_THROW(write_png_rgb(dir / "missing" / "a.png", 16, 16, rgb), InputError);
  EXPECT_THROW(write_png_gray16(dir / "missing" / "a.png", 16, 16, v), InputError);
  EXPECT_THROW(write_png_rgb(dir / "a.jpg", 16, 16, rgb), InputError);
  EXPECT_THROW(write_png_rgb(dir / "a.png", 0, 16, rgb), InputError);
  EXPECT_THROW(write_png_rgb(dir / "a.png", 16, 17, rgb), InputError);  // too few samples
  EXPECT_THROW(write_png_gray16(dir / "a.png", 17, 16, v), InputError);
  EXPECT_TRUE(std::filesystem::is_empty(dir));  // no temporary left either
  EXPECT_FALSE(std::filesystem::exists(dir / "missing"));
  // A failed write leaves an existing file as it was.
  write_png_rgb(dir / "a.png", 16, 16, rgb);
  const std::string before = test::read_file(dir / "a.png");
  EXPECT_THROW(write_png_rgb(dir / "a.png", 16, 17, rgb), InputError);
  EXPECT_EQ(test::read_file(dir / "a.png"), before);
  // The rename onto a folder fails after the file was written: its temporary goes too.
  std::filesystem::create_directories(dir / "b.png" / "inside");
  EXPECT_THROW(write_png_rgb(dir / "b.png", 16, 16, rgb), InputError);
  EXPECT_TRUE(std::filesystem::is_directory(dir / "b.png"));
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir),
                          std::filesystem::directory_iterator()),
            2);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cover

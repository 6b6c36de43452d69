#include "cover/io/png.h"

#include <png.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <string>

#include "cover/io/atomic_file.h"
#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"

// Encoding. Each row is filtered with PNG's Up filter (the first row with Sub). The filtered
// image is cut into bands of about kBandBytes, whole rows, and each band is deflated on its own
// and in parallel (zlib level kLevel, raw deflate, no shared dictionary) ending in a sync flush,
// the last band in the stream's end, so the bands concatenate into one deflate stream; their
// adler32 checksums are combined. The bands depend only on the image's size, so the bytes do not
// depend on the thread count. A band whose filtered bytes look random (sampled zero-order
// entropy above kStoredEntropy bits per byte) is stored: coding its literals would save under
// 2 % at ~30 MB/s. libpng writes the chunks (signature, IHDR, one IDAT per band, IEND) and their
// CRCs. The zlib header and trailer around the bands are written here because libpng compresses
// one serial stream at one level: on a 1024² RGB render (bench/png_bench, docs/benchmarks.md
// "PNG writing", 2 loaded cores) its defaults (level 6, adaptive filters) take 0.060 s, level 1
// with the Up filter 0.016 s for about the bands' size (91.6 against 90.0 kB) where the bands
// take 0.011 s; on random noise 0.18 s and 0.12 s against the bands' 0.012 s; and the bands
// scale with the cores.

namespace cover {
namespace {

constexpr size_t kBandBytes = size_t{64} << 10;
constexpr int kLevel = 3;
constexpr double kStoredEntropy = 7.9;

struct FileCloser {
  void operator()(FILE* f) const {
    if (f) std::fclose(f);
  }
};

/// The bytes of row y in PNG order; `scratch` holds them when they need converting.
using RowSource = std::function<const uint8_t*(int y, std::vector<uint8_t>& scratch)>;

struct Band {
  std::vector<uint8_t> deflated;  ///< raw deflate, ending in a sync flush or the final block
  uint32_t adler = 1;             ///< of the filtered bytes
  size_t length = 0;              ///< filtered bytes
};

/// Zero-order entropy in bits per byte of every 4th byte of `bytes` (a sample: the histogram of
/// every byte would cost about a tenth of the whole encoding).
double sampled_entropy(const std::vector<uint8_t>& bytes) {
  std::array<size_t, 256> counts{};
  size_t n = 0;
  for (size_t i = 0; i < bytes.size(); i += 4, ++n) ++counts[bytes[i]];
  double bits = 0;
  for (size_t c : counts)
    if (c) bits -= static_cast<double>(c) * std::log2(static_cast<double>(c) / n);
  return bits / static_cast<double>(n);
}

/// Filters rows [y0, y1) and deflates them; false when zlib fails (out of memory).
bool encode_band(const RowSource& row, size_t row_bytes, int bpp, int y0, int y1, bool last,
                 Band& band) {
  std::vector<uint8_t> filtered((row_bytes + 1) * static_cast<size_t>(y1 - y0));
  std::vector<uint8_t> scratch[2];
  const uint8_t* prev = y0 > 0 ? row(y0 - 1, scratch[(y0 - 1) & 1]) : nullptr;
  for (int y = y0; y < y1; ++y) {
    const uint8_t* cur = row(y, scratch[y & 1]);
    uint8_t* out = filtered.data() + (row_bytes + 1) * static_cast<size_t>(y - y0);
    if (prev) {
      out[0] = 2;  // Up
      for (size_t i = 0; i < row_bytes; ++i) out[1 + i] = static_cast<uint8_t>(cur[i] - prev[i]);
    } else {
      out[0] = 1;  // Sub
      for (size_t i = 0; i < row_bytes; ++i)
        out[1 + i] =
            static_cast<uint8_t>(cur[i] - (i >= static_cast<size_t>(bpp) ? cur[i - bpp] : 0));
    }
    prev = cur;
  }
  band.length = filtered.size();
  band.adler =
      static_cast<uint32_t>(adler32(1, filtered.data(), static_cast<uInt>(filtered.size())));
  const int level = sampled_entropy(filtered) > kStoredEntropy ? 0 : kLevel;
  z_stream z{};
  if (deflateInit2(&z, level, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) != Z_OK) return false;
  band.deflated.resize(deflateBound(&z, filtered.size()) + 16);  // + the sync flush's 5 bytes
  z.next_in = filtered.data();
  z.avail_in = static_cast<uInt>(filtered.size());
  z.next_out = band.deflated.data();
  z.avail_out = static_cast<uInt>(band.deflated.size());
  const int rc = deflate(&z, last ? Z_FINISH : Z_SYNC_FLUSH);
  const bool done = last ? rc == Z_STREAM_END : rc == Z_OK && z.avail_in == 0 && z.avail_out > 0;
  band.deflated.resize(band.deflated.size() - z.avail_out);
  deflateEnd(&z);
  return done;
}

/// Writes the encoded bands through libpng into `file`; returns false on any libpng or I/O error,
/// with the I/O error's errno in `os_error` (0 when none).
bool write_stream(FILE* file, int width, int height, int bit_depth, int color,
                  const std::vector<Band>& bands, int& os_error) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {  // libpng reports errors by longjmp
    os_error = std::ferror(file) ? errno : 0;
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_init_io(png, file);
  png_set_IHDR(png, info, width, height, bit_depth, color, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  // zlib header: deflate with a 32 KiB window, "fastest" level flag, check bits (0x7801 % 31 = 0).
  const uint8_t header[2] = {0x78, 0x01};
  uint32_t adler = 1;
  for (size_t b = 0; b < bands.size(); ++b) {
    adler = b == 0 ? bands[b].adler
                   : static_cast<uint32_t>(adler32_combine(adler, bands[b].adler,
                                                           static_cast<z_off_t>(bands[b].length)));
  }
  const uint8_t trailer[4] = {static_cast<uint8_t>(adler >> 24), static_cast<uint8_t>(adler >> 16),
                              static_cast<uint8_t>(adler >> 8), static_cast<uint8_t>(adler)};
  const png_byte idat[5] = "IDAT";
  for (size_t b = 0; b < bands.size(); ++b) {
    const bool first = b == 0, last = b + 1 == bands.size();
    const size_t length = bands[b].deflated.size() + (first ? 2 : 0) + (last ? 4 : 0);
    png_write_chunk_start(png, idat, static_cast<png_uint_32>(length));
    if (first) png_write_chunk_data(png, header, 2);
    png_write_chunk_data(png, bands[b].deflated.data(), bands[b].deflated.size());
    if (last) png_write_chunk_data(png, trailer, 4);
    png_write_chunk_end(png);
  }
  const png_byte iend[5] = "IEND";
  png_write_chunk(png, iend, nullptr, 0);
  png_destroy_write_struct(&png, &info);
  if (std::fflush(file) == 0 && !std::ferror(file)) return true;
  os_error = errno;
  return false;
}

/// write_stream() into a new file `tmp`.
bool write_file(const std::filesystem::path& tmp, int width, int height, int bit_depth, int color,
                const std::vector<Band>& bands, int& os_error) {
  errno = 0;
  std::unique_ptr<FILE, FileCloser> file(std::fopen(tmp.c_str(), "wb"));
  if (!file) {
    os_error = errno;
    return false;
  }
  return write_stream(file.get(), width, height, bit_depth, color, bands, os_error);
}

/// The image's filtered rows deflated in bands (the header comment); `name` names it in errors.
std::vector<Band> encode_bands(const std::string& name, int width, int height, int bpp, size_t have,
                               size_t need, const RowSource& row) {
  if (width <= 0 || height <= 0) throw InputError(name + ": empty image");
  if (have < need)
    throw InputError(name + ": " + std::to_string(have) + " samples for a " +
                     std::to_string(width) + "x" + std::to_string(height) + " image (" +
                     std::to_string(need) + " needed)");
  const size_t row_bytes = static_cast<size_t>(width) * bpp;
  const int band_rows =
      static_cast<int>(std::min<size_t>(height, std::max<size_t>(1, kBandBytes / (row_bytes + 1))));
  std::vector<Band> bands(static_cast<size_t>((height + band_rows - 1) / band_rows));
  std::atomic<bool> compressed = true;
  parallel_for(bands.size(), 1, [&](size_t begin, size_t end) {
    for (size_t b = begin; b < end; ++b) {
      const int y0 = static_cast<int>(b) * band_rows;
      if (!encode_band(row, row_bytes, bpp, y0, std::min(height, y0 + band_rows),
                       b + 1 == bands.size(), bands[b]))
        compressed = false;
    }
  });
  if (!compressed) throw InputError(name + ": cannot write PNG (out of memory)");
  return bands;
}

void write_atomic(const std::filesystem::path& path, int width, int height, int bit_depth,
                  int color, int bpp, size_t have, size_t need, const RowSource& row) {
  check_png_path(path);
  const std::vector<Band> bands = encode_bands(path.string(), width, height, bpp, have, need, row);
  int os_error = 0;
  try {
    write_atomically(
        path,
        [&](const std::filesystem::path& tmp) {
          return write_file(tmp, width, height, bit_depth, color, bands, os_error);
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
  const size_t row_bytes = 3 * static_cast<size_t>(std::max(0, width));
  write_atomic(path, width, height, 8, PNG_COLOR_TYPE_RGB, 3, rgb.size(),
               row_bytes * static_cast<size_t>(std::max(0, height)),
               [&](int y, std::vector<uint8_t>&) { return rgb.data() + row_bytes * y; });
}

std::vector<uint8_t> encode_png_rgb(int width, int height, std::span<const uint8_t> rgb) {
  const size_t row_bytes = 3 * static_cast<size_t>(std::max(0, width));
  const std::vector<Band> bands =
      encode_bands("PNG", width, height, 3, rgb.size(), row_bytes * std::max(0, height),
                   [&](int y, std::vector<uint8_t>&) { return rgb.data() + row_bytes * y; });
  // The same bytes as write_png_rgb's file, through a memory stream (POSIX open_memstream).
  char* data = nullptr;
  size_t size = 0;
  FILE* stream = open_memstream(&data, &size);
  if (!stream) throw InputError("PNG: cannot encode (out of memory)");
  int os_error = 0;
  const bool ok = write_stream(stream, width, height, 8, PNG_COLOR_TYPE_RGB, bands, os_error);
  std::fclose(stream);  // sets data and size
  std::vector<uint8_t> out;
  if (ok) out.assign(data, data + size);
  std::free(data);
  if (!ok) throw InputError("PNG: cannot encode (out of memory)");
  return out;
}

void write_png_gray16(const std::filesystem::path& path, int width, int height,
                      std::span<const uint16_t> values) {
  const size_t w = static_cast<size_t>(std::max(0, width));
  write_atomic(path, width, height, 16, PNG_COLOR_TYPE_GRAY, 2, values.size(),
               w * static_cast<size_t>(std::max(0, height)),
               [&](int y, std::vector<uint8_t>& scratch) {
                 scratch.resize(2 * w);
                 const uint16_t* v = values.data() + w * y;
                 for (size_t x = 0; x < w; ++x) {  // PNG stores 16-bit samples big-endian
                   scratch[2 * x] = static_cast<uint8_t>(v[x] >> 8);
                   scratch[2 * x + 1] = static_cast<uint8_t>(v[x] & 0xff);
                 }
                 return static_cast<const uint8_t*>(scratch.data());
               });
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

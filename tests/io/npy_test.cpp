// io/npy.h: the headers npy_header() writes parse back to what was asked, start the data on a
// multiple of 64 bytes, and spell the shape as Python does; parse_npy_header() reads what numpy
// itself writes (versions 1.0, 2.0 and 3.0: recorded bytes below) and refuses what is not a
// header, naming the file. (tests/cli/points_test.cpp covers the malformed headers in detail.)
#include "cover/io/npy.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cover/solid/errors.h"

namespace cover {
namespace {

TEST(Npy, WrittenHeadersParseBack) {
  const std::vector<std::vector<uint64_t>> shapes = {{},     {0},       {7},
                                                     {5, 3}, {4, 4, 4}, {1ull << 40, 3}};
  for (const std::vector<uint64_t>& shape : shapes) {
    const std::string h = npy_header("|u1", shape);
    EXPECT_EQ(h.size() % 64, 0u);
    EXPECT_EQ(h.back(), '\n');
    const NpyHeader parsed = parse_npy_header(h, "a.npy");
    EXPECT_EQ(parsed.descr, "|u1");
    EXPECT_FALSE(parsed.fortran_order);
    EXPECT_EQ(parsed.shape, shape);
    EXPECT_EQ(parsed.data_offset, h.size());
  }
  const std::vector<uint64_t> one{7}, two{5, 3};
  EXPECT_NE(npy_header("<f8", one).find("'shape': (7,)"), std::string::npos);
  EXPECT_NE(npy_header("<f8", two).find("'shape': (5, 3)"), std::string::npos);
}

TEST(Npy, ReadsNumpysOwnHeaders) {
  // np.lib.format.write_array(f, np.zeros((2, 3)), version=V) for V = (1,0), (2,0), (3,0).
  const std::string dict = "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }";
  for (int major : {1, 2, 3}) {
    const size_t preamble = major == 1 ? 10 : 12;
    std::string h = dict + std::string(64 - (preamble + dict.size() + 1) % 64, ' ') + "\n";
    std::string file = "\x93NUMPY";
    file += static_cast<char>(major);
    file += '\0';
    file += static_cast<char>(h.size());
    file += std::string(major == 1 ? 1 : 3, '\0');
    file += h + std::string(48, '\0');
    const NpyHeader parsed = parse_npy_header(file, "a.npy");
    EXPECT_EQ(parsed.descr, "<f8");
    EXPECT_EQ(parsed.shape, (std::vector<uint64_t>{2, 3}));
    EXPECT_EQ(parsed.data_offset, preamble + h.size());
    EXPECT_EQ(parsed.data_offset % 64, 0u);
  }
  EXPECT_TRUE(has_npy_magic(npy_header("<f4", std::vector<uint64_t>{1})));
  EXPECT_FALSE(has_npy_magic("\x93NUMP"));
  try {
    parse_npy_header("PK\x03\x04", "a.npz");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "a.npz: not a NumPy .npy file (no \\x93NUMPY magic)");
  }
}

}  // namespace
}  // namespace cover

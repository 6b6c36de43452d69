#pragma once
// NumPy .npy headers (numpy.lib.format, versions 1.0, 2.0 and 3.0), shared by the writers
// (io/voxel_io.cpp voxel grids, the classes of `cover classify --output`) and the reader of
// `cover classify --points FILE.npy` (cli/points.cpp). Layout of a file:
//   magic      6 bytes "\x93NUMPY"
//   version    2 bytes major, minor: 1.0 (header length uint16), 2.0 / 3.0 (uint32; 3.0: the
//              header text is UTF-8 instead of Latin-1), both little-endian
//   header     a Python dict literal {'descr': DTYPE, 'fortran_order': BOOL, 'shape': (D0, ...)}
//              padded with blanks and ended by '\n'; the writers pad so that the data starts at a
//              multiple of 64 bytes
//   data       the array's elements, C order (last index fastest) unless fortran_order

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace cover {

/// What an .npy header declares.
struct NpyHeader {
  std::string descr;            ///< the dtype string as written, e.g. "<f8", ">f4", "|u1"
  bool fortran_order = false;   ///< true: column-major data (first index fastest)
  std::vector<uint64_t> shape;  ///< one extent per axis; empty for a 0-d array
  size_t data_offset = 0;       ///< byte offset of the first element in the file
};

/// The preamble and header of a version 1.0 file (magic, version, header length, dict padded
/// to a multiple of 64 bytes) for a C-order array of dtype `descr` and `shape`; the data follows
/// directly. Precondition: the header fits in 65535 bytes (any descr of a few characters and
/// up to 32 axes do).
std::string npy_header(std::string_view descr, std::span<const uint64_t> shape);

/// True when `data` starts with the .npy magic "\x93NUMPY".
bool has_npy_magic(std::string_view data);

/// Parses the header at the start of `data` (a file's bytes, at least the header). The dict
/// must hold exactly the keys descr (a string), fortran_order (True / False) and shape (a tuple
/// of whole numbers), in any order, with Python's quoting, blanks and trailing commas.
/// \throws InputError "FILE: ..." (`file` verbatim) for a missing magic, an unsupported version,
/// a header longer than the data, or a header that is not such a dict; the message says which.
NpyHeader parse_npy_header(std::string_view data, const std::string& file);

}  // namespace cover

#include "cover/io/npy.h"

#include <charconv>

#include "cover/io/parse.h"
#include "cover/solid/errors.h"

namespace cover {
namespace {

constexpr std::string_view kMagic("\x93NUMPY", 6);

/// The header dict of an .npy file, read left to right; every failure names the file.
class HeaderParser {
 public:
  HeaderParser(std::string_view text, const std::string& file) : text_(text), file_(file) {}

  NpyHeader parse() {
    NpyHeader h;
    bool seen[3] = {false, false, false};
    expect('{');
    while (!take('}')) {
      const std::string key = string("a key");
      expect(':');
      if (key == "descr") {
        h.descr = string("a dtype string for 'descr'");
        seen[0] = true;
      } else if (key == "fortran_order") {
        h.fortran_order = boolean();
        seen[1] = true;
      } else if (key == "shape") {
        h.shape = tuple();
        seen[2] = true;
      } else {
        fail("unexpected key " + detail::quote(key));
      }
      if (!take(',')) {
        expect('}');
        break;
      }
    }
    skip_blanks();
    if (pos_ != text_.size())
      fail("unexpected " + detail::quote(text_.substr(pos_)) + " after the dict");
    for (int k = 0; k < 3; ++k)
      if (!seen[k])
        fail(std::string("missing key '") +
             (k == 0   ? "descr"
              : k == 1 ? "fortran_order"
                       : "shape") +
             "'");
    return h;
  }

 private:
  [[noreturn]] void fail(const std::string& message) const {
    detail::fail_file(file_, ".npy header: " + message);
  }

  void skip_blanks() {
    while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\t' ||
                                   text_[pos_] == '\n' || text_[pos_] == '\r'))
      ++pos_;
  }
  /// The rest of the header from the current position, for messages.
  std::string found() const {
    return pos_ < text_.size() ? detail::quote(text_.substr(pos_)) : "the end of the header";
  }
  bool take(char c) {
    skip_blanks();
    if (pos_ < text_.size() && text_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  void expect(char c) {
    if (!take(c)) fail(std::string("expected '") + c + "', found " + found());
  }

  /// A quoted Python string without escapes ('...' or "...").
  std::string string(const std::string& what) {
    skip_blanks();
    const char quote = pos_ < text_.size() ? text_[pos_] : '\0';
    if (quote != '\'' && quote != '"') fail("expected " + what + ", found " + found());
    const size_t end = text_.find(quote, pos_ + 1);
    if (end == std::string_view::npos) fail("unterminated string " + found());
    const std::string_view s = text_.substr(pos_ + 1, end - pos_ - 1);
    if (s.find('\\') != std::string_view::npos) fail("unsupported escape in " + detail::quote(s));
    pos_ = end + 1;
    return std::string(s);
  }

  bool boolean() {
    skip_blanks();
    for (const std::string_view word : {std::string_view("True"), std::string_view("False")})
      if (text_.substr(pos_).starts_with(word)) {
        pos_ += word.size();
        return word == "True";
      }
    fail("expected True or False for 'fortran_order', found " + found());
  }

  /// A tuple of whole numbers: "()", "(7,)", "(7, 3)", trailing comma optional.
  std::vector<uint64_t> tuple() {
    std::vector<uint64_t> values;
    expect('(');
    while (!take(')')) {
      skip_blanks();
      uint64_t v = 0;
      const char* begin = text_.data() + pos_;
      const auto [end, ec] = std::from_chars(begin, text_.data() + text_.size(), v);
      if (ec == std::errc::result_out_of_range) fail("shape extent " + found() + " is too large");
      if (ec != std::errc() || end == begin)
        fail("expected a whole number in 'shape', found " + found());
      pos_ += static_cast<size_t>(end - begin);
      values.push_back(v);
      if (!take(',')) {
        expect(')');
        break;
      }
    }
    return values;
  }

  std::string_view text_;
  const std::string& file_;
  size_t pos_ = 0;
};

}  // namespace

std::string npy_header(std::string_view descr, std::span<const uint64_t> shape) {
  std::string dims;
  for (const uint64_t d : shape) dims += std::to_string(d) + ", ";
  if (shape.size() > 1)
    dims.resize(dims.size() - 2);  // "(7,)" but "(7, 3)"
  else if (shape.size() == 1)
    dims.pop_back();
  std::string header =
      "{'descr': '" + std::string(descr) + "', 'fortran_order': False, 'shape': (" + dims + "), }";
  constexpr size_t kPreamble = 10;  // magic (6) + version (2) + header length (2)
  header.append((64 - (kPreamble + header.size() + 1) % 64) % 64, ' ');
  header += '\n';
  if (header.size() > 0xFFFF) throw PreconditionError("npy_header: header over 65535 bytes");
  const auto length = static_cast<uint16_t>(header.size());
  std::string out(kMagic);
  out += '\x01';
  out += '\x00';
  out += static_cast<char>(length & 0xff);
  out += static_cast<char>(length >> 8);
  return out + header;
}

bool has_npy_magic(std::string_view data) { return data.starts_with(kMagic); }

NpyHeader parse_npy_header(std::string_view data, const std::string& file) {
  if (!has_npy_magic(data)) detail::fail_file(file, "not a NumPy .npy file (no \\x93NUMPY magic)");
  if (data.size() < 8) detail::fail_file(file, "truncated .npy file (no version)");
  const auto major = static_cast<unsigned char>(data[6]);
  const auto minor = static_cast<unsigned char>(data[7]);
  if (minor != 0 || major < 1 || major > 3)
    detail::fail_file(file, "unsupported .npy version " + std::to_string(major) + "." +
                                std::to_string(minor) + " (expected 1.0, 2.0 or 3.0)");
  const size_t length_bytes = major == 1 ? 2 : 4;
  if (data.size() < 8 + length_bytes)
    detail::fail_file(file, "truncated .npy file (no header length)");
  uint64_t length = 0;
  for (size_t i = 0; i < length_bytes; ++i)
    length |= static_cast<uint64_t>(static_cast<unsigned char>(data[8 + i])) << (8 * i);
  const size_t start = 8 + length_bytes;
  if (length > data.size() - start)
    detail::fail_file(file, "truncated .npy header (" + std::to_string(length) +
                                " bytes declared, " + std::to_string(data.size() - start) +
                                " in the file)");
  NpyHeader h = HeaderParser(data.substr(start, length), file).parse();
  h.data_offset = start + length;
  return h;
}

}  // namespace cover

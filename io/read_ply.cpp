// PLY reader (Stanford polygon format): ascii, binary_little_endian and binary_big_endian.
// Header (text, one statement per line; a UTF-8 byte order mark may precede "ply"):
//   ply
//   format <ascii|binary_little_endian|binary_big_endian> <version>
//   comment ... | obj_info ...
//   any other line before the first element: free text, read as a comment (Blender 2.4x writes
//   "Created by Blender3D ..." without the comment keyword); after it, an unknown keyword is an
//   error (a misspelt "property" would otherwise shift every value after it)
//   element <name> <count>
//   property <type> <name>                       scalar
//   property list <count type> <item type> <name>
//   end_header
// Types: char/int8 uchar/uint8 short/int16 ushort/uint16 int/int32 uint/uint32 float/float32
// double/float64. Used: element "vertex" (scalar x, y, z of any type) and element "face" (list
// "vertex_indices" or "vertex_index" with integer count and item types, 0-based indices, >= 3
// per face). Every other property and element is read past. Before anything is reserved the
// counts are checked against the body size: an instance takes at least the sum of its scalar
// sizes and list-count sizes (binary) or 2 bytes per token (ascii), and a face at least 3 indices.
// Errors: "FILE:LINE: ..." in the header and in an ascii body, "FILE: byte N: ..." in a binary
// body (N counted from the start of the file).

#include <bit>
#include <string>
#include <vector>

#include "cover/io/parse.h"

namespace cover::detail {
namespace {

enum class Type : uint8_t { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };
enum class Format : uint8_t { kAscii, kBinaryLittle, kBinaryBig };
/// What a property is used for.
enum class Role : uint8_t { kX, kY, kZ, kIndices, kSkip };

struct Property {
  std::string name;
  Type type = Type::kFloat32;  ///< scalar type, or the item type of a list
  bool is_list = false;
  Type count_type = Type::kUint8;  ///< lists only
  Role role = Role::kSkip;
};

struct Element {
  std::string name;
  uint64_t count = 0;
  uint64_t line = 0;  ///< header line of the declaration
  std::vector<Property> properties;
};

struct Header {
  Format format = Format::kAscii;
  std::vector<Element> elements;
  uint64_t body_offset = 0;  ///< byte where the data starts
  uint64_t body_line = 0;    ///< line number of the first body line (ascii)
};

size_t type_size(Type t) {
  constexpr size_t kSizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
  return kSizes[static_cast<int>(t)];
}

bool is_integer(Type t) { return t != Type::kFloat32 && t != Type::kFloat64; }

bool parse_type(std::string_view name, Type& type) {
  struct Named {
    std::string_view name;
    Type type;
  };
  static constexpr Named kNames[] = {
      {"char", Type::kInt8},      {"int8", Type::kInt8},       {"uchar", Type::kUint8},
      {"uint8", Type::kUint8},    {"short", Type::kInt16},     {"int16", Type::kInt16},
      {"ushort", Type::kUint16},  {"uint16", Type::kUint16},   {"int", Type::kInt32},
      {"int32", Type::kInt32},    {"uint", Type::kUint32},     {"uint32", Type::kUint32},
      {"float", Type::kFloat32},  {"float32", Type::kFloat32}, {"double", Type::kFloat64},
      {"float64", Type::kFloat64}};
  for (const Named& named : kNames)
    if (named.name == name) {
      type = named.type;
      return true;
    }
  return false;
}

Type expect_type(std::string_view token, const std::string& file, uint64_t line) {
  Type type;
  if (!parse_type(token, type)) fail_line(file, line, "unknown PLY property type " + quote(token));
  return type;
}

Header parse_header(const std::string& file, std::string_view data) {
  LineReader lines(data);
  std::string_view line;
  const bool first = lines.next(line);
  line = without_bom(line);  // byte offsets stay counted from the start of the file
  if (!first || next_token(line) != "ply" || !only_blanks(line))
    fail_line(file, 1, "not a PLY file (the first line must be 'ply')");
  Header header;
  bool has_format = false;
  for (;;) {
    if (!lines.next(line))
      fail_line(file, lines.line_number(), "unexpected end of file: no end_header");
    const uint64_t n = lines.line_number();
    std::string_view keyword = next_token(line);
    if (keyword == "end_header") break;
    if (keyword.empty() || keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "format") {
      std::string_view name = next_token(line);
      if (has_format) fail_line(file, n, "duplicate format line");
      if (name == "ascii")
        header.format = Format::kAscii;
      else if (name == "binary_little_endian")
        header.format = Format::kBinaryLittle;
      else if (name == "binary_big_endian")
        header.format = Format::kBinaryBig;
      else
        fail_line(file, n, "unknown PLY format " + quote(name));
      has_format = true;
    } else if (keyword == "element") {
      Element element;
      element.name = std::string(next_token(line));
      std::string_view count = next_token(line);
      if (element.name.empty() || !parse_integer(count, element.count) || !only_blanks(line))
        fail_line(file, n, "expected 'element <name> <count>'");
      for (const Element& other : header.elements)
        if (other.name == element.name)
          fail_line(file, n, "duplicate element " + quote(element.name));
      element.line = n;
      header.elements.push_back(std::move(element));
    } else if (keyword == "property") {
      if (header.elements.empty()) fail_line(file, n, "property before any element");
      Property property;
      std::string_view type = next_token(line);
      if (type == "list") {
        property.is_list = true;
        property.count_type = expect_type(next_token(line), file, n);
        if (!is_integer(property.count_type))
          fail_line(file, n, "list count type must be an integer type");
        type = next_token(line);
      }
      property.type = expect_type(type, file, n);
      property.name = std::string(next_token(line));
      if (property.name.empty() || !only_blanks(line))
        fail_line(file, n, "expected 'property [list <count type>] <type> <name>'");
      for (const Property& other : header.elements.back().properties)
        if (other.name == property.name)
          fail_line(file, n, "duplicate property " + quote(property.name));
      header.elements.back().properties.push_back(std::move(property));
    } else if (header.elements.empty()) {
      continue;  // free text before the first element, read as a comment (Blender 2.4x writes
                 // "Created by Blender3D ..." there without the comment keyword)
    } else {
      fail_line(file, n, "unknown PLY header keyword " + quote(keyword));
    }
  }
  if (!has_format) fail_line(file, lines.line_number(), "missing format line");
  header.body_offset = data.size() - lines.bytes_left();
  header.body_line = lines.line_number() + 1;
  return header;
}

/// Assigns roles, checks the vertex and face elements and that every count fits in the body.
void check_header(const std::string& file, Header& header, uint64_t body_bytes, uint64_t end_line) {
  Element* vertex = nullptr;
  Element* face = nullptr;
  for (Element& element : header.elements) {
    if (element.name == "vertex") vertex = &element;
    if (element.name == "face") face = &element;
  }
  if (face == nullptr || face->count == 0) fail_file(file, "no faces");
  if (vertex == nullptr) fail_line(file, end_line, "no vertex element");
  if (vertex->count > kMaxIndexCount)
    fail_line(file, vertex->line,
              "vertex count " + std::to_string(vertex->count) + " exceeds 2^32-1");
  int found = 0;
  for (Property& p : vertex->properties) {
    Role role = p.name == "x"   ? Role::kX
                : p.name == "y" ? Role::kY
                : p.name == "z" ? Role::kZ
                                : Role::kSkip;
    if (role == Role::kSkip) continue;
    if (p.is_list) fail_line(file, vertex->line, "vertex property " + quote(p.name) + " is a list");
    p.role = role;
    ++found;
  }
  if (found != 3) fail_line(file, vertex->line, "vertex element needs properties x, y and z");
  Property* indices = nullptr;
  for (Property& p : face->properties)
    if (p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index") && indices == nullptr)
      indices = &p;
  if (indices == nullptr)
    fail_line(file, face->line, "face element needs a list property vertex_indices");
  if (!is_integer(indices->type))
    fail_line(file, face->line, "vertex_indices must have an integer item type");
  indices->role = Role::kIndices;

  const bool ascii = header.format == Format::kAscii;
  uint64_t left = ascii ? body_bytes + 1 : body_bytes;  // the last ascii token needs no separator
  for (const Element& element : header.elements) {
    uint64_t unit = 0;
    for (const Property& p : element.properties) {
      const size_t items = p.role == Role::kIndices ? 3 : 0;
      if (ascii)
        unit += 2 * (1 + items);
      else
        unit += p.is_list ? type_size(p.count_type) + items * type_size(p.type) : type_size(p.type);
    }
    if (!fits(element.count, unit, left))
      fail_line(file, element.line,
                "element " + quote(element.name) + " with " + std::to_string(element.count) +
                    " entries cannot fit in the " + std::to_string(body_bytes) + "-byte body");
    left -= element.count * unit;
  }
}

template <typename Unsigned>
Unsigned load_unsigned(const char* bytes, bool swap) {
  Unsigned value;
  std::memcpy(&value, bytes, sizeof value);
  if (swap) {
    if constexpr (sizeof value == 2) value = __builtin_bswap16(value);
    if constexpr (sizeof value == 4) value = __builtin_bswap32(value);
    if constexpr (sizeof value == 8) value = __builtin_bswap64(value);
  }
  return value;
}

/// Reads a binary value of any type `t` as a double (integers through load_int).
double load_double(const char* bytes, Type t, bool swap);

/// Reads a binary value of integer type `t`.
int64_t load_int(const char* bytes, Type t, bool swap) {
  switch (t) {
    case Type::kInt8:
      return static_cast<int8_t>(bytes[0]);
    case Type::kUint8:
      return static_cast<uint8_t>(bytes[0]);
    case Type::kInt16:
      return static_cast<int16_t>(load_unsigned<uint16_t>(bytes, swap));
    case Type::kUint16:
      return load_unsigned<uint16_t>(bytes, swap);
    case Type::kInt32:
      return static_cast<int32_t>(load_unsigned<uint32_t>(bytes, swap));
    default:
      return load_unsigned<uint32_t>(bytes, swap);  // kUint32; floats are refused earlier
  }
}

/// Reads a binary value of any type `t` as a double (integers through load_int).
double load_double(const char* bytes, Type t, bool swap) {
  switch (t) {
    case Type::kFloat32:
      return std::bit_cast<float>(load_unsigned<uint32_t>(bytes, swap));
    case Type::kFloat64:
      return std::bit_cast<double>(load_unsigned<uint64_t>(bytes, swap));
    default:
      return static_cast<double>(load_int(bytes, t, swap));
  }
}

/// Shared state while reading the body.
struct Body {
  const std::string& file;
  std::string_view data;
  uint64_t vertex_count;
  PolygonMesh& mesh;
};

std::string instance_name(const Element& element, uint64_t i) {
  return "element " + quote(element.name) + " entry " + std::to_string(i);
}

/// Binary body: a bounds-checked cursor.
class BinaryBody {
 public:
  BinaryBody(Body body, uint64_t offset, bool swap) : body_(body), pos_(offset), swap_(swap) {}

  void read(const Element& element) {
    bool fixed = true;
    uint64_t record = 0;
    for (const Property& p : element.properties) {
      fixed = fixed && !p.is_list && p.role == Role::kSkip;
      record += type_size(p.type);
    }
    if (element.name != "vertex" && fixed) {  // skip all entries at once
      take(element.count * record, element, 0);
      return;
    }
    for (uint64_t i = 0; i < element.count; ++i) read_instance(element, i);
  }

  uint64_t position() const { return pos_; }

 private:
  const char* take(uint64_t bytes, const Element& element, uint64_t i) {
    if (bytes > body_.data.size() - pos_)
      fail_byte(body_.file, pos_,
                "unexpected end of file in " + instance_name(element, i) + " (need " +
                    std::to_string(bytes) + " bytes, " + std::to_string(body_.data.size() - pos_) +
                    " left)");
    const char* at = body_.data.data() + pos_;
    pos_ += bytes;
    return at;
  }

  void read_instance(const Element& element, uint64_t i) {
    Vec3 p;
    for (const Property& prop : element.properties) {
      const uint64_t at = pos_;
      if (!prop.is_list) {
        const char* bytes = take(type_size(prop.type), element, i);
        if (prop.role == Role::kSkip) continue;
        double value = load_double(bytes, prop.type, swap_);
        if (!std::isfinite(value))
          fail_byte(body_.file, at,
                    "non-finite " + prop.name + " coordinate of vertex " + std::to_string(i));
        (prop.role == Role::kX ? p.x : prop.role == Role::kY ? p.y : p.z) = value;
        continue;
      }
      const int64_t count =
          load_int(take(type_size(prop.count_type), element, i), prop.count_type, swap_);
      if (count < 0)
        fail_byte(body_.file, at, "negative list size in " + instance_name(element, i));
      const size_t item = type_size(prop.type);
      const char* items = take(static_cast<uint64_t>(count) * item, element, i);
      if (prop.role != Role::kIndices) continue;
      if (count < 3)
        fail_byte(body_.file, at,
                  "face " + std::to_string(i) + " has " + std::to_string(count) +
                      " vertices (at least 3 needed)");
      for (int64_t k = 0; k < count; ++k) {
        const int64_t index = load_int(items + k * item, prop.type, swap_);
        if (index < 0 || static_cast<uint64_t>(index) >= body_.vertex_count)
          fail_byte(body_.file, at + type_size(prop.count_type) + k * item,
                    "vertex index " + std::to_string(index) + " of face " + std::to_string(i) +
                        " out of range [0, " + std::to_string(body_.vertex_count) + ")");
        body_.mesh.face_vertices.push_back(static_cast<uint32_t>(index));
      }
      if (body_.mesh.face_vertices.size() > kMaxIndexCount)
        fail_byte(body_.file, at, "more than 2^32-1 face vertices in total");
      body_.mesh.face_start.push_back(static_cast<uint32_t>(body_.mesh.face_vertices.size()));
    }
    if (element.name == "vertex") body_.mesh.vertices.push_back(p);
  }

  Body body_;
  uint64_t pos_;
  bool swap_;
};

/// ASCII body: blank- and newline-separated tokens with line numbers.
class AsciiBody {
 public:
  AsciiBody(Body body, uint64_t offset, uint64_t line) : body_(body), pos_(offset), line_(line) {}

  void read(const Element& element) {
    if (element.properties.empty()) return;
    for (uint64_t i = 0; i < element.count; ++i) read_instance(element, i);
  }

  /// Fails when a token is left after the last element.
  void expect_end() {
    std::string_view token = next();
    if (!token.empty())
      fail_line(body_.file, line_,
                "unexpected data after the last element " + quote(token) + " (wrong counts?)");
  }

 private:
  std::string_view next() {
    const std::string_view data = body_.data;
    while (pos_ < data.size() && (is_blank(data[pos_]) || data[pos_] == '\n')) {
      if (data[pos_] == '\n') ++line_;
      ++pos_;
    }
    const size_t start = pos_;
    while (pos_ < data.size() && !is_blank(data[pos_]) && data[pos_] != '\n') ++pos_;
    return data.substr(start, pos_ - start);
  }

  std::string_view need(const Element& element, uint64_t i) {
    std::string_view token = next();
    if (token.empty())
      fail_line(body_.file, line_, "unexpected end of file in " + instance_name(element, i));
    return token;
  }

  int64_t need_integer(const Element& element, uint64_t i) {
    std::string_view token = need(element, i);
    int64_t value;
    if (!parse_integer(token, value))
      fail_line(body_.file, line_,
                "expected an integer in " + instance_name(element, i) + ", found " + quote(token));
    return value;
  }

  /// A value that is read past must still be a number.
  void check_number(std::string_view token, const Element& element, uint64_t i) {
    double ignored;
    const NumberStatus status = parse_number(token, ignored);
    if (status == NumberStatus::kOutOfRange)
      fail_line(body_.file, line_,
                "out-of-range number in " + instance_name(element, i) + ": " + quote(token));
    if (status == NumberStatus::kNotANumber)
      fail_line(body_.file, line_,
                "expected a number in " + instance_name(element, i) + ", found " + quote(token));
  }

  void read_instance(const Element& element, uint64_t i) {
    Vec3 p;
    for (const Property& prop : element.properties) {
      if (!prop.is_list) {
        std::string_view token = need(element, i);
        if (prop.role == Role::kSkip) {
          check_number(token, element, i);
          continue;
        }
        const char axis = prop.role == Role::kX ? 'x' : prop.role == Role::kY ? 'y' : 'z';
        (axis == 'x'   ? p.x
         : axis == 'y' ? p.y
                       : p.z) = parse_coordinate(token, body_.file, line_, axis);
        continue;
      }
      const int64_t count = need_integer(element, i);
      if (count < 0)
        fail_line(body_.file, line_, "negative list size in " + instance_name(element, i));
      if (prop.role == Role::kIndices && count < 3)
        fail_line(body_.file, line_,
                  "face " + std::to_string(i) + " has " + std::to_string(count) +
                      " vertices (at least 3 needed)");
      for (int64_t k = 0; k < count; ++k) {
        if (prop.role != Role::kIndices) {
          check_number(need(element, i), element, i);
          continue;
        }
        const int64_t index = need_integer(element, i);
        if (index < 0 || static_cast<uint64_t>(index) >= body_.vertex_count)
          fail_line(body_.file, line_,
                    "vertex index " + std::to_string(index) + " of face " + std::to_string(i) +
                        " out of range [0, " + std::to_string(body_.vertex_count) + ")");
        body_.mesh.face_vertices.push_back(static_cast<uint32_t>(index));
      }
      if (prop.role != Role::kIndices) continue;
      if (body_.mesh.face_vertices.size() > kMaxIndexCount)
        fail_line(body_.file, line_, "more than 2^32-1 face vertices in total");
      body_.mesh.face_start.push_back(static_cast<uint32_t>(body_.mesh.face_vertices.size()));
    }
    if (element.name == "vertex") body_.mesh.vertices.push_back(p);
  }

  Body body_;
  uint64_t pos_;
  uint64_t line_;
};

}  // namespace

PolygonMesh read_ply(const std::string& file, std::string_view data) {
  Header header = parse_header(file, data);
  const uint64_t body_bytes = data.size() - header.body_offset;
  check_header(file, header, body_bytes, header.body_line - 1);
  PolygonMesh mesh;
  uint64_t vertex_count = 0;
  for (const Element& element : header.elements) {
    if (element.name == "vertex") {
      vertex_count = element.count;
      mesh.vertices.reserve(element.count);
    } else if (element.name == "face") {
      mesh.face_start.reserve(element.count + 1);
      mesh.face_vertices.reserve(3 * element.count);
    }
  }
  Body body{file, data, vertex_count, mesh};
  if (header.format == Format::kAscii) {
    AsciiBody ascii(body, header.body_offset, header.body_line);
    for (const Element& element : header.elements) ascii.read(element);
    ascii.expect_end();
    return mesh;
  }
  const bool big = header.format == Format::kBinaryBig;
  BinaryBody binary(body, header.body_offset, big != (std::endian::native == std::endian::big));
  for (const Element& element : header.elements) binary.read(element);
  if (binary.position() != data.size())
    fail_byte(file, binary.position(),
              std::to_string(data.size() - binary.position()) +
                  " bytes after the last element (wrong counts?)");
  return mesh;
}

}  // namespace cover::detail

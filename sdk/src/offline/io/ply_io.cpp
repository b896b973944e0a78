// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Stanford PLY reader (ascii, binary little- and big-endian) with line- or element-accurate
// errors. Every read is bounds-checked and every declared count is compared with the bytes that
// are actually there before anything is reserved, so a lying header cannot cause a huge
// allocation or an out-of-bounds read.
#include "dermis/offline/io/ply_io.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <utility>
#include <vector>

#include "dermis/core/file_io.h"
#include "offline/io/text_tokens.h"

namespace dermis {
namespace {

enum class Format { kAscii, kBinaryLittleEndian, kBinaryBigEndian };

enum class Type { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

struct TypeName {
  const char* name;
  Type type;
};

// Both the original PLY names and the sized aliases used by newer writers.
constexpr TypeName kTypeNames[] = {
    {"char", Type::kInt8},       {"int8", Type::kInt8},       {"uchar", Type::kUint8},
    {"uint8", Type::kUint8},     {"short", Type::kInt16},     {"int16", Type::kInt16},
    {"ushort", Type::kUint16},   {"uint16", Type::kUint16},   {"int", Type::kInt32},
    {"int32", Type::kInt32},     {"uint", Type::kUint32},     {"uint32", Type::kUint32},
    {"float", Type::kFloat32},   {"float32", Type::kFloat32}, {"double", Type::kFloat64},
    {"float64", Type::kFloat64},
};

bool ParseType(std::string_view s, Type* type) {
  for (const TypeName& t : kTypeNames) {
    if (s == t.name) {
      *type = t.type;
      return true;
    }
  }
  return false;
}

size_t TypeSize(Type t) {
  switch (t) {
    case Type::kInt8:
    case Type::kUint8:
      return 1;
    case Type::kInt16:
    case Type::kUint16:
      return 2;
    case Type::kInt32:
    case Type::kUint32:
    case Type::kFloat32:
      return 4;
    case Type::kFloat64:
      return 8;
  }
  return 1;
}

bool IsFloatType(Type t) { return t == Type::kFloat32 || t == Type::kFloat64; }

struct Property {
  std::string name;
  bool is_list = false;
  Type type = Type::kFloat32;      // The scalar type, or the type of a list's items.
  Type count_type = Type::kUint8;  // Lists only.
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
  int line = 0;  // The header line that declares the element.
};

// What the body parsers need to know, resolved from the header.
struct Header {
  Format format = Format::kAscii;
  std::vector<Element> elements;
  size_t body_offset = 0;   // First byte after the end_header line.
  int end_header_line = 0;  // 1-based line number of the end_header line.
  int vertex_element = -1;
  int face_element = -1;
  int axis_property[3] = {-1, -1, -1};  // Indices of x, y, z in the vertex element.
  int face_list_property = -1;          // Index of vertex_indices in the face element.
};

using text::IsSpace;
using text::ParseDouble;
using text::ParseInt;
using text::Tokenize;
using text::TrimRight;

// Returns the line that starts at *pos (without its '\n') and moves *pos past the '\n'.
std::string_view NextLine(std::string_view text, size_t* pos) {
  size_t end = text.find('\n', *pos);
  if (end == std::string_view::npos) end = text.size();
  const std::string_view line = text.substr(*pos, end - *pos);
  *pos = end < text.size() ? end + 1 : end;
  return line;
}

bool ParseCount(std::string_view s, std::uint64_t* out) {
  const auto res = std::from_chars(s.data(), s.data() + s.size(), *out);
  return res.ec == std::errc() && res.ptr == s.data() + s.size();
}

std::string Quote(std::string_view s) { return "'" + std::string(s) + "'"; }

constexpr std::uint64_t kMaxIndex = static_cast<std::uint64_t>(std::numeric_limits<Index>::max());

Status LineError(const std::string& name, int line, const std::string& what) {
  return Status::InvalidInput(name + ":" + std::to_string(line) + ": " + what);
}

// `format TYPE 1.0`.
Status ParseFormatLine(const std::vector<std::string_view>& tokens, const std::string& name,
                       int line_no, Header* header) {
  if (tokens.size() != 3) return LineError(name, line_no, "expected 'format TYPE 1.0'");
  if (tokens[1] == "ascii") {
    header->format = Format::kAscii;
  } else if (tokens[1] == "binary_little_endian") {
    header->format = Format::kBinaryLittleEndian;
  } else if (tokens[1] == "binary_big_endian") {
    header->format = Format::kBinaryBigEndian;
  } else {
    return LineError(name, line_no,
                     "unknown format " + Quote(tokens[1]) +
                         " (expected ascii, binary_little_endian or binary_big_endian)");
  }
  double version = 0.0;
  if (!ParseDouble(tokens[2], &version) || version != 1.0) {
    return LineError(name, line_no, "unsupported PLY version " + Quote(tokens[2]) + " (only 1.0)");
  }
  return Status::Ok();
}

// `element NAME COUNT`.
Status ParseElementLine(const std::vector<std::string_view>& tokens, const std::string& name,
                        int line_no, Header* header) {
  if (tokens.size() != 3) return LineError(name, line_no, "expected 'element NAME COUNT'");
  Element element;
  element.name = std::string(tokens[1]);
  element.line = line_no;
  if (!ParseCount(tokens[2], &element.count)) {
    return LineError(name, line_no, Quote(tokens[2]) + " is not a valid element count");
  }
  for (const Element& other : header->elements) {
    if (other.name == element.name) {
      return LineError(name, line_no, "element " + Quote(element.name) + " is declared twice");
    }
  }
  header->elements.push_back(std::move(element));
  return Status::Ok();
}

// `property TYPE NAME` or `property list COUNT_TYPE ITEM_TYPE NAME`, of the last element.
Status ParsePropertyLine(const std::vector<std::string_view>& tokens, const std::string& name,
                         int line_no, Header* header) {
  auto error = [&](const std::string& what) { return LineError(name, line_no, what); };
  if (header->elements.empty()) return error("a property before any element");
  Property property;
  if (tokens.size() >= 2 && tokens[1] == "list") {
    if (tokens.size() != 5) return error("expected 'property list COUNT_TYPE ITEM_TYPE NAME'");
    property.is_list = true;
    if (!ParseType(tokens[2], &property.count_type)) {
      return error("unknown property type " + Quote(tokens[2]));
    }
    if (!ParseType(tokens[3], &property.type)) {
      return error("unknown property type " + Quote(tokens[3]));
    }
    if (IsFloatType(property.count_type)) {
      return error("the list count type " + Quote(tokens[2]) + " is not an integer");
    }
    property.name = std::string(tokens[4]);
  } else {
    if (tokens.size() != 3) return error("expected 'property TYPE NAME'");
    if (!ParseType(tokens[1], &property.type)) {
      return error("unknown property type " + Quote(tokens[1]));
    }
    property.name = std::string(tokens[2]);
  }
  Element& element = header->elements.back();
  for (const Property& other : element.properties) {
    if (other.name == property.name) {
      return error("property " + Quote(property.name) + " of element " + Quote(element.name) +
                   " is declared twice");
    }
  }
  element.properties.push_back(std::move(property));
  return Status::Ok();
}

// The vertex element must have scalar x, y and z; a face element an integer index list.
Status CheckVertexAndFaceElements(const std::string& name, Header* header) {
  for (size_t e = 0; e < header->elements.size(); ++e) {
    const Element& element = header->elements[e];
    auto error = [&](const std::string& what) { return LineError(name, element.line, what); };
    if (element.name == "vertex") {
      header->vertex_element = static_cast<int>(e);
      if (element.count > kMaxIndex) {
        return error("vertex count " + std::to_string(element.count) + " is too large");
      }
      static constexpr const char* kAxes[3] = {"x", "y", "z"};
      for (int axis = 0; axis < 3; ++axis) {
        for (size_t p = 0; p < element.properties.size(); ++p) {
          if (element.properties[p].name == kAxes[axis]) {
            header->axis_property[axis] = static_cast<int>(p);
          }
        }
        const int p = header->axis_property[axis];
        if (p < 0) {
          return error(std::string("the vertex element has no '") + kAxes[axis] + "' property");
        }
        if (element.properties[static_cast<size_t>(p)].is_list) {
          return error(std::string("vertex property '") + kAxes[axis] + "' is a list");
        }
      }
    } else if (element.name == "face") {
      header->face_element = static_cast<int>(e);
      if (element.count >= kMaxIndex) {
        return error("face count " + std::to_string(element.count) + " is too large");
      }
      for (size_t p = 0; p < element.properties.size(); ++p) {
        const Property& property = element.properties[p];
        if (property.name == "vertex_indices" || property.name == "vertex_index") {
          if (!property.is_list) {
            return error("face property " + Quote(property.name) + " is not a list");
          }
          if (IsFloatType(property.type)) {
            return error("face property " + Quote(property.name) + " has non-integer indices");
          }
          header->face_list_property = static_cast<int>(p);
          break;
        }
      }
      if (header->face_list_property < 0) {
        return error("the face element has no 'vertex_indices' list property");
      }
    }
  }
  if (header->vertex_element < 0) return Status::InvalidInput(name + ": no vertex element");
  return Status::Ok();
}

Status ParseHeader(std::string_view bytes, const std::string& name, Header* header) {
  size_t pos = 0;
  if (TrimRight(NextLine(bytes, &pos)) != "ply") {
    return Status::InvalidInput(name + ": missing 'ply' magic on the first line (not a PLY file)");
  }
  // Find the end of the header first, so that a missing end_header is reported as such rather
  // than as a strange header line made of body data.
  std::vector<std::string_view> tokens;
  const size_t header_start = pos;
  size_t end_start = 0;  // Where the end_header line starts.
  int end_line = 1;
  bool found_end = false;
  while (pos < bytes.size()) {
    end_start = pos;
    Tokenize(NextLine(bytes, &pos), &tokens);
    if (end_line < std::numeric_limits<int>::max()) ++end_line;  // No overflow on huge input.
    if (tokens.size() == 1 && tokens[0] == "end_header") {
      found_end = true;
      break;
    }
  }
  if (!found_end) return Status::InvalidInput(name + ": missing end_header");
  header->body_offset = pos;
  header->end_header_line = end_line;

  bool have_format = false;
  pos = header_start;
  int line_no = 1;
  while (pos < end_start) {
    Tokenize(NextLine(bytes, &pos), &tokens);
    if (line_no < std::numeric_limits<int>::max()) ++line_no;
    if (tokens.empty()) continue;
    const std::string_view key = tokens[0];
    Status s;
    if (key == "comment" || key == "obj_info") continue;
    if (key == "format") {
      if (have_format && tokens.size() == 3)
        return LineError(name, line_no, "a second format line");
      have_format = true;
      s = ParseFormatLine(tokens, name, line_no, header);
    } else if (key == "element") {
      s = ParseElementLine(tokens, name, line_no, header);
    } else if (key == "property") {
      s = ParsePropertyLine(tokens, name, line_no, header);
    } else {
      s = LineError(name, line_no, "unknown header line " + Quote(key));
    }
    if (!s.ok()) return s;
  }
  if (!have_format) return Status::InvalidInput(name + ": missing format line");
  return CheckVertexAndFaceElements(name, header);
}

// Decodes one scalar of `type` from `p` (TypeSize(type) readable bytes), either endianness,
// independently of the host's byte order.
std::uint64_t LoadBits(const unsigned char* p, size_t size, bool big_endian) {
  std::uint64_t bits = 0;
  for (size_t i = 0; i < size; ++i) {
    const std::uint64_t byte = big_endian ? p[i] : p[size - 1 - i];
    bits = (bits << 8) | byte;
  }
  return bits;
}

double BitsToDouble(Type type, std::uint64_t bits) {
  switch (type) {
    case Type::kFloat32: {
      const std::uint32_t u = static_cast<std::uint32_t>(bits);
      float f;
      std::memcpy(&f, &u, sizeof(f));
      return static_cast<double>(f);
    }
    case Type::kFloat64: {
      double d;
      std::memcpy(&d, &bits, sizeof(d));
      return d;
    }
    default:
      break;
  }
  return 0.0;
}

// Integer types only.
std::int64_t BitsToInt(Type type, std::uint64_t bits) {
  switch (type) {
    case Type::kInt8:
      return static_cast<std::int8_t>(static_cast<std::uint8_t>(bits));
    case Type::kInt16:
      return static_cast<std::int16_t>(static_cast<std::uint16_t>(bits));
    case Type::kInt32:
      return static_cast<std::int32_t>(static_cast<std::uint32_t>(bits));
    default:
      break;
  }
  return static_cast<std::int64_t>(bits);
}

double BitsToNumber(Type type, std::uint64_t bits) {
  return IsFloatType(type) ? BitsToDouble(type, bits) : static_cast<double>(BitsToInt(type, bits));
}

std::string NumberText(double x) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof(buf), x);
  return std::string(buf, res.ptr);
}

// Appends a face after checking its size and indices; returns an empty string or the problem.
std::string CheckedAddFace(const std::vector<std::int64_t>& indices, std::uint64_t num_vertices,
                           PolygonMesh* m) {
  if (indices.size() < 3) {
    return "a face needs at least 3 vertices, this one has " + std::to_string(indices.size());
  }
  if (m->face_vertices.size() + indices.size() > kMaxIndex) return "too many face vertices";
  for (const std::int64_t v : indices) {
    if (v < 0 || static_cast<std::uint64_t>(v) >= num_vertices) {
      return "vertex index " + std::to_string(v) + " is out of range (the file has " +
             std::to_string(num_vertices) + " vertices)";
    }
  }
  for (const std::int64_t v : indices) m->face_vertices.push_back(static_cast<Index>(v));
  m->face_offsets.push_back(static_cast<Index>(m->face_vertices.size()));
  return {};
}

int AxisOf(const Header& header, size_t e, size_t p) {
  if (static_cast<int>(e) != header.vertex_element) return -1;
  for (int axis = 0; axis < 3; ++axis) {
    if (header.axis_property[axis] == static_cast<int>(p)) return axis;
  }
  return -1;
}

std::uint64_t VertexCount(const Header& header) {
  return header.elements[static_cast<size_t>(header.vertex_element)].count;
}

// The values of one entry of element e on one line (`tokens`): vertex coordinates into *p,
// the face list added to the mesh, every other value checked to be a number.
Status ParseAsciiEntry(const std::vector<std::string_view>& tokens, const Header& header, size_t e,
                       const std::string& name, int line_no, std::vector<std::int64_t>* face,
                       Vec3* p, PolygonMesh* m) {
  auto error = [&](const std::string& what) { return LineError(name, line_no, what); };
  const Element& element = header.elements[e];
  const bool is_face = static_cast<int>(e) == header.face_element;
  size_t k = 0;
  for (size_t q = 0; q < element.properties.size(); ++q) {
    const Property& property = element.properties[q];
    if (k >= tokens.size()) {
      return error("the line ends before " + element.name + " property " + Quote(property.name) +
                   " (" + std::to_string(tokens.size()) + " values)");
    }
    if (!property.is_list) {
      const std::string_view token = tokens[k++];
      double x;
      if (!ParseDouble(token, &x)) return error(Quote(token) + " is not a number");
      const int axis = AxisOf(header, e, q);
      if (axis >= 0) {
        if (!std::isfinite(x)) return error("vertex coordinate " + Quote(token) + " is not finite");
        (*p)[axis] = x;
      }
      continue;
    }
    const std::string_view count_token = tokens[k++];
    long long count;
    if (!ParseInt(count_token, &count)) return error(Quote(count_token) + " is not a list count");
    if (count < 0) return error("negative list count " + std::to_string(count));
    const size_t left = tokens.size() - k;
    if (static_cast<unsigned long long>(count) > left) {
      return error("list count " + std::to_string(count) +
                   " is larger than the number of values left on the line (" +
                   std::to_string(left) + ")");
    }
    const size_t n = static_cast<size_t>(count);
    const bool is_face_list = is_face && static_cast<int>(q) == header.face_list_property;
    if (is_face_list) face->clear();
    for (size_t j = 0; j < n; ++j) {
      const std::string_view token = tokens[k++];
      if (is_face_list) {
        long long v;
        if (!ParseInt(token, &v)) return error(Quote(token) + " is not a vertex index");
        face->push_back(v);
      } else {
        double x;
        if (!ParseDouble(token, &x)) return error(Quote(token) + " is not a number");
      }
    }
    if (is_face_list) {
      const std::string problem = CheckedAddFace(*face, VertexCount(header), m);
      if (!problem.empty()) return error(problem);
      m->face_lines.push_back(line_no);
    }
  }
  if (k < tokens.size()) {
    return error("unexpected value " + Quote(tokens[k]) + " after the last " + element.name +
                 " property");
  }
  return Status::Ok();
}

Status ParseAsciiBody(std::string_view bytes, const std::string& name, const Header& header,
                      PolygonMesh* m) {
  size_t pos = header.body_offset;
  int line_no = header.end_header_line;
  std::vector<std::string_view> tokens;
  std::vector<std::int64_t> face;
  for (size_t e = 0; e < header.elements.size(); ++e) {
    const Element& element = header.elements[e];
    if (element.properties.empty()) continue;  // Nothing is written for such elements.
    const bool is_vertex = static_cast<int>(e) == header.vertex_element;
    const bool is_face = static_cast<int>(e) == header.face_element;
    // Every line has at least one character and a '\n' (but the last), so this bounds the
    // reservation by the data that is really there.
    const size_t bound =
        static_cast<size_t>(std::min<std::uint64_t>(element.count, (bytes.size() - pos) / 2 + 1));
    if (is_vertex) {
      m->positions.reserve(bound);
      m->vertex_lines.reserve(bound);
    }
    if (is_face) {
      m->face_offsets.reserve(bound + 1);
      m->face_lines.reserve(bound);
    }
    for (std::uint64_t i = 0; i < element.count; ++i) {
      bool have_line = false;
      while (pos < bytes.size()) {
        Tokenize(NextLine(bytes, &pos), &tokens);
        if (line_no < std::numeric_limits<int>::max()) ++line_no;
        if (!tokens.empty()) {
          have_line = true;
          break;
        }
      }
      if (!have_line) {
        return LineError(name, line_no,
                         "the file ends after " + std::to_string(i) + " of " +
                             std::to_string(element.count) + " " + element.name +
                             " elements (truncated data)");
      }
      Vec3 p(0.0);
      const Status s = ParseAsciiEntry(tokens, header, e, name, line_no, &face, &p, m);
      if (!s.ok()) return s;
      if (is_vertex) {
        m->positions.push_back(p);
        m->vertex_lines.push_back(line_no);
      }
    }
  }
  return Status::Ok();
}

// A binary body being read: the bytes, their byte order, the read position.
struct BinaryCursor {
  const unsigned char* data;
  size_t size;
  bool big_endian;
  size_t pos;
};

// Entry i of element e: vertex coordinates into *p, the face list added to the mesh, every
// other value skipped. `error(what)` names the entry.
template <typename Error>
Status ParseBinaryEntry(const Header& header, size_t e, std::uint64_t i, const Error& error,
                        BinaryCursor* c, std::vector<std::int64_t>* face, Vec3* p, PolygonMesh* m) {
  const Element& element = header.elements[e];
  const bool is_face = static_cast<int>(e) == header.face_element;
  for (size_t q = 0; q < element.properties.size(); ++q) {
    const Property& property = element.properties[q];
    const Type first_type = property.is_list ? property.count_type : property.type;
    const size_t first_size = TypeSize(first_type);
    if (c->size - c->pos < first_size) {
      return error(i, "truncated data: the file ends inside this " + element.name);
    }
    const std::uint64_t bits = LoadBits(c->data + c->pos, first_size, c->big_endian);
    c->pos += first_size;
    if (!property.is_list) {
      const int axis = AxisOf(header, e, q);
      if (axis >= 0) {
        const double x = BitsToNumber(property.type, bits);
        if (!std::isfinite(x)) {
          return error(
              i, "vertex coordinate " + property.name + " = " + NumberText(x) + " is not finite");
        }
        (*p)[axis] = x;
      }
      continue;
    }
    const std::int64_t n = BitsToInt(property.count_type, bits);
    if (n < 0) return error(i, "negative list count " + std::to_string(n));
    const size_t item_size = TypeSize(property.type);
    const size_t left = c->size - c->pos;
    if (static_cast<std::uint64_t>(n) > left / item_size) {
      return error(i, "list count " + std::to_string(n) + " is larger than the " +
                          std::to_string(left) + " bytes left (truncated data)");
    }
    const size_t items = static_cast<size_t>(n);
    if (is_face && static_cast<int>(q) == header.face_list_property) {
      face->clear();
      for (size_t j = 0; j < items; ++j) {
        face->push_back(
            BitsToInt(property.type, LoadBits(c->data + c->pos, item_size, c->big_endian)));
        c->pos += item_size;
      }
      const std::string problem = CheckedAddFace(*face, VertexCount(header), m);
      if (!problem.empty()) return error(i, problem);
    } else {
      c->pos += items * item_size;
    }
  }
  return Status::Ok();
}

Status ParseBinaryBody(std::string_view bytes, const std::string& name, const Header& header,
                       PolygonMesh* m) {
  BinaryCursor c{reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(),
                 header.format == Format::kBinaryBigEndian, header.body_offset};
  std::vector<std::int64_t> face;
  for (size_t e = 0; e < header.elements.size(); ++e) {
    const Element& element = header.elements[e];
    auto error = [&](std::uint64_t i, const std::string& what) {
      return Status::InvalidInput(name + ": " + element.name + " " + std::to_string(i) + ": " +
                                  what);
    };
    const bool is_vertex = static_cast<int>(e) == header.vertex_element;
    const bool is_face = static_cast<int>(e) == header.face_element;
    // The fewest bytes one entry can take (a list takes at least its count).
    size_t min_size = 0;
    bool has_list = false;
    for (const Property& property : element.properties) {
      min_size += TypeSize(property.is_list ? property.count_type : property.type);
      has_list = has_list || property.is_list;
    }
    if (min_size == 0 || element.count == 0) continue;
    // At most this many entries fit in the rest of the data: a fixed-size element that
    // declares more is truncated at exactly that entry; for elements with lists the loop below
    // finds where the data ends. Reservations never exceed what the bytes can hold.
    const size_t remaining = c.size - c.pos;
    const size_t fit = remaining / min_size;
    if (!has_list && element.count > fit) {
      return error(fit, "truncated data: the file ends inside this " + element.name + " (" +
                            std::to_string(element.count) + " declared)");
    }
    const std::uint64_t count = element.count;
    if (!is_vertex && !is_face && !has_list) {
      c.pos += static_cast<size_t>(count) * min_size;  // <= remaining, checked above.
      continue;
    }
    const size_t bound = static_cast<size_t>(std::min<std::uint64_t>(count, fit));
    if (is_vertex) m->positions.reserve(bound);
    if (is_face) {
      m->face_offsets.reserve(bound + 1);
      const size_t index_size =
          TypeSize(element.properties[static_cast<size_t>(header.face_list_property)].type);
      m->face_vertices.reserve(std::min(bound * 3, remaining / index_size));
    }
    // Every entry takes at least min_size > 0 bytes, so a lying count ends at the data's end.
    for (std::uint64_t i = 0; i < count; ++i) {
      Vec3 p(0.0);
      const Status s = ParseBinaryEntry(header, e, i, error, &c, &face, &p, m);
      if (!s.ok()) return s;
      if (is_vertex) m->positions.push_back(p);
    }
  }
  return Status::Ok();
}

}  // namespace

Status ParsePly(std::string_view bytes, const std::string& name, PolygonMesh* mesh) {
  Header header;
  Status status = ParseHeader(bytes, name, &header);
  if (!status.ok()) return status;
  PolygonMesh m;
  m.source_name = name;
  status = header.format == Format::kAscii ? ParseAsciiBody(bytes, name, header, &m)
                                           : ParseBinaryBody(bytes, name, header, &m);
  if (!status.ok()) return status;
  *mesh = std::move(m);
  return Status::Ok();
}

Status ReadPly(const std::string& path, PolygonMesh* mesh) {
  std::string bytes;
  const Status read = ReadFileBytes(path, "a PLY file", &bytes);
  if (!read.ok()) return read;
  return ParsePly(bytes, path, mesh);
}

}  // namespace dermis

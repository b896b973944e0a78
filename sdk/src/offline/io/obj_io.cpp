// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Wavefront OBJ polygon reader with line-accurate errors, and an atomic OBJ writer.
#include "dermis/offline/io/obj_io.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "dermis/core/file_io.h"
#include "offline/io/text_tokens.h"

namespace dermis {
namespace {

using text::IsSpace;
using text::ParseDouble;
using text::ParseInt;
using text::Tokenize;
using text::TrimRight;

void AppendDouble(std::string* out, double x) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof(buf), x);
  out->append(buf, res.ptr);
}

// One "PREFIXx y z" line per vector.
void AppendVectors(std::string* out, const char* prefix, const std::vector<Vec3>& vectors) {
  for (const Vec3& p : vectors) {
    *out += prefix;
    AppendDouble(out, p.x);
    *out += ' ';
    AppendDouble(out, p.y);
    *out += ' ';
    AppendDouble(out, p.z);
    *out += '\n';
  }
}

void AppendUint(std::string* out, std::uint64_t x) {
  char buf[24];
  const auto res = std::to_chars(buf, buf + sizeof(buf), x);
  out->append(buf, res.ptr);
}

Status LineError(const std::string& name, int line, const std::string& what) {
  return Status::InvalidInput(name + ":" + std::to_string(line) + ": " + what);
}

// The next statement from `pos`: one line, or several joined by trailing backslashes (into
// `joined`), without its comment. `line_no` counts the lines read.
std::string_view NextStatement(std::string_view text, size_t* pos, int* line_no,
                               std::string* joined) {
  size_t end = text.find('\n', *pos);
  if (end == std::string_view::npos) end = text.size();
  std::string_view line = TrimRight(text.substr(*pos, end - *pos));
  *pos = end + 1;
  ++*line_no;
  if (!line.empty() && line.back() == '\\') {
    joined->assign(line.substr(0, line.size() - 1));
    while (*pos < text.size()) {
      size_t e = text.find('\n', *pos);
      if (e == std::string_view::npos) e = text.size();
      std::string_view next = TrimRight(text.substr(*pos, e - *pos));
      *pos = e + 1;
      ++*line_no;
      joined->push_back(' ');
      if (!next.empty() && next.back() == '\\') {
        joined->append(next.substr(0, next.size() - 1));
      } else {
        joined->append(next);
        break;
      }
    }
    line = *joined;
  }
  const size_t hash = line.find('#');
  if (hash != std::string_view::npos) line = line.substr(0, hash);
  return line;
}

// `v x y z [w]`: three finite coordinates.
Status ParseVertex(const std::vector<std::string_view>& tokens, const std::string& name, int line,
                   PolygonMesh* m) {
  if (tokens.size() < 4) return LineError(name, line, "a vertex needs 3 coordinates");
  Vec3 p;
  for (int k = 0; k < 3; ++k) {
    double x;
    if (!ParseDouble(tokens[1 + k], &x)) {
      return LineError(name, line, "'" + std::string(tokens[1 + k]) + "' is not a number");
    }
    if (!std::isfinite(x)) {
      return LineError(name, line,
                       "vertex coordinate '" + std::string(tokens[1 + k]) + "' is not finite");
    }
    p[k] = x;
  }
  m->positions.push_back(p);
  m->vertex_lines.push_back(line);
  return Status::Ok();
}

// `f a b c ...` with indices a, a/b, a/b/c or a//c, negative ones relative to the vertices so
// far; at least 3 distinct vertices. `face` is scratch space.
Status ParseFace(const std::vector<std::string_view>& tokens, const std::string& name, int line,
                 std::vector<Index>* face, PolygonMesh* m) {
  face->clear();
  for (size_t k = 1; k < tokens.size(); ++k) {
    std::string_view t = tokens[k];
    const size_t slash = t.find('/');
    std::string_view idx = t.substr(0, slash);
    long long value;
    if (!ParseInt(idx, &value)) {
      return LineError(name, line, "'" + std::string(t) + "' is not a vertex index");
    }
    const long long count = static_cast<long long>(m->positions.size());
    if (value == 0) return LineError(name, line, "vertex index 0 (OBJ indices start at 1)");
    if (value < 0) {
      if (value < -count) {  // not -value > count: -LLONG_MIN overflows
        return LineError(
            name, line,
            "relative vertex index " + std::to_string(value) + " points before the first vertex");
      }
      value = count + value + 1;
    }
    if (value > std::numeric_limits<Index>::max()) {
      return LineError(name, line, "vertex index " + std::to_string(value) + " is too large");
    }
    face->push_back(static_cast<Index>(value - 1));
  }
  // Repeated vertices: pairwise for small faces, sorted for large ones (n log n, not n^2).
  Index repeated = kInvalidIndex;
  if (face->size() <= 16) {
    for (size_t i = 0; i < face->size() && repeated == kInvalidIndex; ++i) {
      for (size_t j = 0; j < i; ++j) {
        if ((*face)[j] == (*face)[i]) repeated = (*face)[i];
      }
    }
  } else {
    std::vector<Index> sorted(*face);
    std::sort(sorted.begin(), sorted.end());
    const auto it = std::adjacent_find(sorted.begin(), sorted.end());
    if (it != sorted.end()) repeated = *it;
  }
  if (repeated != kInvalidIndex) {
    return LineError(name, line,
                     "the face uses vertex " + std::to_string(repeated + 1) + " more than once");
  }
  if (face->size() < 3) {
    return LineError(
        name, line,
        "a face needs at least 3 vertices, this one has " + std::to_string(face->size()));
  }
  m->AddFace(*face);
  m->face_lines.push_back(line);
  return Status::Ok();
}

// Indices may point forward; once every vertex is read they must all exist.
Status CheckFaceIndices(const PolygonMesh& m, const std::string& name) {
  for (Index f = 0; f < m.num_faces(); ++f) {
    for (Index h = m.face_offsets[f]; h < m.face_offsets[f + 1]; ++h) {
      if (m.face_vertices[h] >= m.num_vertices()) {
        return LineError(name, m.face_lines[f],
                         "vertex index " + std::to_string(m.face_vertices[h] + 1) +
                             " is out of range (the file has " + std::to_string(m.num_vertices()) +
                             " vertices)");
      }
    }
  }
  return Status::Ok();
}

}  // namespace

Status ParseObj(std::string_view text, const std::string& name, PolygonMesh* mesh,
                bool require_faces) {
  PolygonMesh m;
  m.source_name = name;
  std::vector<std::string_view> tokens;
  std::vector<Index> face;
  std::string joined;
  size_t pos = 0;
  int line_no = 0;
  while (pos < text.size()) {
    const int statement_line = line_no + 1;
    Tokenize(NextStatement(text, &pos, &line_no, &joined), &tokens);
    if (tokens.empty()) continue;
    const std::string_view key = tokens[0];
    Status s;
    if (key == "v") {
      s = ParseVertex(tokens, name, statement_line, &m);
    } else if (key == "f" || key == "fo") {
      s = ParseFace(tokens, name, statement_line, &face, &m);
    }
    // Everything else (vt, vn, vp, o, g, s, usemtl, mtllib, l, p, curves) carries nothing a
    // control mesh needs and is skipped.
    if (!s.ok()) return s;
  }
  if (m.positions.empty()) return Status::InvalidInput(name + ": no vertices (empty mesh)");
  if (m.num_faces() == 0 && require_faces)
    return Status::InvalidInput(name + ": no faces (a control mesh needs polygons)");
  const Status s = CheckFaceIndices(m, name);
  if (!s.ok()) return s;
  *mesh = std::move(m);
  return Status::Ok();
}

Status ReadObj(const std::string& path, PolygonMesh* mesh, bool require_faces) {
  std::string text;
  const Status read = ReadFileBytes(path, "an OBJ file", &text);
  if (!read.ok()) return read;
  if (text.find('\0') != std::string::npos) {
    return Status::InvalidInput(path + ": not a text OBJ file (contains NUL bytes)");
  }
  return ParseObj(text, path, mesh, require_faces);
}

Status WriteObj(const std::string& path, const std::vector<Vec3>& positions,
                const std::vector<Vec3>& normals, const std::vector<std::uint32_t>& triangles,
                const std::string& header_comment) {
  std::string text;
  const Status s = FormatObj(positions, normals, triangles, header_comment, &text);
  if (!s.ok()) return s.WithContext(path);
  return WriteFileAtomically(path, text);
}

Status FormatObj(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals,
                 const std::vector<std::uint32_t>& triangles, const std::string& header_comment,
                 std::string* text) {
  if (!normals.empty() && normals.size() != positions.size()) {
    return Status::InvalidInput("normal count does not match position count");
  }
  std::string& out = *text;
  out.clear();
  out.reserve(positions.size() * 100 + triangles.size() * 12);
  if (!header_comment.empty()) out += "# " + header_comment + "\n";
  AppendVectors(&out, "v ", positions);
  AppendVectors(&out, "vn ", normals);
  for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
    out += 'f';
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t i = std::uint64_t{triangles[t + k]} + 1;
      out += ' ';
      AppendUint(&out, i);
      if (!normals.empty()) {
        out += "//";
        AppendUint(&out, i);
      }
    }
    out += '\n';
  }
  return Status::Ok();
}

Status WritePolygonObj(const std::string& path, const PolygonMesh& mesh) {
  std::string out;
  AppendVectors(&out, "v ", mesh.positions);
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    out += 'f';
    for (Index h = mesh.face_offsets[f]; h < mesh.face_offsets[f + 1]; ++h) {
      out += ' ';
      AppendUint(&out, static_cast<std::uint64_t>(mesh.face_vertices[h]) + 1);
    }
    out += '\n';
  }
  return WriteFileAtomically(path, out);
}

}  // namespace dermis

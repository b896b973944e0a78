// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Software rasteriser: orthographic camera, edge-function rasterisation with a z-buffer at
// `supersample`^2 samples per pixel, per-sample Blinn-Phong shading of interpolated normals,
// box-filter downsampling; legend and caption text from stb_easy_font quads; PNG through
// stb_image_write (docs/cli.md explains why a rasteriser of our own).
#include "render/raster.h"

#include <stb/stb_easy_font.h>
#include <stb/stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "dermis/core/file_io.h"

namespace dermis::render {
namespace {

struct Frame {
  glm::vec3 center, right, up, back;
  float scale = 1.0f;  // pixels per model unit (at the supersampled resolution)
  float cx = 0.0f, cy = 0.0f;
};

Frame MakeFrame(const Box& box, const View& view, int w, int h) {
  Frame f;
  f.center = 0.5f * (box.lo + box.hi);
  const float az = glm::radians(view.azimuth), el = glm::radians(view.elevation);
  f.back = glm::vec3(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
  glm::vec3 up_world(0.0f, 1.0f, 0.0f);
  if (std::fabs(glm::dot(up_world, f.back)) > 0.999f) up_world = glm::vec3(0.0f, 0.0f, -1.0f);
  f.right = glm::normalize(glm::cross(up_world, f.back));
  f.up = glm::cross(f.back, f.right);
  // Fit the box's projected extent (its 8 corners) with a margin.
  float ex = 1e-12f, ey = 1e-12f;
  for (int c = 0; c < 8; ++c) {
    const glm::vec3 p((c & 1) ? box.hi.x : box.lo.x, (c & 2) ? box.hi.y : box.lo.y,
                      (c & 4) ? box.hi.z : box.lo.z);
    ex = std::max(ex, std::fabs(glm::dot(p - f.center, f.right)));
    ey = std::max(ey, std::fabs(glm::dot(p - f.center, f.up)));
  }
  // A legend takes the right quarter of the picture.
  const float usable_w = view.show_legend ? 0.75f * static_cast<float>(w) : static_cast<float>(w);
  f.scale = 0.46f * std::min(usable_w / ex, static_cast<float>(h) / ey);
  f.cx = 0.5f * usable_w;
  f.cy = 0.5f * static_cast<float>(h);
  return f;
}

glm::vec3 Shade(glm::vec3 n, const glm::vec3& base, const Frame& f) {
  const float len = glm::length(n);
  n = len > 0.0f && std::isfinite(len) ? n / len : f.back;
  if (glm::dot(n, f.back) < 0.0f) n = -n;  // two-sided
  const glm::vec3 key = glm::normalize(-0.45f * f.right + 0.6f * f.up + 0.66f * f.back);
  const glm::vec3 fill = glm::normalize(0.6f * f.right - 0.2f * f.up + 0.77f * f.back);
  const glm::vec3 half = glm::normalize(key + f.back);
  const float diffuse =
      0.62f * std::max(0.0f, glm::dot(n, key)) + 0.22f * std::max(0.0f, glm::dot(n, fill));
  const float spec = 0.18f * std::pow(std::max(0.0f, glm::dot(n, half)), 48.0f);
  return glm::clamp(base * (0.22f + diffuse) + glm::vec3(spec), 0.0f, 1.0f);
}

std::uint8_t Byte(float x) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(x, 0.0f, 1.0f) * 255.0f));
}

void FillRect(Image* img, int x0, int y0, int x1, int y1, glm::vec3 c) {
  x0 = std::max(0, x0);
  y0 = std::max(0, y0);
  x1 = std::min(img->width, x1);
  y1 = std::min(img->height, y1);
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      std::uint8_t* p = &img->rgb[3 * (static_cast<std::size_t>(y) * img->width + x)];
      p[0] = Byte(c.r);
      p[1] = Byte(c.g);
      p[2] = Byte(c.b);
    }
  }
}

// Text at (x, y) (top left), `scale` pixels per font unit, through stb_easy_font's quads.
void DrawText(Image* img, int x, int y, const std::string& text, int scale, glm::vec3 color) {
  if (text.empty()) return;
  static thread_local std::vector<char> buffer(1 << 16);
  std::string t = text;
  const int quads = stb_easy_font_print(0.0f, 0.0f, t.data(), nullptr, buffer.data(),
                                        static_cast<int>(buffer.size()));
  for (int q = 0; q < quads; ++q) {
    // 4 vertices of 16 bytes (x, y, z floats and an RGBA colour) per quad.
    float lo[2] = {1e30f, 1e30f}, hi[2] = {-1e30f, -1e30f};
    for (int v = 0; v < 4; ++v) {
      float xy[2];
      std::copy_n(reinterpret_cast<const float*>(buffer.data() + 16 * (4 * q + v)), 2, xy);
      for (int k = 0; k < 2; ++k) {
        lo[k] = std::min(lo[k], xy[k]);
        hi[k] = std::max(hi[k], xy[k]);
      }
    }
    FillRect(img, x + static_cast<int>(lo[0]) * scale, y + static_cast<int>(lo[1]) * scale,
             x + static_cast<int>(hi[0]) * scale, y + static_cast<int>(hi[1]) * scale, color);
  }
}

int TextWidth(const std::string& text) {
  std::string t = text;
  return stb_easy_font_width(t.data());
}

std::string Format(float v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.3g", static_cast<double>(v));
  return buf;
}

void DrawLegend(Image* img, const View& view) {
  const int s = std::max(1, img->height / 240);
  const int bar_w = 14 * s, bar_h = img->height / 2;
  const int label_w = 8 * 6 * s;
  const int x0 = img->width - bar_w - label_w - 12 * s;
  const int y0 = (img->height - bar_h) / 2;
  for (int y = 0; y < bar_h; ++y) {
    const float t = 1.0f - static_cast<float>(y) / static_cast<float>(bar_h - 1);
    FillRect(img, x0, y0 + y, x0 + bar_w, y0 + y + 1, ColorMap(t));
  }
  const glm::vec3 ink(0.15f);
  for (int k = 0; k <= 4; ++k) {
    const float t = static_cast<float>(k) / 4.0f;
    const float v = view.scalar_min + t * (view.scalar_max - view.scalar_min);
    const int y = y0 + static_cast<int>((1.0f - t) * static_cast<float>(bar_h - 1));
    FillRect(img, x0 + bar_w, y, x0 + bar_w + 4 * s, y + s, ink);
    DrawText(img, x0 + bar_w + 6 * s, y - 3 * s, Format(v), s, ink);
  }
  if (!view.legend.empty()) {
    const int w = TextWidth(view.legend) * s;
    DrawText(img, std::max(0, x0 + bar_w / 2 - w / 2), y0 - 14 * s, view.legend, s, ink);
  }
}

}  // namespace

void Box::Add(const glm::vec3& p) {
  lo = glm::min(lo, p);
  hi = glm::max(hi, p);
}

Box Bounds(const std::vector<Mesh>& meshes) {
  Box b;
  for (const Mesh& m : meshes) {
    for (const glm::vec3& p : m.positions) {
      if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) b.Add(p);
    }
  }
  return b;
}

glm::vec3 ColorMap(float t) {
  static const glm::vec3 stops[] = {{0.16f, 0.10f, 0.48f},
                                    {0.13f, 0.40f, 0.85f},
                                    {0.10f, 0.72f, 0.66f},
                                    {0.95f, 0.85f, 0.20f},
                                    {0.85f, 0.15f, 0.10f}};
  if (!(t > 0.0f)) return stops[0];
  if (t >= 1.0f) return stops[4];
  const float x = t * 4.0f;
  const int i = std::min(3, static_cast<int>(x));
  return glm::mix(stops[i], stops[i + 1], x - static_cast<float>(i));
}

Image Render(const std::vector<Mesh>& meshes, const View& view) {
  const int ss = std::clamp(view.supersample, 1, 4);
  const int w = view.width * ss, h = view.height * ss;
  Box box = view.frame.empty() ? Bounds(meshes) : view.frame;
  if (box.empty()) box.Add(glm::vec3(0.0f));
  const Frame f = MakeFrame(box, view, w, h);
  std::vector<float> depth(static_cast<std::size_t>(w) * h, -1e30f);
  std::vector<glm::vec3> color(depth.size(), view.background);
  const float range = view.scalar_max - view.scalar_min;
  struct Segment {
    glm::vec3 a, b;  // screen x, y and depth
    glm::vec3 color;
  };
  std::vector<Segment> segments;
  for (const Mesh& m : meshes) {
    const std::size_t nv = m.positions.size();
    std::vector<glm::vec3> sp(nv);  // screen x, y and depth (larger is nearer)
    for (std::size_t i = 0; i < nv; ++i) {
      const glm::vec3 d = m.positions[i] - f.center;
      sp[i] = glm::vec3(f.cx + f.scale * glm::dot(d, f.right), f.cy - f.scale * glm::dot(d, f.up),
                        glm::dot(d, f.back));
    }
    for (std::size_t l = 0; l + 1 < m.lines.size(); l += 2) {
      const std::uint32_t ia = m.lines[l], ib = m.lines[l + 1];
      if (ia >= nv || ib >= nv) continue;
      segments.push_back({sp[ia], sp[ib], m.line_color});
    }
    const bool has_scalar = m.scalar.size() == nv;
    const bool has_normals = m.normals.size() == nv;
    for (std::size_t t = 0; t + 2 < m.triangles.size(); t += 3) {
      const std::uint32_t ia = m.triangles[t], ib = m.triangles[t + 1], ic = m.triangles[t + 2];
      if (ia >= nv || ib >= nv || ic >= nv) continue;
      const glm::vec3 a = sp[ia], b = sp[ib], c = sp[ic];
      const float area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
      if (!(std::fabs(area) > 1e-12f) || !std::isfinite(area)) continue;
      const glm::vec3 face_n =
          glm::cross(m.positions[ib] - m.positions[ia], m.positions[ic] - m.positions[ia]);
      const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x, b.x, c.x}))));
      const int x1 = std::min(w - 1, static_cast<int>(std::ceil(std::max({a.x, b.x, c.x}))));
      const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y, b.y, c.y}))));
      const int y1 = std::min(h - 1, static_cast<int>(std::ceil(std::max({a.y, b.y, c.y}))));
      const float inv = 1.0f / area;
      for (int y = y0; y <= y1; ++y) {
        const float py = static_cast<float>(y) + 0.5f;
        for (int x = x0; x <= x1; ++x) {
          const float px = static_cast<float>(x) + 0.5f;
          const float w0 = ((b.x - px) * (c.y - py) - (b.y - py) * (c.x - px)) * inv;
          const float w1 = ((c.x - px) * (a.y - py) - (c.y - py) * (a.x - px)) * inv;
          const float w2 = 1.0f - w0 - w1;
          if (w0 < 0.0f || w1 < 0.0f || w2 < 0.0f) continue;
          const float z = w0 * a.z + w1 * b.z + w2 * c.z;
          const std::size_t k = static_cast<std::size_t>(y) * w + x;
          if (z <= depth[k]) continue;
          depth[k] = z;
          glm::vec3 base = m.color;
          if (has_scalar) {
            const float s = w0 * m.scalar[ia] + w1 * m.scalar[ib] + w2 * m.scalar[ic];
            base = ColorMap(range > 0.0f ? (s - view.scalar_min) / range : 0.0f);
          }
          const glm::vec3 n =
              has_normals ? w0 * m.normals[ia] + w1 * m.normals[ib] + w2 * m.normals[ic] : face_n;
          color[k] = Shade(n, base, f);
        }
      }
    }
  }
  // Segments after every triangle, so that the depth test sees the whole surface: a square
  // of side `ss` (one output pixel) every half sample along the segment, where its depth is
  // within a small bias of the nearest surface there (the segments lie on that surface).
  const float bias = 0.004f * glm::length(box.hi - box.lo);
  for (const Segment& g : segments) {
    const glm::vec3 d = g.b - g.a;
    const float len = std::max(std::fabs(d.x), std::fabs(d.y));
    if (!std::isfinite(len)) continue;
    const int steps = std::max(1, static_cast<int>(std::ceil(2.0f * len)));
    const int half = ss / 2;
    for (int k = 0; k <= steps; ++k) {
      const glm::vec3 p = g.a + d * (static_cast<float>(k) / static_cast<float>(steps));
      const int px = static_cast<int>(std::floor(p.x)), py = static_cast<int>(std::floor(p.y));
      for (int y = py - half; y < py - half + ss; ++y) {
        if (y < 0 || y >= h) continue;
        for (int x = px - half; x < px - half + ss; ++x) {
          if (x < 0 || x >= w) continue;
          const std::size_t at = static_cast<std::size_t>(y) * w + x;
          if (p.z + bias < depth[at]) continue;
          color[at] = g.color;
        }
      }
    }
  }
  Image img;
  img.width = view.width;
  img.height = view.height;
  img.rgb.resize(3 * static_cast<std::size_t>(img.width) * img.height);
  const float norm = 1.0f / static_cast<float>(ss * ss);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      glm::vec3 sum(0.0f);
      for (int j = 0; j < ss; ++j) {
        for (int i = 0; i < ss; ++i) {
          sum += color[static_cast<std::size_t>(y * ss + j) * w + (x * ss + i)];
        }
      }
      std::uint8_t* p = &img.rgb[3 * (static_cast<std::size_t>(y) * img.width + x)];
      p[0] = Byte(sum.r * norm);
      p[1] = Byte(sum.g * norm);
      p[2] = Byte(sum.b * norm);
    }
  }
  if (view.show_legend) DrawLegend(&img, view);
  if (!view.caption.empty()) {
    const int s = std::max(1, img.height / 240);
    DrawText(&img, 8 * s, 8 * s, view.caption, s, glm::vec3(0.15f));
  }
  return img;
}

Image ContactSheet(const std::vector<Image>& images, int columns) {
  Image sheet;
  if (images.empty()) return sheet;
  columns = std::max(1, std::min(columns, static_cast<int>(images.size())));
  const int rows = (static_cast<int>(images.size()) + columns - 1) / columns;
  int cell_w = 0, cell_h = 0;
  for (const Image& im : images) {
    cell_w = std::max(cell_w, im.width);
    cell_h = std::max(cell_h, im.height);
  }
  sheet.width = cell_w * columns;
  sheet.height = cell_h * rows;
  sheet.rgb.assign(3 * static_cast<std::size_t>(sheet.width) * sheet.height, 255);
  for (std::size_t k = 0; k < images.size(); ++k) {
    const Image& im = images[k];
    const int ox = static_cast<int>(k % static_cast<std::size_t>(columns)) * cell_w;
    const int oy = static_cast<int>(k / static_cast<std::size_t>(columns)) * cell_h;
    for (int y = 0; y < im.height; ++y) {
      std::copy_n(&im.rgb[3 * static_cast<std::size_t>(y) * im.width], 3 * im.width,
                  &sheet.rgb[3 * (static_cast<std::size_t>(oy + y) * sheet.width + ox)]);
    }
  }
  return sheet;
}

std::string EncodePng(const Image& image) {
  std::string out;
  auto append = [](void* ctx, void* data, int size) {
    static_cast<std::string*>(ctx)->append(static_cast<const char*>(data),
                                           static_cast<std::size_t>(size));
  };
  stbi_write_png_to_func(append, &out, image.width, image.height, 3, image.rgb.data(),
                         3 * image.width);
  return out;
}

Status WritePng(const std::string& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0) return Status::InvalidInput(path + ": empty image");
  const std::string bytes = EncodePng(image);
  if (bytes.empty()) return Status::Internal(path + ": PNG encoding failed");
  return WriteFileAtomically(path, bytes);
}

}  // namespace dermis::render

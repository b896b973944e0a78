// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Ying-Zorin chart maps (docs/notes/manifold.md sections 0, 2, 3 and 7; S1 Vfcd2xy / Vfcd2Fcd /
// Fcdv2Vfcd). z = e^{i f Theta/K} r^p e^{i q alpha} for w = r e^{i alpha} in ring face f,
// q = 2 Theta/(pi K).
#include "dermis/surface/chart.h"

#include <algorithm>
#include <cmath>

namespace dermis {
namespace {
constexpr double kPi = 3.14159265358979323846;

Vec2 CMul(Vec2 a, Vec2 b) { return Vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x); }

// v turned by n quarter turns counter-clockwise (n >= 0), exactly.
Vec2 QuarterTurns(int n, Vec2 v) {
  switch (n & 3) {
    case 0:
      return v;
    case 1:
      return Vec2(-v.y, v.x);
    case 2:
      return Vec2(-v.x, -v.y);
    default:
      return Vec2(v.y, -v.x);
  }
}
}  // namespace

double CatmullClarkSubdominantEigenvalue(int valence) {
  const double k = static_cast<double>(valence);
  const double c2 = std::cos(2.0 * kPi / k);
  return (5.0 + c2 + std::cos(kPi / k) * std::sqrt(2.0 * (9.0 + c2))) / 16.0;
}

double SectorAngle(VertexKind kind) {
  switch (kind) {
    case VertexKind::kInterior:
      return 2.0 * kPi;
    case VertexKind::kCrease:
      return kPi;
    case VertexKind::kConvexCorner:
      return 0.5 * kPi;
    case VertexKind::kConcaveCorner:
      return 1.5 * kPi;
  }
  return 2.0 * kPi;
}

ChartParams MakeChartParams(int valence, VertexKind kind, ChartType type) {
  ChartParams c;
  c.valence = std::max(valence, 1);
  c.kind = kind;
  c.sector = SectorAngle(kind);
  c.q = 2.0 * c.sector / (kPi * c.valence);
  switch (type) {
    case ChartType::kFullyComplex:
      c.p = c.q;
      break;
    case ChartType::kIsodistance:
      c.p = 1.0;
      break;
    case ChartType::kCharacteristicMap:
      // Inside: log2(1/lambda_K). On a boundary the Catmull-Clark crease/corner rules have
      // subdominant eigenvalue 1/2, so p = 1 (docs/notes/manifold.md section 7; concave corner
      // p = 1).
      c.p = (kind == VertexKind::kInterior && c.valence >= 3)
                ? std::log2(1.0 / CatmullClarkSubdominantEigenvalue(c.valence))
                : 1.0;
      if (c.valence == 4 && kind == VertexKind::kInterior) c.p = 1.0;  // exact, not 1 - 1e-16
      break;
  }
  return c;
}

Vec2 CornerToFace(int corner, Vec2 w) {
  switch (corner & 3) {
    case 0:
      return w;
    case 1:
      return Vec2(1.0 - w.y, w.x);  // 1 + i w
    case 2:
      return Vec2(1.0 - w.x, 1.0 - w.y);  // (1+i) - w
    default:
      return Vec2(w.y, 1.0 - w.x);  // i (1 - w)
  }
}

Vec2 FaceToCorner(int corner, Vec2 uv) {
  switch (corner & 3) {
    case 0:
      return uv;
    case 1:
      return Vec2(uv.y, 1.0 - uv.x);
    case 2:
      return Vec2(1.0 - uv.x, 1.0 - uv.y);
    default:
      return Vec2(1.0 - uv.y, uv.x);
  }
}

int DominantCorner(Vec2 uv) { return uv.x <= 0.5 ? (uv.y <= 0.5 ? 0 : 3) : (uv.y <= 0.5 ? 1 : 2); }

glm::dmat2 FaceToCornerJacobian(int corner) {
  // glm matrices are column-major: dmat2(col0, col1), col0 = d(c,d)/ds, col1 = d(c,d)/dt.
  switch (corner & 3) {
    case 0:
      return glm::dmat2(Vec2(1, 0), Vec2(0, 1));
    case 1:
      return glm::dmat2(Vec2(0, -1), Vec2(1, 0));
    case 2:
      return glm::dmat2(Vec2(-1, 0), Vec2(0, -1));
    default:
      return glm::dmat2(Vec2(0, 1), Vec2(-1, 0));
  }
}

Vec2 CornerTransition(int delta, Vec2 w) {
  switch (delta & 3) {
    case 0:
      return w;
    case 1:
      return Vec2(w.y, 1.0 - w.x);  // i (1 - w): to the next corner
    case 2:
      return Vec2(1.0 - w.x, 1.0 - w.y);  // (1+i) - w: to the diagonal corner
    default:
      return Vec2(1.0 - w.y, w.x);  // 1 + i w: to the previous corner
  }
}

bool ChartMap(const ChartParams& chart, int face_in_ring, Vec2 w, Vec2* z, glm::dmat2* jacobian) {
  if (chart.p == 1.0 && chart.q == 1.0) {
    // q = 2 Theta / (pi K) = 1: every ring face spans a quarter turn (4 faces inside, 2 on a
    // crease, 1 at a convex corner, 3 at a concave one), and with p = 1 the map is the rotation
    // by face_in_ring quarter turns: exact, without trigonometry. Adding 0 turns the -0 that a
    // negation leaves into +0, so the angle of z is never -pi.
    *z = QuarterTurns(face_in_ring, w) + Vec2(0.0);
    if (jacobian) {
      const Vec2 x = QuarterTurns(face_in_ring, Vec2(1.0, 0.0)) + Vec2(0.0);
      *jacobian = glm::dmat2(x, Vec2(-x.y, x.x) + Vec2(0.0));
    }
    return true;
  }
  const double r2 = w.x * w.x + w.y * w.y;
  const double base = face_in_ring * chart.sector / chart.valence;
  if (r2 == 0.0) {
    *z = Vec2(0.0);
    if (jacobian) {
      // p = q = 1 took the rotation above, so the map is not differentiable here.
      *jacobian = glm::dmat2(0.0);
      return false;
    }
    return true;
  }
  const double r = std::sqrt(r2);
  const double alpha = std::atan2(w.y, w.x);
  const double rho = chart.p == 1.0 ? r : std::pow(r, chart.p);
  const double ang = base + chart.q * alpha;
  const Vec2 zz(rho * std::cos(ang), rho * std::sin(ang));
  *z = zz;
  if (jacobian) {
    // dz/dc = z (p c - i q d) / r^2, dz/dd = z (p d + i q c) / r^2.
    const Vec2 dc = CMul(zz, Vec2(chart.p * w.x, -chart.q * w.y)) / r2;
    const Vec2 dd = CMul(zz, Vec2(chart.p * w.y, chart.q * w.x)) / r2;
    *jacobian = glm::dmat2(dc, dd);
  }
  return true;
}

bool ChartMapInverse(const ChartParams& chart, Vec2 z, int* face_in_ring, Vec2* w) {
  const double rho = std::sqrt(z.x * z.x + z.y * z.y);
  if (!(rho > 0.0)) {
    *face_in_ring = 0;
    *w = Vec2(0.0);
    return rho == 0.0;
  }
  if (chart.p == 1.0 && chart.q == 1.0 && chart.kind == VertexKind::kInterior) {
    // The regular interior chart (ChartMap: a rotation by quarter turns): the face is the
    // quadrant of z, angles [f pi/2, (f + 1) pi/2) as below, and w is z turned back.
    int f = 3;
    if (z.x > 0.0 && z.y >= 0.0) {
      f = 0;
    } else if (z.x <= 0.0 && z.y > 0.0) {
      f = 1;
    } else if (z.x < 0.0 && z.y <= 0.0) {
      f = 2;
    }
    *face_in_ring = f;
    *w = QuarterTurns(4 - f, z) + Vec2(0.0);
    return true;
  }
  double theta = std::atan2(z.y, z.x);  // (-pi, pi]
  const double wedge = chart.sector / chart.valence;
  if (chart.kind == VertexKind::kInterior) {
    if (theta < 0.0) theta += 2.0 * kPi;
  } else {
    // Angles below 0 but nearer to 0 than to the sector's far end stay negative (outside).
    if (theta < -0.5 * (2.0 * kPi - chart.sector)) theta += 2.0 * kPi;
    const double tol = 1e-12;
    if (theta < -tol || theta > chart.sector + tol) return false;
    theta = std::clamp(theta, 0.0, chart.sector);
  }
  int f = static_cast<int>(std::floor(theta / wedge));
  f = std::clamp(f, 0, chart.valence - 1);
  const double alpha = std::clamp((theta - f * wedge) / chart.q, 0.0, 0.5 * kPi);
  const double r = chart.p == 1.0 ? rho : std::pow(rho, 1.0 / chart.p);
  *face_in_ring = f;
  *w = Vec2(r * std::cos(alpha), r * std::sin(alpha));
  return true;
}

}  // namespace dermis

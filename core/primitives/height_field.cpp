#include "core/primitives/height_field.h"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <tuple>

#include "core/geometry/geometry.h"
#include "core/optimizer/height_field_eval.h"
#include "core/primitives/primitives.h"
#include "core/primitives/spline_surface.h"

namespace c3d {

namespace {

// Cubic B-splines, clamped, on `spans` even spans over [a, b].
struct Axis {
  double a = 0, b = 1;
  int spans = 1;
  int poles() const { return spans + 3; }
  double width() const { return (b - a) / spans; }
  // Knot j of the clamped sequence: a four times, the inner knots, b four times.
  double knot(int j) const { return j <= 3 ? a : j >= 3 + spans ? b : a + (j - 3) * width(); }
  std::vector<double> knots() const {
    std::vector<double> k;
    for (int j = 0; j < spans + 7; ++j) k.push_back(knot(j));
    return k;
  }
  // Greville abscissae: poles there make the spline of t equal to t.
  double greville(int i) const { return (knot(i + 1) + knot(i + 2) + knot(i + 3)) / 3; }
  // The first of the four poles t depends on, and their weights (Cox-de Boor).
  int basis(double t, double w[4]) const {
    const int span = std::clamp(int((t - a) / width()), 0, spans - 1) + 3;  // k[span] <= t < k[span + 1]
    double left[4], right[4];
    w[0] = 1;
    for (int j = 1; j <= 3; ++j) {
      left[j] = t - knot(span + 1 - j);
      right[j] = knot(span + j) - t;
      double saved = 0;
      for (int r = 0; r < j; ++r) {
        const double tmp = w[r] / (right[r + 1] + left[j - r]);
        w[r] = saved + right[r + 1] * tmp;
        saved = left[j - r] * tmp;
      }
      w[j] = saved;
    }
    return span - 3;
  }
};

// The surface reaches kMarginM past the points and the footprint; its knots
// stand at least kMinKnotSpacings point spacings apart (16 points a span)
// and a roof has at most kMaxSpans a side.
constexpr double kMarginM = 0.5, kMinKnotSpacings = 4, kMaxSpans = 24;

// A penalty on the poles' second differences along each axis (Eilers and
// Marx's P-splines), light: it only decides poles no point speaks for.
constexpr double kSmoothing = 1e-4;

// The heights of the poles that fit `points` best by least squares.
Eigen::VectorXd solve_poles(const std::vector<Vec3>& points, const std::vector<char>& use, const Axis& ax,
                            const Axis& ay) {
  const int m = ax.poles() * ay.poles();
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(m, m);
  Eigen::VectorXd r = Eigen::VectorXd::Zero(m);
  for (size_t k = 0; k < points.size(); ++k) {
    if (!use[k]) continue;
    double wx[4], wy[4];
    const int i0 = ax.basis(points[k].x(), wx), j0 = ay.basis(points[k].y(), wy);
    int idx[16];
    double w[16];
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) idx[i + 4 * j] = (i0 + i) + ax.poles() * (j0 + j), w[i + 4 * j] = wx[i] * wy[j];
    for (int p = 0; p < 16; ++p) {
      r(idx[p]) += w[p] * points[k].z();
      for (int q = 0; q < 16; ++q) N(idx[p], idx[q]) += w[p] * w[q];
    }
  }
  const double lambda = kSmoothing * std::max(N.trace() / m, 1e-9);
  auto penalise = [&](int a, int b, int c) {  // (c_a - 2 c_b + c_c)^2
    const int id[3] = {a, b, c};
    const double d[3] = {1, -2, 1};
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q) N(id[p], id[q]) += lambda * d[p] * d[q];
  };
  for (int j = 0; j < ay.poles(); ++j)
    for (int i = 1; i + 1 < ax.poles(); ++i)
      penalise(i - 1 + ax.poles() * j, i + ax.poles() * j, i + 1 + ax.poles() * j);
  for (int j = 1; j + 1 < ay.poles(); ++j)
    for (int i = 0; i < ax.poles(); ++i)
      penalise(i + ax.poles() * (j - 1), i + ax.poles() * j, i + ax.poles() * (j + 1));
  // N is banded (a point speaks for 4 x 4 neighbouring poles): a sparse
  // factorisation costs the band's width squared per pole, not m^2.
  const Eigen::SparseMatrix<double> sparse = N.sparseView();
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(sparse);
  if (ldlt.info() == Eigen::Success) return ldlt.solve(r);
  return N.ldlt().solve(r);  // not positive definite: the pivoting dense one
}

// The plan frame a surface is fitted in: u along `along`, v across it.
struct Frame {
  Vec2 e1 = Vec2::UnitX(), e2 = Vec2::UnitY();
  Vec2 to_uv(const Vec2& q) const { return {q.dot(e1), q.dot(e2)}; }
  Vec2 to_xy(const Vec2& uv) const { return uv.x() * e1 + uv.y() * e2; }
};

// Poles at the Greville abscissae of their axes: the surface is the height
// over plan point u e1 + v e2 at parameters (u, v).
SplineSurface surface_of(const Eigen::VectorXd& c, const Axis& ax, const Axis& ay, const Frame& f) {
  SplineSurface s;
  s.poles_u = ax.poles(), s.poles_v = ay.poles();
  s.knots_u = ax.knots(), s.knots_v = ay.knots();
  for (int j = 0; j < ay.poles(); ++j)
    for (int i = 0; i < ax.poles(); ++i) {
      const Vec2 xy = f.to_xy({ax.greville(i), ay.greville(j)});
      s.poles.emplace_back(xy.x(), xy.y(), c(i + ax.poles() * j));
    }
  return s;
}

// What a fit is judged by: the criterion, where the points beyond 2.5 noise
// count as if at 2.5 noise (a wrong surface pays for what it leaves).
double score(const HeightFieldRoof& roof, size_t n, double noise) {
  const double outliers = double(n - roof.inliers.size());
  return bic(roof.rmse, roof.parameters, double(roof.inliers.size()), noise) + outliers * 6.25;
}

// The surface on knots `width` apart along u and v, fitted twice: the second
// time without the points beyond 3 noise of the first (a chimney, a bird).
// `uv`: the points in the frame's coordinates.
HeightFieldRoof fit_on(const std::vector<Vec3>& points, const std::vector<Vec3>& uv, double noise, const Vec2& lo,
                       const Vec2& hi, const Vec2& width, const Frame& frame) {
  const Axis ax{lo.x(), hi.x(), std::max(1, int(std::round((hi.x() - lo.x()) / width.x())))};
  const Axis ay{lo.y(), hi.y(), std::max(1, int(std::round((hi.y() - lo.y()) / width.y())))};
  std::vector<char> use(points.size(), 1);
  HeightFieldRoof roof;
  for (int pass = 0; pass < 2; ++pass) {
    roof.surface = surface_of(solve_poles(uv, use, ax, ay), ax, ay, frame);
    const HeightField f(roof.surface);
    roof.inliers.clear();
    double rss = 0;
    for (size_t k = 0; k < points.size(); ++k) {
      const double d = f.distance(points[k]);
      use[k] = std::abs(d) <= 3 * noise;
      if (std::abs(d) > 2.5 * noise) continue;
      roof.inliers.push_back(int(k));
      rss += d * d;
    }
    roof.rmse = std::sqrt(rss / double(std::max<size_t>(1, roof.inliers.size())));
  }
  roof.parameters = ax.poles() * ay.poles();
  return roof;
}

}  // namespace

std::string HeightFieldRoof::describe() const {
  char s[120];
  std::snprintf(s, sizeof s, "B-spline height field, %d x %d poles, fit %.3f m", surface.poles_u, surface.poles_v,
                rmse);
  return s;
}

// The surface with the plan frame of its parameters, read off its poles
// (they stand on a grid along the frame's axes, at their Greville abscissae).
struct HeightField::Surface {
  Handle(Geom_BSplineSurface) occ;
  Vec2 origin = Vec2::Zero(), e1 = Vec2::UnitX(), e2 = Vec2::UnitY();  // plan point of parameters (0, 0); axes
  Vec2 uv(const Vec2& q) const { return {(q - origin).dot(e1), (q - origin).dot(e2)}; }
  // The height at plan point q and its slope there (dz/dx, dz/dy), in one evaluation.
  double height(const Vec2& q, Vec2& slope) const {
    const Vec2 at = uv(q);
    gp_Pnt p;
    gp_Vec du, dv;
    occ->D1(at.x(), at.y(), p, du, dv);
    slope = du.Z() * e1 + dv.Z() * e2;
    return p.Z();
  }
};

HeightField::HeightField(const SplineSurface& s) {
  auto f = std::make_shared<Surface>();
  f->occ = occ_surface(s);
  std::tie(f->origin, f->e1) = spline_plan_frame(s);
  f->e2 = Vec2(-f->e1.y(), f->e1.x());
  surface_ = f;
}

double HeightField::z(const Vec2& q) const {
  const Vec2 uv = surface_->uv(q);
  return surface_->occ->Value(uv.x(), uv.y()).Z();
}

Vec2 HeightField::slope(const Vec2& q) const {
  Vec2 slope;
  surface_->height(q, slope);
  return slope;
}

double HeightField::distance(const Vec3& p) const {
  Vec2 slope;
  const double z = surface_->height(p.head<2>(), slope);
  return (p.z() - z) / std::sqrt(1 + slope.squaredNorm());
}

double HeightField::max_curvature(const Vec2& lo, const Vec2& hi, double step) const {
  double k = 0;
  for (double y = lo.y(); y <= hi.y(); y += step)
    for (double x = lo.x(); x <= hi.x(); x += step) {
      const Vec2 uv = surface_->uv({x, y});
      gp_Pnt p;
      gp_Vec du, dv, duu, dvv, duv;
      surface_->occ->D2(uv.x(), uv.y(), p, du, dv, duu, dvv, duv);
      const Eigen::Matrix2d h{{duu.Z(), duv.Z()}, {duv.Z(), dvv.Z()}};  // its eigenvalues turn with no frame
      k = std::max(k, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(h).eigenvalues().cwiseAbs().maxCoeff());
    }
  return k;
}

std::optional<HeightFieldRoof> fit_height_field(const std::vector<Vec3>& points, double noise, double spacing,
                                                const Ring2& cover, const Vec2& along) {
  if (points.size() < 50 || noise <= 0 || along.norm() <= 0) return std::nullopt;
  Frame frame;
  frame.e1 = along.normalized();
  frame.e2 = Vec2(-frame.e1.y(), frame.e1.x());
  std::vector<Vec3> uv;
  Vec2 a(1e300, 1e300), b(-1e300, -1e300);
  for (const Vec3& p : points) {
    const Vec2 q = frame.to_uv(p.head<2>());
    uv.push_back({q.x(), q.y(), p.z()});
    a = a.cwiseMin(q), b = b.cwiseMax(q);
  }
  for (const Vec2& c : cover) a = a.cwiseMin(frame.to_uv(c)), b = b.cwiseMax(frame.to_uv(c));
  a -= Vec2(kMarginM, kMarginM), b += Vec2(kMarginM, kMarginM);
  const double longest = (b - a).maxCoeff();
  const double finest = std::max({kMinKnotSpacings * spacing, longest / kMaxSpans, 0.5});
  auto fit = [&](const Vec2& width) { return fit_on(points, uv, noise, a, b, width, frame); };
  // Even knots from the finest to one span over the whole roof, 1.5 times
  // wider each step; then each axis's coarser on its own while the criterion
  // gains (a wave along the hall needs few spans across it).
  std::optional<HeightFieldRoof> best;
  double best_score = 1e300;
  Vec2 best_width;
  auto consider = [&](const Vec2& width) {
    HeightFieldRoof roof = fit(width);
    if (roof.inliers.empty()) return false;
    const double sc = score(roof, points.size(), noise);
    if (sc >= best_score) return false;
    best_score = sc, best = std::move(roof), best_width = width;
    return true;
  };
  for (double w = finest; w < 2 * longest; w *= 1.5) consider({w, w});
  if (!best) return std::nullopt;
  for (int axis = 0; axis < 2; ++axis)
    for (Vec2 w = best_width; w[axis] < 2 * longest;) {
      w[axis] *= 1.5;
      if (!consider(w)) break;
    }
  return best;
}

}  // namespace c3d

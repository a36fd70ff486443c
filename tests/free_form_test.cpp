// Free-form roofs (core/primitives/height_field.h): a B-spline height field
// fitted to a saddle's and a wave's noisy points, and the hall under it with
// the exact areas and volume.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "core/check/solid_check.h"
#include "core/geometry/geometry.h"
#include "core/optimizer/height_field_eval.h"
#include "core/optimizer/optimizer.h"
#include "core/primitives/exact_shape.h"
#include "core/primitives/height_field.h"
#include "core/synthetic/sample_town.h"

using namespace c3d;

namespace {

struct Roof {
  std::string name;
  double L, W, H;
  std::function<double(double, double)> z, zx, zy;
};

Roof saddle() {
  const double L = 16, W = 11, H = 5, h = 3, c = 2 * h / (L * W);
  return {"saddle", L, W, H, [=](double x, double y) { return H + h / 2 + c * (x - L / 2) * (y - W / 2); },
          [=](double, double y) { return c * (y - W / 2); }, [=](double x, double) { return c * (x - L / 2); }};
}

Roof wave() {
  const double L = 18, W = 10, H = 4, h = 2.5, k = 3 * M_PI / L;
  return {"wave", L, W, H, [=](double x, double) { return H + h * (1 - std::cos(k * x)) / 2; },
          [=](double x, double) { return h * k * std::sin(k * x) / 2; }, [](double, double) { return 0.0; }};
}

// Points seen from the air at `density` per m2 in plan, 3 cm of noise.
std::vector<Vec3> scan(const Roof& r, double density, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x(0, r.L), y(0, r.W);
  std::normal_distribution<double> noise(0, 0.03);
  std::vector<Vec3> pts;
  for (int k = 0; k < int(density * r.L * r.W); ++k) {
    const double px = x(rng), py = y(rng);
    pts.push_back({px, py, r.z(px, py) + noise(rng)});
  }
  return pts;
}

// Exact figures by fine midpoint sums (1e-6 relative on these smooth roofs).
double exact_roof_area(const Roof& r) {
  const int n = 1000;
  double a = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double x = r.L * (i + 0.5) / n, y = r.W * (j + 0.5) / n;
      a += std::sqrt(1 + std::pow(r.zx(x, y), 2) + std::pow(r.zy(x, y), 2));
    }
  return a * r.L * r.W / (double(n) * n);
}

double exact_volume_of(const Roof& r) {
  const int n = 1000;
  double v = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) v += r.z(r.L * (i + 0.5) / n, r.W * (j + 0.5) / n);
  return v * r.L * r.W / (double(n) * n);
}

Ring2 box(const Roof& r) { return {{0, 0}, {r.L, 0}, {r.L, r.W}, {0, r.W}}; }

double area_of(const Building& b, ElementType t) {
  double a = 0;
  for (const Element& e : b.elements)
    if (e.type == t) a += e.area;
  return a;
}

}  // namespace

// The surface follows the shape to the noise and not beyond: its points sit
// at the scan's 3 cm, the surface 1.5 cm RMS from the true roof (6 cm at
// most, at its edge, where the points stop), with a few dozen poles.
TEST(FreeForm, HeightFieldFollowsTheRoofNotTheNoise) {
  for (const Roof& r : {saddle(), wave()}) {
    SCOPED_TRACE(r.name);
    const std::vector<Vec3> pts = scan(r, 10, 3);
    const auto hf = fit_height_field(pts, 0.03, 1 / std::sqrt(10.0), box(r), {1, 0});
    ASSERT_TRUE(hf.has_value());
    EXPECT_GT(hf->inliers.size(), 0.98 * double(pts.size()));
    EXPECT_NEAR(hf->rmse, 0.03, 0.006) << hf->describe();
    const HeightField f(hf->surface);
    double worst = 0, ss = 0;
    int n = 0;
    for (double x = 0; x <= r.L; x += 0.5)
      for (double y = 0; y <= r.W; y += 0.5, ++n) {
        const double e = f.z({x, y}) - r.z(x, y);
        worst = std::max(worst, std::abs(e)), ss += e * e;
      }
    EXPECT_LT(std::sqrt(ss / n), 0.015) << hf->describe();
    EXPECT_LT(worst, 0.06) << hf->describe() << ": at the roof's edge, where its points stop";
    EXPECT_LT(hf->parameters, 50) << "a surface, not the points";
    std::printf("%s: %s, %.4f m RMS, %.4f m at most from the true roof\n", r.name.c_str(), hf->describe().c_str(),
                std::sqrt(ss / n), worst);
  }
}

// The hall under a fitted roof: roof and walls within 1 % of the exact
// areas, the volume within 1 %, the faces closed, the roof's triangles
// within the 1 cm chord of their surface, and its exact shape's volume
// (OpenCASCADE, cut under the B-spline) the faces' within 0.3 %.
TEST(FreeForm, HallUnderItsRoofHasTheExactFigures) {
  for (const Roof& r : {saddle(), wave()}) {
    SCOPED_TRACE(r.name);
    const std::vector<Vec3> pts = scan(r, 20, 5);
    const auto hf = fit_height_field(pts, 0.03, 1 / std::sqrt(20.0), box(r), {1, 0});
    ASSERT_TRUE(hf.has_value());
    FreeFormInput in;
    in.building_id = "p_b1";
    in.roof = hf->surface;
    in.footprint = Polygon2{box(r), {}};
    in.edge_sigma.assign(4, 0.02);  // each edge's own sigma; none shared
    const std::optional<Building> b = free_form_building(in);
    ASSERT_TRUE(b.has_value());
    EXPECT_NEAR(area_of(*b, ElementType::Roof) / exact_roof_area(r), 1, 0.01);
    double walls = 0;  // the exact wall area: the roof's height along the four sides
    for (int i = 0; i < 2000; ++i) {
      const double x = r.L * (i + 0.5) / 2000, y = r.W * (i + 0.5) / 2000;
      walls += (r.z(x, 0) + r.z(x, r.W)) * r.L / 2000 + (r.z(0, y) + r.z(r.L, y)) * r.W / 2000;
    }
    EXPECT_NEAR(area_of(*b, ElementType::Wall) / walls, 1, 0.01);
    EXPECT_NEAR(area_of(*b, ElementType::Ground), r.L * r.W, 1e-6);
    std::string problem;
    EXPECT_TRUE(shell_is_closed(b->solid, &problem)) << problem;
    const double faces = shell_volume(b->solid);
    EXPECT_NEAR(faces / exact_volume_of(r), 1, 0.01);
    const HeightField f(hf->surface);
    double off = 0;
    for (const Face& t : b->elements.front().faces) {
      const Vec3 mid = (t.ring[0] + t.ring[1] + t.ring[2]) / 3;
      off = std::max(off, std::abs(mid.z() - f.z(mid.head<2>())));
    }
    EXPECT_LT(off, 0.0105);
    // Each side moved out by 2 cm on its own adds its length (lifted by the
    // roof's slope along it) times 2 cm: in quadrature, at least the plan's.
    const double plan_sigma = 0.02 * std::sqrt(2 * r.L * r.L + 2 * r.W * r.W);
    EXPECT_GE(b->elements.front().sigma_area, plan_sigma);
    EXPECT_LT(b->elements.front().sigma_area, 1.5 * plan_sigma);
    ASSERT_EQ(b->exact.parts.size(), 1u);
    EXPECT_NEAR(exact_volume(b->exact) / faces, 1, 0.003);
    // The store's JSON keeps the surface: the same solid read back.
    const Vec3 offset(500000, 6000000, 10);
    const ExactShape back = exact_shape_from_json(exact_shape_json(b->exact, offset), offset);
    EXPECT_NEAR(exact_volume(back), exact_volume(b->exact), 1e-6 * faces);
  }
}

// A roof that stands under the ground somewhere is no hall.
TEST(FreeForm, RoofBelowTheGroundIsRefused) {
  const Roof r = saddle();
  const auto hf = fit_height_field(scan(r, 10, 3), 0.03, 0.3, box(r), {1, 0});
  ASSERT_TRUE(hf.has_value());
  FreeFormInput in;
  in.roof = hf->surface;
  in.footprint = Polygon2{{{0, 0}, {r.L, 0}, {r.L, r.W}, {0, r.W}}, {}};
  in.ground_z = 6;  // above the saddle's low corners
  EXPECT_FALSE(free_form_building(in).has_value());
}

// A hall at an angle to the axes: its footprint's edges are cut at points a
// rounding off their line, and the roof still closes with its walls (the
// project's solid check, as the batch runs it).
TEST(FreeForm, SlantedHallCloses) {
  const Roof r = saddle();
  const double a = 0.3;
  auto turned = [&](double x, double y) {
    return Vec2(std::cos(a) * x - std::sin(a) * y + 20, std::sin(a) * x + std::cos(a) * y + 10);
  };
  std::vector<Vec3> pts;
  for (const Vec3& p : scan(r, 20, 7)) pts.push_back({turned(p.x(), p.y()).x(), turned(p.x(), p.y()).y(), p.z()});
  FreeFormInput in;
  in.footprint = Polygon2{{turned(0, 0), turned(r.L, 0), turned(r.L, r.W), turned(0, r.W)}, {}};
  const auto hf = fit_height_field(pts, 0.03, 1 / std::sqrt(20.0), in.footprint.outer, turned(1, 0) - turned(0, 0));
  ASSERT_TRUE(hf.has_value());
  in.roof = hf->surface;
  const std::optional<Building> b = free_form_building(in);
  ASSERT_TRUE(b.has_value());
  const SolidCheck check = check_solid(b->solid);
  EXPECT_TRUE(check.ok) << check.summary();
  EXPECT_NEAR(area_of(*b, ElementType::Roof) / exact_roof_area(r), 1, 0.01);
}

// The optimizer snaps onto the height field as OpenCASCADE evaluates it
// (core/optimizer/height_field_eval.h, in the spline's own frame turned off
// the axes): a point of the surface is on it, its normal is OpenCASCADE's,
// and a point lifted off along that normal comes back to it.
TEST(FreeForm, OptimizerSeesTheSurfaceOpenCascadeHolds) {
  const Roof r = saddle();
  const auto hf = fit_height_field(scan(r, 20, 5), 0.03, 1 / std::sqrt(20.0), box(r), {std::cos(0.4), std::sin(0.4)});
  ASSERT_TRUE(hf.has_value());
  const HeightField occ(hf->surface);
  CurvedPrimitive s;
  s.kind = CurvedPrimitive::Kind::HeightField;
  s.heights = std::make_shared<const HeightFieldData>(height_field_data(hf->surface).value());
  for (double x = 1; x < r.L; x += 1.3)
    for (double y = 1; y < r.W; y += 1.1) {
      const Vec3 on(x, y, occ.z({x, y}));
      const Vec3 n = Vec3(-occ.slope({x, y}).x(), -occ.slope({x, y}).y(), 1).normalized();
      EXPECT_TRUE(s.spans(on, 0));
      EXPECT_LT(s.distance(on), 1e-9) << x << " " << y;
      EXPECT_GT(s.normal(on).dot(n), 1 - 1e-12) << x << " " << y;
      EXPECT_LT((s.project(on + 0.1 * n) - on).norm(), 1e-6) << x << " " << y;
    }
  EXPECT_FALSE(s.spans({-3, -3, 5}, 0.5)) << "beyond its knots";
}

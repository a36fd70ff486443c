#include "core/reconstruct/envelope/wall_faces.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/reconstruct/envelope/common.h"
#include "core/reconstruct/envelope/elements.h"

namespace c3d::envelope {

constexpr double kAlongSlope = 0.1;  // a piece's edge within 6 degrees of the footprint edge runs along it
// A step wall of a few square centimetres (two roof planes meeting millimetres
// apart near a junction) is no wall anyone could point at or cost: its faces
// stay in the shell but join the nearest wall element. The other step walls
// are appended to `elements` after the facades.
constexpr double kMinStepWallArea = 0.01;  // m^2
// Positions along an edge, and points, closer than this coincide (numerical
// duplicates, far below the weld).
constexpr double kSamePoint = 1e-7;  // m
// A wall stands at least this high: a roof below the terrain (bad data) must
// not fold the wall over itself.
constexpr double kMinWallHeight = 0.01;  // m
// Two roof pieces closer than this in height along a shared edge are level
// there: no step wall.
constexpr double kLevelTol = 1e-6;  // m
// A footprint edge comes from an outline edge parallel to it within about 11
// degrees; any other is a worse source than one that far away.
constexpr double kSourceParallelCos = 0.98;
constexpr double kNotParallel = 100.0;  // m added to a non-parallel edge's distance
// A step wall's area is known to this times its square root (its two roof
// planes' heights along the step).
constexpr double kStepWallSigma = 0.05;  // m
// A step wall lower than this on average is as likely two planes' junction
// modelled apart (a cross gable's valley: 0.5-2 m^2 of sawtooth, 0.3-0.7 m
// high on average in the sample towns) as a step between levels (those rise
// by a storey, 3.7-5.4 m there): its whole area is in doubt.
constexpr double kDoubtfulStepHeight = 1.0;  // m

namespace {

// Nearest distance between two elements' vertices.
double vertex_gap(const Element& a, const Element& b) {
  double best = 1e18;
  for (const auto& fa : a.faces)
    for (const auto& p : fa.ring)
      for (const auto& fb : b.faces)
        for (const auto& q : fb.ring) best = std::min(best, (p - q).norm());
  return best;
}

// The walls of one outline edge and the sigma of their area.
struct Facade {
  const OutlineEdge* src;
  std::vector<Face> faces;
  SharedSigma sigma;
};

// Each footprint wall's position error, into the facades' areas (as
// wall_area_sensitivity books it), the ground's and the hanging roof's; the
// terrain level under all walls, and the roof plane's height over each.
void add_position_sigmas(const Ring2& fp, const std::vector<Face>& walls, const std::vector<const OutlineEdge*>& src,
                         const std::vector<int>& facade_of, double ground_z, const std::vector<Face>& inside,
                         const RoofEdgeNoise& noise, const std::vector<OutlineEdge>& edges,
                         std::vector<Facade>& facades, Facades& out) {
  const size_t m = fp.size();
  const double perimeter = sampled_perimeter(edges);
  for (size_t i = 0; i < m; ++i) {
    if (facade_of[i] < 0) continue;
    const WallPositionError err = wall_position_error(*src[i], noise, perimeter);
    const double len = (fp[(i + 1) % m] - fp[i]).norm();
    out.ground.add(len * err.wall, len * err.wall_shared);
    out.eaves.add(len * err.eave, len * err.eave_shared);
    const WallSensitivity g = wall_area_sensitivity(fp, i, walls[i], ground_z, inside);
    double self = g.top;
    for (const auto& [j, part] : {std::pair{(i + m - 1) % m, g.at_a}, std::pair{(i + 1) % m, g.at_b}}) {
      if (facade_of[j] < 0 || src[j]->party == src[i]->party) self += part;
      else facades[size_t(facade_of[j])].sigma.add(part * err.wall, part * err.wall_shared);
    }
    SharedSigma& s = facades[size_t(facade_of[i])].sigma;
    s.add(std::hypot(self * err.wall, len * noise.plane_z), self * err.wall_shared + len * kTerrainSigma);
  }
}

// Whether footprint edges under outline edges a and b are one wall element:
// under one edge, or under the chords of one outline arc (a curved wall).
bool one_wall(const OutlineEdge& a, const OutlineEdge& b) { return &a == &b || (a.arc >= 0 && a.arc == b.arc); }

// Area over plan length of a vertical element (its faces' widest plan extents).
double mean_height(const Element& e) {
  double len = 0;
  for (const auto& f : e.faces) {
    double w = 0;
    for (const auto& p : f.ring)
      for (const auto& q : f.ring) w = std::max(w, (p - q).head<2>().norm());
    len += w;
  }
  return len > 0 ? e.area / len : 0;
}

}  // namespace

// The roof underside along a footprint edge, from the inside pieces' edges on it.
std::vector<ProfileSegment> roof_profile(const Vec2& a, const Vec2& b,
                                         const std::vector<Face>& inside_faces) {
  Vec2 d = b - a;
  double len = d.norm();
  d /= len;
  Vec2 n = outward(d);
  std::vector<ProfileSegment> segs;
  for (const auto& f : inside_faces) {
    const Ring3& r = f.ring;
    for (size_t i = 0; i < r.size(); ++i) {
      const Vec3& p = r[i];
      const Vec3& q = r[(i + 1) % r.size()];
      Vec2 p2 = p.head<2>() - a, q2 = q.head<2>() - a;
      // welded ends may sit off the line
      if (std::abs(n.dot(p2)) > 2 * kWeldTol || std::abs(n.dot(q2)) > 2 * kWeldTol) continue;
      double tp = d.dot(p2), tq = d.dot(q2);
      if (std::min(tp, tq) < -2 * kWeldTol || std::max(tp, tq) > len + 2 * kWeldTol) continue;
      if (std::abs(tp - tq) < kSamePoint) continue;
      tp = std::clamp(tp, 0.0, len);  // welding may put an end past the corner, as it may off the line
      tq = std::clamp(tq, 0.0, len);
      if (std::abs(tp - tq) < kSamePoint) continue;
      const bool along = std::abs(n.dot(q2 - p2)) < kAlongSlope * std::abs(tq - tp);
      if (tp < tq) segs.push_back({tp, p.z(), tq, q.z(), p.head<2>(), q.head<2>(), along});
      else segs.push_back({tq, q.z(), tp, p.z(), q.head<2>(), p.head<2>(), along});
    }
  }
  std::sort(segs.begin(), segs.end(), [](auto& x, auto& y) { return x.t0 > y.t0; });
  return segs;
}

Face wall_face(const Vec2& a, const Vec2& b, double ground_z,
               const std::vector<ProfileSegment>& profile) {
  // Breakpoints of the profile; on each interval the highest roof piece over it
  // is the underside the wall meets (overlaps of clipped pieces are numerical).
  std::vector<double> ts;
  for (const auto& s : profile) ts.push_back(s.t0), ts.push_back(s.t1);
  std::sort(ts.begin(), ts.end());
  // Breakpoints closer than the weld tolerance are one: a roof piece touching
  // the edge over less than a millimetre (a corner on a step line) would put a
  // spike of no width into the wall.
  ts.erase(std::unique(ts.begin(), ts.end(), [](double x, double y) { return y - x < kWeldTol; }),
           ts.end());
  auto z_on = [](const ProfileSegment& s, double t) {
    return s.z0 + (s.z1 - s.z0) * (t - s.t0) / (s.t1 - s.t0);
  };
  Vec2 d = (b - a).normalized();
  Face f;
  f.ring.emplace_back(a.x(), a.y(), ground_z);
  f.ring.emplace_back(b.x(), b.y(), ground_z);
  // The wall meets the roof at the corner of a piece running along the edge
  // where one ends there: a corner may sit a millimetre or two off the edge,
  // more than the weld joins. At the footprint's corners the walls meet each
  // other.
  const double len = (b - a).norm();
  auto push = [&](const ProfileSegment& s, double t) {
    Vec2 at = a + t * d;
    if (t < kWeldTol) at = a;
    else if (t > len - kWeldTol) at = b;
    else if (s.along && std::abs(t - s.t0) < kWeldTol) at = s.at0;
    else if (s.along && std::abs(t - s.t1) < kWeldTol) at = s.at1;
    // A roof below the terrain (bad data) must not fold the wall over itself.
    Vec3 v(at.x(), at.y(), std::max(z_on(s, t), ground_z + kMinWallHeight));
    if ((f.ring.back() - v).norm() > kSamePoint) f.ring.push_back(v);
  };
  for (size_t k = ts.size(); k-- > 1;) {  // from b back to a
    double hi = ts[k], lo = ts[k - 1], mid = 0.5 * (hi + lo);
    const ProfileSegment* best = nullptr;
    for (const auto& s : profile)
      if (s.t0 <= mid && s.t1 >= mid && (!best || z_on(s, mid) > z_on(*best, mid))) best = &s;
    if (!best) continue;
    push(*best, hi);
    push(*best, lo);
  }
  if ((f.ring.back() - f.ring.front()).norm() < kSamePoint) f.ring.pop_back();
  return f;
}

// Vertical faces where two inside roof pieces meet at different heights,
// grouped by the roof region above them: one step wall element per roof plane,
// however many edge pieces (and lower neighbours) its foot is made of.
std::map<int, std::vector<Face>> step_walls(const std::vector<Face>& inside,
                                            const std::vector<int>& region_of) {
  // Every ring of every piece, holes included: an island piece meets the hole
  // of the piece around it along opposite edges.
  std::vector<const Ring3*> rings;
  std::vector<int> piece_of;
  for (size_t f = 0; f < inside.size(); ++f) {
    rings.push_back(&inside[f].ring);
    piece_of.push_back(int(f));
    for (const auto& h : inside[f].holes) rings.push_back(&h), piece_of.push_back(int(f));
  }
  auto key = [](const Vec3& p, const Vec3& q) { return directed(p.head<2>(), q.head<2>()); };
  std::map<EdgeKey, std::pair<int, int>> edge_at;  // (ring, vertex)
  for (size_t k = 0; k < rings.size(); ++k)
    for (size_t i = 0; i < rings[k]->size(); ++i)
      edge_at[key((*rings[k])[i], (*rings[k])[(i + 1) % rings[k]->size()])] = {int(k), int(i)};
  std::map<int, std::vector<Face>> out;
  for (size_t k = 0; k < rings.size(); ++k) {
    const Ring3& r = *rings[k];
    for (size_t i = 0; i < r.size(); ++i) {
      const Vec3& p = r[i];
      const Vec3& q = r[(i + 1) % r.size()];
      auto it = edge_at.find(key(q, p));
      if (it == edge_at.end() || piece_of[it->second.first] == piece_of[k]) continue;
      const Ring3& o = *rings[it->second.first];
      const Vec3& oq = o[it->second.second];
      const Vec3& op = o[(it->second.second + 1) % o.size()];
      double dp = p.z() - op.z(), dq = q.z() - oq.z();
      if ((dp > kLevelTol && dq < -kLevelTol) || (dp < -kLevelTol && dq > kLevelTol)) {
        // The two roofs cross along the edge (an outer ring or a hole's): each
        // walls the part where it is the higher, a triangle up to the crossing
        // point, which lies on both roofs; noding the shell puts it into their edges.
        const Vec3 c = p + dp / (dp - dq) * (q - p);
        out[region_of[piece_of[k]]].push_back(dp > 0 ? Face{{op, c, p}, {}} : Face{{c, oq, q}, {}});
        continue;
      }
      if (dp < -kLevelTol || dq < -kLevelTol || (dp < kLevelTol && dq < kLevelTol)) continue;  // not the higher side
      Face w;
      w.ring.push_back(op);
      w.ring.push_back(oq);
      if (dq > kLevelTol) w.ring.push_back(q);
      if (dp > kLevelTol) w.ring.push_back(p);
      if (w.ring.size() >= 3) out[region_of[piece_of[k]]].push_back(std::move(w));
    }
  }
  return out;
}

// Footprint edge -> outline edge it came from (parallel and nearest).
const OutlineEdge& source_edge(const std::vector<OutlineEdge>& edges, const Vec2& a, const Vec2& b) {
  Vec2 d = (b - a).normalized(), mid = 0.5 * (a + b);
  const OutlineEdge* best = &edges[0];
  double best_score = 1e18;
  for (const auto& e : edges) {
    Vec2 ed = (e.b - e.a).normalized();
    Vec2 em = 0.5 * (e.a + e.b);
    double off = std::abs(outward(ed).dot(mid - e.a));
    double along = std::max(0.0, std::abs(ed.dot(mid - em)) - 0.5 * (e.b - e.a).norm());
    double score = off + along + (ed.dot(d) < kSourceParallelCos ? kNotParallel : 0.0);
    if (score < best_score) best_score = score, best = &e;
  }
  return *best;
}

Facades facade_walls(const Polygon2& fp, const std::vector<OutlineEdge>& edges, double ground_z,
                     const std::vector<Face>& inside, const RoofEdgeNoise& noise) {
  // Walls along the footprint, from the terrain up to the roof underside: one
  // element per outline edge they stand under, or per outline arc (a notch
  // in the footprint does not split a facade into separate elements).
  Facades out;
  const size_t m = fp.outer.size();
  std::vector<Face> walls(m);
  std::vector<const OutlineEdge*> src(m, nullptr);
  std::vector<int> facade_of(m, -1);
  std::vector<Facade> facades;
  for (size_t i = 0; i < m; ++i) {
    walls[i] = wall_under(fp.outer[i], fp.outer[(i + 1) % m], ground_z, inside);
    if (walls[i].ring.size() < 3) continue;
    src[i] = &source_edge(edges, fp.outer[i], fp.outer[(i + 1) % m]);
    if (facades.empty() || !one_wall(*facades.back().src, *src[i])) facades.push_back({src[i], {}, {}});
    facade_of[i] = int(facades.size()) - 1;
    out.faces.push_back(walls[i]);
    facades.back().faces.push_back(walls[i]);
  }
  if (facades.size() > 1 && one_wall(*facades.front().src, *facades.back().src)) {  // wraps round
    Facade& last = facades.back();
    facades.front().faces.insert(facades.front().faces.begin(), last.faces.begin(), last.faces.end());
    for (int& f : facade_of)
      if (f == int(facades.size()) - 1) f = 0;
    facades.pop_back();
  }
  add_position_sigmas(fp.outer, walls, src, facade_of, ground_z, inside, noise, edges, facades, out);
  for (auto& [source, faces, sigma] : facades) {
    Element e = make_element(source->party ? ElementType::PartyWall : ElementType::Wall, std::move(faces));
    e.evidence = source->evidence;
    e.support_points = source->support;
    e.rmse = source->rms;
    e.azimuth_deg = azimuth_of(widest_face(e));
    e.slope_deg = 90.0;
    e.sigma_area = sigma.total();
    e.sigma_shared = sigma.shared;
    out.elements.push_back(std::move(e));
  }
  return out;
}

StepWalls step_wall_elements(const std::vector<Face>& inside, const std::vector<int>& inside_region) {
  StepWalls out;
  for (auto& [above, faces] : step_walls(inside, inside_region)) {
    out.faces.insert(out.faces.end(), faces.begin(), faces.end());
    Element e = make_element(ElementType::Wall, std::move(faces));
    e.evidence = WallEvidence::RoofStep;
    e.slope_deg = 90.0;
    e.sigma_area = mean_height(e) < kDoubtfulStepHeight ? e.area : kStepWallSigma * std::sqrt(e.area);
    e.azimuth_deg = azimuth_of(widest_face(e));
    out.elements.push_back(std::move(e));
  }
  return out;
}

void fold_sliver_steps(std::vector<Element>& steps, std::vector<Element>& elements) {
  for (auto& e : steps)
    if (e.area >= kMinStepWallArea) elements.push_back(std::move(e));
  for (auto& e : steps) {
    if (e.area >= kMinStepWallArea) continue;  // listed above
    Element* host = nullptr;
    double gap = 1e18;
    for (auto& w : elements) {
      if (w.type != ElementType::Wall && w.type != ElementType::PartyWall) continue;
      const double d = vertex_gap(e, w);
      if (d < gap) gap = d, host = &w;
    }
    if (!host) {  // no other wall: keep it as it is
      elements.push_back(std::move(e));
      continue;
    }
    host->faces.insert(host->faces.end(), e.faces.begin(), e.faces.end());
    host->area += e.area;
    host->plan_area += e.plan_area;
    host->sigma_area = std::hypot(host->sigma_area, e.sigma_area);
  }
}

}  // namespace c3d::envelope

namespace c3d {

using envelope::roof_profile;
using envelope::wall_face;

Face wall_under(const Vec2& a, const Vec2& b, double ground_z, const std::vector<Face>& inside_pieces) {
  const auto profile = roof_profile(a, b, inside_pieces);
  return profile.empty() ? Face{} : wall_face(a, b, ground_z, profile);
}

}  // namespace c3d

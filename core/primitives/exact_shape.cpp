#include "core/primitives/exact_shape.h"

#include <nlohmann/json.hpp>
#include <stdexcept>

namespace c3d {

namespace {

nlohmann::json xy(const Vec2& q) { return {q.x(), q.y()}; }
nlohmann::json xyz(const Vec3& q) { return {q.x(), q.y(), q.z()}; }
Vec2 vec2(const nlohmann::json& j) { return {j.at(0).get<double>(), j.at(1).get<double>()}; }
Vec3 vec3(const nlohmann::json& j) { return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()}; }

const char* kind_name(ProfileStep::Kind k) {
  return k == ProfileStep::Kind::Line ? "line" : k == ProfileStep::Kind::Arc ? "arc" : "spline";
}

ProfileStep::Kind kind_from(const std::string& s) {
  if (s == "line") return ProfileStep::Kind::Line;
  if (s == "arc") return ProfileStep::Kind::Arc;
  if (s == "spline") return ProfileStep::Kind::Spline;
  throw std::invalid_argument("unknown profile step '" + s + "'");
}

nlohmann::json spline_json(const SplineSurface& s, const Vec3& offset) {
  nlohmann::json poles = nlohmann::json::array();
  for (const Vec3& q : s.poles) poles.push_back(xyz(q + offset));
  return {{"degree", {s.degree_u, s.degree_v}}, {"poles_uv", {s.poles_u, s.poles_v}}, {"poles", poles},
          {"knots_u", s.knots_u}, {"knots_v", s.knots_v}};
}

SplineSurface spline_from(const nlohmann::json& j, const Vec3& offset) {
  SplineSurface s;
  s.degree_u = j.at("degree").at(0).get<int>(), s.degree_v = j.at("degree").at(1).get<int>();
  s.poles_u = j.at("poles_uv").at(0).get<int>(), s.poles_v = j.at("poles_uv").at(1).get<int>();
  for (const nlohmann::json& q : j.at("poles")) s.poles.push_back(vec3(q) - offset);
  s.knots_u = j.at("knots_u").get<std::vector<double>>();
  s.knots_v = j.at("knots_v").get<std::vector<double>>();
  if (s.poles_u < 2 || s.poles_v < 2 || s.poles.size() != size_t(s.poles_u) * size_t(s.poles_v) ||
      s.knots_u.size() != size_t(s.poles_u + s.degree_u + 1) || s.knots_v.size() != size_t(s.poles_v + s.degree_v + 1))
    throw std::invalid_argument("exact shape: a spline surface's poles and knots do not agree");
  return s;
}

}  // namespace

std::string exact_shape_json(const ExactShape& shape, const Vec3& offset) {
  if (shape.parts.empty()) return "";
  nlohmann::json parts = nlohmann::json::array();
  for (const ShapePart& p : shape.parts) {
    nlohmann::json steps = nlohmann::json::array();
    for (const ProfileStep& s : p.steps) {
      nlohmann::json through = nlohmann::json::array();
      for (const Vec2& q : s.through) through.push_back(xy(q));
      steps.push_back({{"kind", kind_name(s.kind)}, {"through", through}, {"to", xy(s.to)}});
    }
    parts.push_back({{"revolve", p.revolve}, {"origin", xyz(p.origin + offset)}, {"u", xyz(p.u)}, {"v", xyz(p.v)},
                     {"path", xyz(p.path)}, {"start", xy(p.start)}, {"steps", steps}});
    if (!p.roof.empty()) parts.back()["roof"] = spline_json(p.roof, offset);
  }
  return nlohmann::json{{"parts", parts}}.dump();
}

ExactShape exact_shape_from_json(const std::string& text, const Vec3& offset) {
  ExactShape shape;
  if (text.empty()) return shape;
  try {
    const nlohmann::json doc = nlohmann::json::parse(text);  // held: the loop walks its parts
    for (const nlohmann::json& j : doc.at("parts")) {
      ShapePart p;
      p.revolve = j.at("revolve").get<bool>();
      p.origin = vec3(j.at("origin")) - offset;
      p.u = vec3(j.at("u")), p.v = vec3(j.at("v")), p.path = vec3(j.at("path"));
      p.start = vec2(j.at("start"));
      for (const nlohmann::json& s : j.at("steps")) {
        ProfileStep step;
        step.kind = kind_from(s.at("kind").get<std::string>());
        for (const nlohmann::json& q : s.at("through")) step.through.push_back(vec2(q));
        step.to = vec2(s.at("to"));
        p.steps.push_back(std::move(step));
      }
      if (j.contains("roof")) p.roof = spline_from(j.at("roof"), offset);
      shape.parts.push_back(std::move(p));
    }
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(std::string("exact shape: ") + e.what());
  }
  return shape;
}

}  // namespace c3d

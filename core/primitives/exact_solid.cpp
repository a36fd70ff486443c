#include "core/primitives/exact_solid.h"

#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepGProp.hxx>
#include <BRepAlgoAPI_Common.hxx>
#include <BRepPrimAPI_MakeHalfSpace.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <BRepPrimAPI_MakeRevol.hxx>
#include <GC_MakeArcOfCircle.hxx>
#include <GProp_GProps.hxx>
#include <GeomAPI_PointsToBSpline.hxx>
#include <Geom_BSplineCurve.hxx>
#include <ShapeUpgrade_UnifySameDomain.hxx>
#include <Standard_Failure.hxx>
#include <TColgp_HArray1OfPnt.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Solid.hxx>
#include <TopoDS_Wire.hxx>
#include <gp_Ax1.hxx>

#include <cmath>
#include <stdexcept>

#include "core/primitives/exact_shape.h"
#include "core/primitives/spline_surface.h"

namespace c3d {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSamePointM = 1e-7;
constexpr double kSplineTolM = 0.005;

gp_Pnt at(const ShapePart& p, const Vec2& q) {
  const Vec3 w = p.origin + q.x() * p.u + q.y() * p.v;
  return gp_Pnt(w.x(), w.y(), w.z());
}

TopoDS_Edge step_edge(const ShapePart& p, const Vec2& from, const ProfileStep& s) {
  switch (s.kind) {
    case ProfileStep::Kind::Line: return BRepBuilderAPI_MakeEdge(at(p, from), at(p, s.to)).Edge();
    case ProfileStep::Kind::Arc: {
      if (s.through.size() != 1) throw std::runtime_error("an arc needs one point on it");
      GC_MakeArcOfCircle arc(at(p, from), at(p, s.through[0]), at(p, s.to));
      if (!arc.IsDone()) throw std::runtime_error("no arc through its three points");
      return BRepBuilderAPI_MakeEdge(arc.Value()).Edge();
    }
    case ProfileStep::Kind::Spline: {
      Handle(TColgp_HArray1OfPnt) pts = new TColgp_HArray1OfPnt(1, int(s.through.size()) + 2);
      pts->SetValue(1, at(p, from));
      for (size_t k = 0; k < s.through.size(); ++k) pts->SetValue(int(k) + 2, at(p, s.through[k]));
      pts->SetValue(int(s.through.size()) + 2, at(p, s.to));
      // Approximated within kSplineTolM, not interpolated: a profile read
      // from points wiggles by their noise, which interpolation amplifies.
      GeomAPI_PointsToBSpline spline(pts->Array1(), 3, 8, GeomAbs_C2, kSplineTolM);
      if (!spline.IsDone()) throw std::runtime_error("no spline along its points");
      return BRepBuilderAPI_MakeEdge(spline.Curve()).Edge();
    }
  }
  throw std::logic_error("step_edge: unknown kind");
}

TopoDS_Wire profile_wire(const ShapePart& p) {
  BRepBuilderAPI_MakeWire wire;
  Vec2 from = p.start;
  auto add = [&](const Vec2& to, const ProfileStep& s) {
    if ((to - from).norm() <= kSamePointM) return;
    wire.Add(step_edge(p, from, s));
    if (!wire.IsDone()) throw std::runtime_error("profile steps do not join");
    from = to;
  };
  for (const ProfileStep& s : p.steps) add(s.to, s);
  add(p.start, ProfileStep{ProfileStep::Kind::Line, {}, p.start});
  return wire.Wire();
}

// The part of a hall's prism under its free-form roof: the prism in common
// with the half-space below the roof's surface (which spans its plan).
TopoDS_Shape under_roof(const TopoDS_Shape& prism, const SplineSurface& roof, double floor_z) {
  BRepBuilderAPI_MakeFace face(occ_surface(roof), kSamePointM);
  if (!face.IsDone()) throw std::runtime_error("no face on the roof's spline surface");
  const Vec3& corner = roof.poles.front();
  const gp_Pnt under(corner.x(), corner.y(), floor_z - 1e3);
  const TopoDS_Shape below = BRepPrimAPI_MakeHalfSpace(face.Face(), under).Solid();
  BRepAlgoAPI_Common common(prism, below);
  if (!common.IsDone()) throw std::runtime_error("the roof's surface does not cut the hall");
  return common.Shape();
}

TopoDS_Shape part_solid(const ShapePart& p) {
  BRepBuilderAPI_MakeFace face(profile_wire(p), /*OnlyPlane=*/true);
  if (!face.IsDone()) throw std::runtime_error("profile is not a plane face");
  if (!p.revolve) {
    const TopoDS_Shape prism = BRepPrimAPI_MakePrism(face.Face(), gp_Vec(p.path.x(), p.path.y(), p.path.z())).Shape();
    return p.roof.empty() ? prism : under_roof(prism, p.roof, p.origin.z());
  }
  const gp_Ax1 axis(at(p, Vec2::Zero()), gp_Dir(p.v.x(), p.v.y(), p.v.z()));
  return BRepPrimAPI_MakeRevol(face.Face(), axis, 2 * kPi).Shape();
}

}  // namespace

TopoDS_Shape exact_solid(const ExactShape& shape) {
  if (shape.parts.empty()) throw std::runtime_error("no exact shape");
  TopoDS_Shape all;
  try {
    for (const ShapePart& p : shape.parts) {
      const TopoDS_Shape s = part_solid(p);
      if (all.IsNull()) {
        all = s;
        continue;
      }
      BRepAlgoAPI_Fuse fuse(all, s);
      if (!fuse.IsDone()) throw std::runtime_error("parts do not fuse");
      all = fuse.Shape();
    }
    ShapeUpgrade_UnifySameDomain unify(all, true, true, false);  // one face per plane the parts share
    unify.Build();
    all = unify.Shape();
  } catch (const Standard_Failure& e) {
    throw std::runtime_error(std::string("OpenCASCADE: ") + (e.GetMessageString() ? e.GetMessageString() : "failed"));
  }
  TopExp_Explorer solids(all, TopAbs_SOLID);
  if (!solids.More()) throw std::runtime_error("exact shape makes no solid");
  const TopoDS_Solid solid = TopoDS::Solid(solids.Current());
  solids.Next();
  if (solids.More()) throw std::runtime_error("exact shape makes more than one solid");
  if (!BRepCheck_Analyzer(solid).IsValid()) throw std::runtime_error("exact solid is not valid");
  return solid;
}

double exact_volume(const ExactShape& shape) {
  try {
    GProp_GProps props;
    BRepGProp::VolumeProperties(exact_solid(shape), props);
    return props.Mass();
  } catch (const std::runtime_error&) {
    return kNaN;
  }
}

}  // namespace c3d

#include "core/check/occ_check.h"

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepGProp.hxx>
#include <GProp_GProps.hxx>
#include <ShapeFix_Face.hxx>
#include <Standard_Failure.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <TopoDS_Wire.hxx>
#include <gp_Pln.hxx>

#include "core/geometry/geometry.h"

namespace c3d {
namespace {

constexpr double kSewTol = 1e-5;

bool make_wire(const Ring3& ring, bool reverse, TopoDS_Wire& wire) {
  BRepBuilderAPI_MakePolygon poly;
  const int n = int(ring.size());
  for (int k = 0; k < n; ++k) {
    const Vec3& p = ring[reverse ? n - 1 - k : k];
    poly.Add(gp_Pnt(p.x(), p.y(), p.z()));
  }
  poly.Close();
  if (!poly.IsDone()) return false;
  wire = poly.Wire();
  return true;
}

// A planar face on the plane through the ring centroid with the ring's normal;
// holes are wound opposite to the outer ring, as OCC expects.
bool make_face(const Face& f, TopoDS_Face& face) {
  if (f.ring.size() < 3) return false;
  const Vec3 n = unit_normal(f);
  Vec3 c = Vec3::Zero();
  for (const auto& p : f.ring) c += p;
  c /= double(f.ring.size());
  TopoDS_Wire outer;
  if (!make_wire(f.ring, false, outer)) return false;
  BRepBuilderAPI_MakeFace mf(gp_Pln(gp_Pnt(c.x(), c.y(), c.z()), gp_Dir(n.x(), n.y(), n.z())), outer);
  if (!mf.IsDone()) return false;
  for (const auto& h : f.holes) {
    TopoDS_Wire w;
    if (!make_wire(h, newell_normal(h).dot(n) > 0, w)) return false;
    mf.Add(w);
  }
  ShapeFix_Face fix(mf.Face());
  fix.Perform();
  face = fix.Face();
  return true;
}

}  // namespace

OccMeasures occ_measure(const std::vector<Face>& shell) {
  OccMeasures m;
  try {
    BRepBuilderAPI_Sewing sew(kSewTol);
    for (size_t i = 0; i < shell.size(); ++i) {
      TopoDS_Face face;
      if (!make_face(shell[i], face)) {
        m.problem = "face " + std::to_string(i) + " could not be built";
        return m;
      }
      sew.Add(face);
    }
    sew.Perform();
    const TopoDS_Shape sewn = sew.SewedShape();
    m.free_edges = sew.NbFreeEdges();
    GProp_GProps surf;
    BRepGProp::SurfaceProperties(sewn, surf);
    m.area = surf.Mass();

    int shells = 0;
    TopoDS_Shell the_shell;
    for (TopExp_Explorer ex(sewn, TopAbs_SHELL); ex.More(); ex.Next(), ++shells)
      the_shell = TopoDS::Shell(ex.Current());
    if (shells != 1) {
      m.problem = "sewing gave " + std::to_string(shells) + " shells";
      return m;
    }
    BRepBuilderAPI_MakeSolid ms(the_shell);
    if (!ms.IsDone()) {
      m.problem = "no solid from the shell";
      return m;
    }
    GProp_GProps vol;
    BRepGProp::VolumeProperties(ms.Solid(), vol);
    m.volume = vol.Mass();
    m.ok = m.free_edges == 0;
    if (!m.ok) m.problem = std::to_string(m.free_edges) + " free edges after sewing";
  } catch (const Standard_Failure& e) {
    m.ok = false;
    m.problem = std::string("OpenCASCADE: ") + e.GetMessageString();
  }
  return m;
}

}  // namespace c3d

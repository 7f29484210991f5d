// The STEP writer of `ltca geometry --step` (docs/export.md), a shared module that alone links
// OpenCASCADE: `ltca` loads it with dlopen() only for --step, so no other command's start-up loads
// OpenCASCADE (ltca_step.h). The disc as one solid:
//   - each smooth piece of the outline a cubic B-spline interpolating points of the analytic curve
//     (GeomAPI_Interpolate, chord-length parameters), measured against further analytic points
//     between them (GeomAPI_ProjectPointOnCurve): no file when one strays beyond the tolerance;
//   - the pieces a closed wire, a planar face with the holes (circles) as inner wires;
//   - the face extruded over the width (BRepPrimAPI_MakePrism), checked by BRepCheck_Analyzer;
//   - written as AP214 in millimetres (STEPControl_Writer).
#include "ltca_step.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>

#include <APIHeaderSection_MakeHeader.hxx>
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <GC_MakeCircle.hxx>
#include <GeomAPI_Interpolate.hxx>
#include <GeomAPI_ProjectPointOnCurve.hxx>
#include <Geom_BSplineCurve.hxx>
#include <Geom_Circle.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>

#include <Standard_Failure.hxx>
#include <STEPControl_Writer.hxx>
#include <TColgp_HArray1OfPnt.hxx>
#include <TCollection_HAsciiString.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <TopoDS_Wire.hxx>
#include <gp_Ax2.hxx>
#include <gp_Circ.hxx>
#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>

namespace {

void Fail(LtcaStepReport* report, const std::string& what) {
  std::snprintf(report->error, sizeof(report->error), "%s", what.c_str());
}

/// Distance of p from the curve (its nearest point; the curve's ends when no foot is interior).
double Distance(const gp_Pnt& p, const Handle(Geom_BSplineCurve)& curve) {
  GeomAPI_ProjectPointOnCurve projection(p, curve);
  double d = std::min(p.Distance(curve->StartPoint()), p.Distance(curve->EndPoint()));
  if (projection.NbPoints() > 0) d = std::min(d, projection.LowerDistance());
  return d;
}

int Write(const LtcaStepDisc& disc, LtcaStepReport* report) {
  if (disc.abi_version != LTCA_STEP_ABI_VERSION) {
    Fail(report, "ltca_step.so does not match this ltca (ABI version " + std::to_string(disc.abi_version) +
                     ", the module's " + std::to_string(LTCA_STEP_ABI_VERSION) + ")");
    return 1;
  }
  if (disc.piece_count < 1 || !(disc.width_mm > 0.0)) {
    Fail(report, "no outline or no width");
    return 1;
  }
  BRepBuilderAPI_MakeWire outline;
  for (int i = 0; i < disc.piece_count; ++i) {
    const int first = disc.piece_offsets[i], last = disc.piece_offsets[i + 1];
    if (last - first < 2) {
      Fail(report, "outline piece " + std::to_string(i) + " has fewer than two points");
      return 1;
    }
    Handle(TColgp_HArray1OfPnt) points = new TColgp_HArray1OfPnt(1, last - first);
    for (int j = first; j < last; ++j) {
      points->SetValue(j - first + 1, gp_Pnt(disc.points_xy[2 * j], disc.points_xy[2 * j + 1], 0.0));
    }
    GeomAPI_Interpolate interpolate(points, Standard_False, 1e-9);
    interpolate.Perform();
    if (!interpolate.IsDone()) {
      Fail(report, "GeomAPI_Interpolate failed on outline piece " + std::to_string(i));
      return 1;
    }
    const Handle(Geom_BSplineCurve) curve = interpolate.Curve();
    report->poles += curve->NbPoles();
    for (int j = 1; j <= points->Length(); ++j) {
      report->max_node_deviation_mm = std::max(report->max_node_deviation_mm, Distance(points->Value(j), curve));
    }
    for (int j = disc.check_offsets[i]; j < disc.check_offsets[i + 1]; ++j) {
      const gp_Pnt p(disc.check_xy[2 * j], disc.check_xy[2 * j + 1], 0.0);
      report->max_check_deviation_mm = std::max(report->max_check_deviation_mm, Distance(p, curve));
    }
    BRepBuilderAPI_MakeEdge edge(curve);
    if (!edge.IsDone()) {
      Fail(report, "no edge from outline piece " + std::to_string(i));
      return 1;
    }
    outline.Add(edge.Edge());
    if (!outline.IsDone()) {
      Fail(report, "outline piece " + std::to_string(i) + " does not join its predecessor");
      return 1;
    }
  }
  const double worst = std::max(report->max_node_deviation_mm, report->max_check_deviation_mm);
  if (!(worst <= disc.tolerance_mm)) {
    char text[200];
    std::snprintf(text, sizeof(text), "the B-splines stray %.3g mm from the analytic profile (more than %.3g mm)", worst,
                  disc.tolerance_mm);
    Fail(report, text);
    return 1;
  }
  if (!outline.Wire().Closed()) {
    Fail(report, "the outline is not closed");
    return 1;
  }
  BRepBuilderAPI_MakeFace face(outline.Wire(), Standard_True);
  if (!face.IsDone()) {
    Fail(report, "no planar face from the outline");
    return 1;
  }
  for (int h = 0; h < disc.hole_count; ++h) {
    const double* c = disc.holes_xyr + 3 * h;
    // Clockwise seen from +z (the axis -z): an inner wire of the face.
    const gp_Circ circle(gp_Ax2(gp_Pnt(c[0], c[1], 0.0), gp_Dir(0.0, 0.0, -1.0)), c[2]);
    const TopoDS_Wire wire = BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(circle).Edge()).Wire();
    face.Add(wire);
  }
  BRepPrimAPI_MakePrism prism(face.Face(), gp_Vec(0.0, 0.0, disc.width_mm));
  prism.Build();
  if (!prism.IsDone()) {
    Fail(report, "the extrusion failed");
    return 1;
  }
  const TopoDS_Shape solid = prism.Shape();
  report->solid_valid = BRepCheck_Analyzer(solid).IsValid() ? 1 : 0;
  if (report->solid_valid == 0) {
    Fail(report, "the solid is not valid (BRepCheck_Analyzer)");
    return 1;
  }

  STEPControl_Writer writer;
  Interface_Static::SetCVal("write.step.schema", "AP214IS");
  Interface_Static::SetCVal("write.step.unit", "MM");
  Interface_Static::SetCVal("write.precision.mode", "0");
  if (writer.Transfer(solid, STEPControl_AsIs) != IFSelect_RetDone) {
    Fail(report, "the solid could not be transferred to STEP");
    return 1;
  }
  APIHeaderSection_MakeHeader header(writer.Model());
  header.SetName(new TCollection_HAsciiString(disc.name != nullptr ? disc.name : disc.path));
  header.SetOriginatingSystem(new TCollection_HAsciiString("ltca"));
  header.SetDescriptionValue(1, new TCollection_HAsciiString(disc.description));
  if (writer.Write(disc.path) != IFSelect_RetDone) {
    Fail(report, std::string(disc.path) + ": STEPControl_Writer could not write the file");
    return 1;
  }
  return 0;
}

}  // namespace

extern "C" __attribute__((visibility("default"))) int ltca_step_write(const LtcaStepDisc* disc, LtcaStepReport* report) {
  if (report == nullptr) return 1;
  *report = LtcaStepReport{};
  if (disc == nullptr) {
    Fail(report, "no disc");
    return 1;
  }
  try {
    // OpenCASCADE's messages (the STEP writer's statistics) stay off ltca's standard output.
    Message::DefaultMessenger()->ChangePrinters().Clear();
    return Write(*disc, report);
  } catch (const Standard_Failure& e) {
    Fail(report, std::string("OpenCASCADE: ") + e.GetMessageString());
  } catch (const std::exception& e) {
    Fail(report, e.what());
  } catch (...) {
    Fail(report, "an unknown exception");
  }
  return 1;
}

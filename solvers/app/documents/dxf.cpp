#include "documents/dxf.hpp"

#include <cerrno>
#include <cstring>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <dl_dxf.h>
#include <dl_writer_ascii.h>
#include <fmt/format.h>

#include "ltca/app/temporaries.hpp"
#include "ltca/contact/holes.hpp"
#include "ltca/geometry/outline.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/reducer.hpp"

namespace ltca::app::documents {
namespace {

struct Layer {
  const char* name;
  int colour;  // AutoCAD colour index
};
constexpr Layer kLayers[] = {{"DISC_PROFILE", 7}, {"BORE", 1}, {"HOLES", 3}, {"PIN_RING", 5}, {"OUTPUT_PINS", 6}};

DL_Attributes On(const char* layer) { return DL_Attributes(layer, 256, -1, -1, "BYLAYER"); }  // colour by layer

}  // namespace

std::size_t DxfProfileVertices(const geometry::RealPair& real, double sagitta) {
  return geometry::OutlinePolyline(real.profile(), sagitta).size();
}

std::string Dxf(const Deck& deck, const geometry::RealPair& real, const std::string& scratch_folder, double sagitta) {
  const std::vector<Eigen::Vector2d> outline = geometry::OutlinePolyline(real.profile(), sagitta);
  app::ScratchFile scratch;
  std::string pattern = (scratch_folder.empty() ? std::string(".") : scratch_folder) + "/.ltca-dxf-XXXXXX";
  if (!app::CreateTemporary(pattern, false)) {
    throw std::runtime_error(fmt::format("{}: cannot create a temporary file for the DXF ({})", pattern, std::strerror(errno)));
  }
  scratch.path = pattern;
  {
    DL_Dxf dxf;
    const DL_Codes::version version = DL_Codes::AC1015;
    std::unique_ptr<DL_WriterA> dw(dxf.out(scratch.path.c_str(), version));
    if (dw == nullptr || dw->openFailed()) throw std::runtime_error(fmt::format("{}: cannot write the DXF", scratch.path));
    dxf.writeHeader(*dw);
    dw->dxfString(9, "$INSUNITS");
    dw->dxfInt(70, 4);  // millimetres
    dw->dxfString(9, "$MEASUREMENT");
    dw->dxfInt(70, 1);  // metric
    dw->sectionEnd();
    dw->sectionTables();
    dxf.writeVPort(*dw);
    dw->tableLinetypes(3);
    dxf.writeLinetype(*dw, DL_LinetypeData("BYBLOCK", "", 0, 0, 0.0));
    dxf.writeLinetype(*dw, DL_LinetypeData("BYLAYER", "", 0, 0, 0.0));
    dxf.writeLinetype(*dw, DL_LinetypeData("CONTINUOUS", "Solid line", 0, 0, 0.0));
    dw->tableEnd();
    dw->tableLayers(1 + static_cast<int>(std::size(kLayers)));
    dxf.writeLayer(*dw, DL_LayerData("0", 0), DL_Attributes("", 7, 100, "CONTINUOUS", 1.0));
    for (const Layer& l : kLayers) dxf.writeLayer(*dw, DL_LayerData(l.name, 0), DL_Attributes("", l.colour, 100, "CONTINUOUS", 1.0));
    dw->tableEnd();
    dw->tableStyle(1);
    dxf.writeStyle(*dw, DL_StyleData("standard", 0, 2.5, 1.0, 0.0, 0, 2.5, "txt", ""));
    dw->tableEnd();
    dxf.writeView(*dw);
    dxf.writeUcs(*dw);
    dw->tableAppid(1);
    dxf.writeAppid(*dw, "ACAD");
    dw->tableEnd();
    dxf.writeDimStyle(*dw, 1, 1, 1, 1, 1);
    dxf.writeBlockRecord(*dw);
    dw->tableEnd();
    dw->sectionEnd();
    dw->sectionBlocks();
    dxf.writeBlock(*dw, DL_BlockData("*Model_Space", 0, 0.0, 0.0, 0.0));
    dxf.writeEndBlock(*dw, "*Model_Space");
    dxf.writeBlock(*dw, DL_BlockData("*Paper_Space", 0, 0.0, 0.0, 0.0));
    dxf.writeEndBlock(*dw, "*Paper_Space");
    dxf.writeBlock(*dw, DL_BlockData("*Paper_Space0", 0, 0.0, 0.0, 0.0));
    dxf.writeEndBlock(*dw, "*Paper_Space0");
    dw->sectionEnd();

    dw->sectionEntities();
    // The profile: one closed polyline (flag 1).
    dxf.writePolyline(*dw, DL_PolylineData(static_cast<int>(outline.size()), 0, 0, 1), On("DISC_PROFILE"));
    for (const Eigen::Vector2d& p : outline) dxf.writeVertex(*dw, DL_VertexData(p.x(), p.y(), 0.0, 0.0));
    dxf.writePolylineEnd(*dw);
    // The bore.
    if (deck.disc.bore_radius > 0.0) dxf.writeCircle(*dw, DL_CircleData(0.0, 0.0, 0.0, deck.disc.bore_radius), On("BORE"));
    // The ring's pins where they stand at crank 0, in the disc's body frame.
    const geometry::Pose pose = real.CycloidPose(0.0);
    for (int j = 0; j < real.nominal().pin_count; ++j) {
      const Eigen::Vector2d c = pose.ToBody(real.PinCentre(j));
      dxf.writeCircle(*dw, DL_CircleData(c.x(), c.y(), 0.0, real.PinRadius(j)), On("PIN_RING"));
    }
    // [output]: the holes in the disc and the output pins at crank 0.
    if (deck.reducer) {
      const solvers::ReducerSettings& reducer = *deck.reducer;
      if (reducer.kind == solvers::OutputKind::kPins) {
        const contact::OutputPins& w = reducer.pins;
        const std::vector<Eigen::Vector2d> holes = contact::HolesInDisc(w.circle_radius, w.count, w.phase, w.hole_deviation);
        for (int j = 0; j < w.count; ++j) {
          const double alpha = 2.0 * units::kPi * j / w.count + w.phase;
          const Eigen::Vector2d& hole = holes[static_cast<std::size_t>(j)];
          dxf.writeCircle(*dw, DL_CircleData(hole.x(), hole.y(), 0.0, w.hole_radius), On("HOLES"));
          const Eigen::Vector2d pin = pose.ToBody(w.circle_radius * Eigen::Vector2d(std::cos(alpha), std::sin(alpha)));
          dxf.writeCircle(*dw, DL_CircleData(pin.x(), pin.y(), 0.0, w.pin_radius), On("OUTPUT_PINS"));
        }
      } else {
        const contact::Cranks& k = reducer.cranks;
        for (const Eigen::Vector2d& hole : contact::HolesInDisc(k.circle_radius, k.count, k.phase, k.hole_deviation)) {
          dxf.writePoint(*dw, DL_PointData(hole.x(), hole.y(), 0.0), On("HOLES"));
        }
      }
    }
    dw->sectionEnd();
    dxf.writeObjects(*dw);
    dxf.writeObjectsEnd(*dw);
    dw->dxfEOF();
    dw->close();
  }
  std::ifstream in(scratch.path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) throw std::runtime_error(fmt::format("{}: cannot read back the DXF", scratch.path));
  return text.str();
}

}  // namespace ltca::app::documents

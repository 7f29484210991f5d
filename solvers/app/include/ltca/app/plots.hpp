#pragma once
// Figures: every plot of ltca is drawn here, in one visual style, by a plotting
// library (PLplot, docs/plots.md). This header holds plain data only; the library stays in
// solvers/app/src/plots.cpp.
//
// A Figure is a grid of Panels under one title, with a caption (the source deck) at the foot.
// A Panel has axes with ticks, a grid, labels with units, its series and reference marks, and a
// legend when it holds more than one labelled series.
#include <algorithm>
#include <cstddef>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace ltca::app::plots {

enum class Style {
  kLine,         ///< a polyline through the points
  kMarkers,      ///< a marker at each point
  kLineMarkers,  ///< both
  kBars,         ///< a vertical bar from 0 to y at each x (Series::bar_width wide)
  kPolygon,      ///< a closed outline, filled with a light tint of the series colour
  kOutline,      ///< a closed outline, not filled
};

/// One series. An empty label keeps it out of the legend (outlines that are part of a drawing).
struct Series {
  std::string label;
  std::vector<double> x, y;
  Style style = Style::kLine;
  int colour = -1;   ///< index into the palette (0..7); -1: the series' order among labelled ones
  int marker = -1;   ///< index into the markers (0..7); -1: as colour
  bool dashed = false;
  double bar_width = 0.8;
  double marker_size = 1.0;  ///< relative: curves that coincide stay visible with nested markers
};

/// A horizontal (y = value) or vertical (x = value) reference line with its label.
struct Mark {
  enum class Axis { kHorizontal, kVertical };
  Axis axis = Axis::kHorizontal;
  double value = 0.0;
  std::string label;
  bool dashed = false;
  bool dotted = false;  ///< a third style (e.g. a worst-case corner beside dashed percentiles)
};

/// Text at a point in the panel's data coordinates; justification 0 left, 0.5 centre, 1 right.
struct Note {
  double x = 0.0, y = 0.0;
  std::string text;
  double justification = 0.5;
  double size = 0.8;  ///< relative to the tick labels
};

/// A colour map of z over a grid of cells (a pin x crank-angle map): z[i][j] is the cell at
/// (x[i], y[j]), centres; NaN cells are left blank. Drawn with a colour bar labelled z_label.
struct Map {
  std::vector<double> x, y;
  std::vector<std::vector<double>> z;
  std::string z_label;  ///< with its unit, e.g. "pin force (N)"
};

enum class LegendPlace { kTopRight, kTopLeft, kBottomRight, kBottomLeft, kOutsideRight };

struct Panel {
  std::string title;             ///< above the panel
  std::string x_label, y_label;  ///< with units, e.g. "crank angle (deg)"
  std::vector<Series> series;
  std::vector<Mark> marks;
  std::vector<Note> notes;
  std::optional<Map> map;  ///< drawn under the series
  bool log_x = false, log_y = false;
  bool equal_scale = false;  ///< one mm is as long on both axes (drawings)
  std::optional<double> x_min, x_max, y_min, y_max;  ///< default: the data, padded 4 %
  LegendPlace legend = LegendPlace::kTopRight;
  /// Labelled series: those the legend shows (and the SVG's metadata lists).
  std::size_t LabelledSeries() const {
    return static_cast<std::size_t>(std::count_if(series.begin(), series.end(), [](const Series& s) { return !s.label.empty(); }));
  }
};

struct Figure {
  std::string title;    ///< names the case and the crank angle or range
  std::string caption;  ///< the source deck (and the model that ran); lines split at '\n'
  std::vector<Panel> panels;
  int columns = 1;
  int width = 900, height = 560;  ///< pixels (SVG user units)
};

/// The drawing module (ltca_plots.so, loaded at run time) is handed a Figure, C++ objects of this
/// header, so it must be built from the same declarations. kPlotsAbiVersion is raised with any
/// change to the structs above; PlotsAbi(version) names it with the project's version and the
/// structs' sizes. The module exports its own (ltca_plots_abi) and the loader refuses a module
/// whose text differs, naming both.
inline constexpr int kPlotsAbiVersion = 1;
inline std::string PlotsAbi(const std::string& version) {
  return "ltca " + version + ", plots ABI " + std::to_string(kPlotsAbiVersion) + ", sizes " + std::to_string(sizeof(Figure)) +
         "/" + std::to_string(sizeof(Panel)) + "/" + std::to_string(sizeof(Series)) + "/" + std::to_string(sizeof(Map)) + "/" +
         std::to_string(sizeof(Mark));
}

enum class Format { kSvg, kPng, kPdf };

/// The format a path asks for by its extension: .png, .pdf, else SVG (also for "-").
Format FormatForPath(const std::string& path);
const char* FormatName(Format format);

/// Throws std::runtime_error naming the missing package when the library cannot draw in this
/// format (so that a command can refuse before computing).
void RequireFormat(Format format);

/// Draws the figure and writes it to the stream. SVG carries a <title>, a <desc> (the caption)
/// and a <metadata> listing every panel's axis labels and labelled series, for tests and
/// scripts. Throws std::runtime_error when the library cannot draw in that format (a missing
/// driver package). Safe to call from several threads (the library is not: calls are
/// serialised).
void Write(const Figure& figure, std::ostream& os, Format format = Format::kSvg);

/// Text escaped for XML and HTML (& < > "): the figures' metadata and the report's tables.
std::string XmlEscape(const std::string& text);

}  // namespace ltca::app::plots

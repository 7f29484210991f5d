// Figures drawn by PLplot (docs/plots.md). PLplot keeps global state and is not
// thread-safe: every call runs under one mutex. It writes to a named file: each figure is drawn
// into a temporary file, which is then copied to the stream (SVG with its metadata added).
#include "ltca/app/plots.hpp"

#include "ltca/app/temporaries.hpp"

#include <plplot.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace ltca::app::plots {
namespace {

// cmap0: 0 background, 1 ink, 2 reference marks, 3 grid, 4..11 the palette, 12..19 its tints, 20 a map cell.
constexpr int kInk = 1, kMarkInk = 2, kGridInk = 3, kPalette = 4, kTint = 12, kColours = 21;  // 20: a map cell
// Okabe and Ito's colour-blind-safe palette (black replaced by a blue-grey), then light tints.
constexpr std::array<std::array<int, 3>, 8> kRgb = {{{0, 114, 178},
                                                     {213, 94, 0},
                                                     {0, 158, 115},
                                                     {204, 121, 167},
                                                     {230, 159, 0},
                                                     {86, 180, 233},
                                                     {120, 120, 120},
                                                     {240, 228, 66}}};
// One marker per palette entry, so that colour and marker both tell the series apart.
constexpr std::array<const char*, 8> kMarkers = {"●", "■", "▲", "◆", "▼", "✚", "✖", "★"};

/// Text height at scale 1, mm: set from the page after plinit so that text is ~17 px high at
/// scale 1 whatever the page size (PLplot's default scales with the page).
double g_char_mm = 0.0;
void Chr(double scale) { plschr(g_char_mm, scale); }

std::mutex& Lock() {
  static std::mutex m;
  return m;
}

/// Characters of a text drawn by PLplot at most: PLplot crashes in plend (SIGSEGV) on a string of
/// about 980 characters or more; a figure's title is unreadable long before that.
constexpr std::size_t kMaxDrawnCharacters = 200;

/// PLplot's text escape is '#' (#u superscript, ...): a literal '#' is "##". A text longer than
/// kMaxDrawnCharacters is cut there (at a UTF-8 character boundary) and ends in "..."; a control
/// character is drawn as a space. The SVG's <title> and <desc> keep the whole text.
std::string Pl(const std::string& text) {
  std::string out;
  out.reserve(std::min(text.size(), 4 * kMaxDrawnCharacters) + 3);
  std::size_t characters = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    const bool starts_character = (c & 0xC0) != 0x80;
    if (starts_character && characters++ == kMaxDrawnCharacters) {
      out += "...";
      break;
    }
    if (c < 0x20 || c == 0x7f) {
      out += ' ';
    } else {
      out += text[i];
      if (text[i] == '#') out += '#';
    }
  }
  return out;
}


const char* Device(Format format) {
  switch (format) {
    case Format::kPng: return "pngcairo";
    case Format::kPdf: return "pdfcairo";
    case Format::kSvg: break;
  }
  return "svg";  // PLplot's own SVG driver (libplplot17), no cairo needed
}

bool HasDevice(const char* name) {
  const char** menu = nullptr;
  const char** devices = nullptr;
  int n = 64;
  std::vector<const char*> m(static_cast<std::size_t>(n)), d(static_cast<std::size_t>(n));
  menu = m.data();
  devices = d.data();
  plgDevs(&menu, &devices, &n);
  for (int i = 0; i < n; ++i) {
    if (devices[i] != nullptr && std::string(devices[i]) == name) return true;
  }
  return false;
}

int ColourOf(const Series& s, int order) { return s.colour >= 0 ? s.colour % 8 : order % 8; }
int MarkerOf(const Series& s, int order) { return s.marker >= 0 ? s.marker % 8 : ColourOf(s, order); }

struct Range {
  double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
  void Add(double v) {
    if (!std::isfinite(v)) return;
    lo = std::min(lo, v), hi = std::max(hi, v);
  }
  bool Empty() const { return !(lo <= hi); }
};

double Axis(double v, bool log) { return log ? (v > 0.0 ? std::log10(v) : std::numeric_limits<double>::quiet_NaN()) : v; }

/// The panel's data range on one axis (log10 on a log axis), padded, with the given limits.
Range DataRange(const Panel& p, bool x_axis) {
  const bool log = x_axis ? p.log_x : p.log_y;
  Range r;
  for (const Series& s : p.series) {
    const auto& v = x_axis ? s.x : s.y;
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (s.style == Style::kBars && x_axis) {
        r.Add(Axis(v[i] - s.bar_width / 2, log)), r.Add(Axis(v[i] + s.bar_width / 2, log));
      } else {
        r.Add(Axis(v[i], log));
      }
    }
    if (s.style == Style::kBars && !x_axis) r.Add(0.0);
  }
  for (const Mark& m : p.marks) {
    if ((m.axis == Mark::Axis::kVertical) == x_axis) r.Add(Axis(m.value, log));
  }
  if (r.Empty()) r = {0.0, 1.0};  // no data: 0..1 (1..10 on a log axis)
  if (r.hi - r.lo < 1e-12 * std::max(1.0, std::abs(r.hi))) {
    const double d = log ? 0.5 : std::max(std::abs(r.hi) * 0.1, 1e-9);
    r.lo -= d, r.hi += d;
  } else {
    const double pad = 0.04 * (r.hi - r.lo);
    r.lo -= pad, r.hi += pad;
  }
  const auto lo = x_axis ? p.x_min : p.y_min;
  const auto hi = x_axis ? p.x_max : p.y_max;
  if (lo) r.lo = Axis(*lo, log);
  if (hi) r.hi = Axis(*hi, log);
  return r;
}

void Polyline(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() >= 2) plline(static_cast<PLINT>(x.size()), x.data(), y.data());
}

/// Draws one series in data coordinates (log10 already applied to the vectors).
void DrawSeries(const Series& s, int order, const std::vector<double>& x, const std::vector<double>& y) {
  const int colour = ColourOf(s, order);
  pllsty(s.dashed ? 2 : 1);
  plwidth(1.6);
  switch (s.style) {
    case Style::kBars:
      for (std::size_t i = 0; i < x.size(); ++i) {
        if (!std::isfinite(x[i]) || !std::isfinite(y[i]) || y[i] == 0.0) continue;
        const double h = s.bar_width / 2;
        const std::array<double, 4> bx = {x[i] - h, x[i] + h, x[i] + h, x[i] - h};
        const std::array<double, 4> by = {0.0, 0.0, y[i], y[i]};
        plcol0(kTint + colour);
        plfill(4, bx.data(), by.data());
        plcol0(kPalette + colour);
        plwidth(1.0);
        const std::array<double, 5> ox = {bx[0], bx[1], bx[2], bx[3], bx[0]};
        const std::array<double, 5> oy = {by[0], by[1], by[2], by[3], by[0]};
        plline(5, ox.data(), oy.data());
      }
      break;
    case Style::kPolygon:
    case Style::kOutline: {
      std::vector<double> cx(x), cy(y);
      if (!cx.empty()) cx.push_back(cx.front()), cy.push_back(cy.front());
      if (s.style == Style::kPolygon && x.size() >= 3) {
        plcol0(kTint + colour);
        plfill(static_cast<PLINT>(x.size()), x.data(), y.data());
      }
      plcol0(kPalette + colour);
      plwidth(1.2);
      Polyline(cx, cy);
      break;
    }
    default: {
      plcol0(kPalette + colour);
      if (s.style != Style::kMarkers) {
        // Break the line at non-finite points (a failed position is a gap, not a zero).
        std::vector<double> px, py;
        for (std::size_t i = 0; i <= x.size(); ++i) {
          if (i < x.size() && std::isfinite(x[i]) && std::isfinite(y[i])) {
            px.push_back(x[i]), py.push_back(y[i]);
          } else {
            Polyline(px, py);
            px.clear(), py.clear();
          }
        }
      }
      if (s.style != Style::kLine) {
        std::vector<double> px, py;
        for (std::size_t i = 0; i < x.size(); ++i) {
          if (std::isfinite(x[i]) && std::isfinite(y[i])) px.push_back(x[i]), py.push_back(y[i]);
        }
        Chr(0.42 * s.marker_size);
        if (!px.empty()) plstring(static_cast<PLINT>(px.size()), px.data(), py.data(), kMarkers[static_cast<std::size_t>(MarkerOf(s, order))]);
      }
    }
  }
  pllsty(1);
  plwidth(1.0);
}

/// A sequential colour (viridis-like, from dark blue through green to yellow) for t in [0, 1], as
/// the 8-bit RGB the figure gets.
std::array<int, 3> MapRgb(double t) {
  static constexpr std::array<std::array<double, 3>, 5> stops = {
      {{68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}}};
  t = std::clamp(t, 0.0, 1.0) * (stops.size() - 1);
  const auto k = std::min<std::size_t>(static_cast<std::size_t>(t), stops.size() - 2);
  const double f = t - static_cast<double>(k);
  const auto c = [&](int i) {
    return static_cast<int>(std::lround(stops[k][static_cast<std::size_t>(i)] * (1 - f) + stops[k + 1][static_cast<std::size_t>(i)] * f));
  };
  return {c(0), c(1), c(2)};
}

void SetRgb(const std::array<int, 3>& rgb) {
  plscol0(kColours - 1, rgb[0], rgb[1], rgb[2]);
  plcol0(kColours - 1);
}

void MapColour(double t) { SetRgb(MapRgb(t)); }

/// The range of a map's finite values (0..1 when it has none).
Range MapRange(const Map& m) {
  Range r;
  for (const auto& column : m.z) {
    for (const double v : column) r.Add(v);
  }
  if (r.Empty()) r = {0.0, 1.0};
  if (r.hi - r.lo <= 0.0) r.hi = r.lo + 1.0;
  return r;
}

/// Half the spacing around centre i of sorted centres (1 when there is one).
double HalfCell(const std::vector<double>& c, std::size_t i, bool upper) {
  if (c.size() < 2) return 0.5;
  if (upper) return i + 1 < c.size() ? (c[i + 1] - c[i]) / 2 : (c[i] - c[i - 1]) / 2;
  return i > 0 ? (c[i] - c[i - 1]) / 2 : (c[i + 1] - c[i]) / 2;
}

/// The colour steps of a map and of its colour bar: a cell takes the colour of the bar's step its
/// value falls in, so that the map shows what the bar can be read to.
constexpr int kMapSteps = 64;

void DrawMap(const Map& m) {
  // Each cell is coloured by its step of the colour bar (kMapSteps). Cells of one column in the
  // same step are one run, and runs over the same pins in the same step in neighbouring columns
  // are one rectangle: the same picture in far fewer SVG elements (the solve figure of
  // a two-disc deck was 2.3 MB; the bands of the loaded pins change little from one crank angle
  // to the next).
  const Range r = MapRange(m);
  const auto step = [&](double v) {
    if (!std::isfinite(v)) return -1;
    return std::clamp(static_cast<int>(std::floor((v - r.lo) / (r.hi - r.lo) * kMapSteps)), 0, kMapSteps - 1);
  };
  struct Run {
    std::size_t j0, j1;
    int step;
    double x0, x1;
  };
  const auto fill = [&](const Run& run) {
    const double y0 = m.y[run.j0] - HalfCell(m.y, run.j0, false), y1 = m.y[run.j1] + HalfCell(m.y, run.j1, true);
    const std::array<double, 4> bx = {run.x0, run.x1, run.x1, run.x0}, by = {y0, y0, y1, y1};
    SetRgb(MapRgb((run.step + 0.5) / kMapSteps));
    plfill(4, bx.data(), by.data());
  };
  std::vector<Run> open, next;  // the runs of the last column, each from where it began
  std::vector<Run> done;        // the rectangles, drawn at the end by colour (they do not overlap)
  const std::size_t columns = std::min(m.x.size(), m.z.size());
  for (std::size_t i = 0; i < columns; ++i) {
    const double x0 = m.x[i] - HalfCell(m.x, i, false), x1 = m.x[i] + HalfCell(m.x, i, true);
    const std::size_t n = std::min(m.y.size(), m.z[i].size());
    next.clear();
    for (std::size_t j = 0; j < n;) {
      const int k = step(m.z[i][j]);
      std::size_t last = j;
      while (last + 1 < n && step(m.z[i][last + 1]) == k) ++last;
      if (k >= 0) next.push_back({j, last, k, x0, x1});
      j = last + 1;
    }
    // A run of this column that continues one of the last (the same pins, the same step) keeps its
    // beginning; the last column's runs that do not continue are drawn.
    std::size_t a = 0;
    for (Run& run : next) {
      while (a < open.size() && open[a].j0 < run.j0) done.push_back(open[a++]);
      if (a < open.size() && open[a].j0 == run.j0 && open[a].j1 == run.j1 && open[a].step == run.step) {
        run.x0 = open[a++].x0;
      }
    }
    while (a < open.size()) done.push_back(open[a++]);
    std::swap(open, next);
  }
  done.insert(done.end(), open.begin(), open.end());
  // One colour after another: MergePolylines writes each colour's cells as one path.
  std::stable_sort(done.begin(), done.end(), [](const Run& a, const Run& b) { return a.step < b.step; });
  for (const Run& run : done) fill(run);
}

/// The colour bar of a map, in the page box [x0, x1] x [y0, y1], with its ticks and label.
void DrawColourBar(const Map& m, double x0, double x1, double y0, double y1) {
  const Range r = MapRange(m);
  plvpor(x0, x1, y0, y1);
  plwind(0.0, 1.0, r.lo, r.hi);
  const int steps = kMapSteps;
  for (int k = 0; k < steps; ++k) {
    const double a = r.lo + (r.hi - r.lo) * k / steps, b = r.lo + (r.hi - r.lo) * (k + 1) / steps;
    const std::array<double, 4> bx = {0.0, 1.0, 1.0, 0.0}, by = {a, a, b, b};
    MapColour((k + 0.5) / steps);
    plfill(4, bx.data(), by.data());
  }
  plcol0(kInk);
  Chr(0.65);
  plbox("bc", 0, 0, "bcmstv", 0, 0);
  Chr(0.75);
  plmtex("r", 5.5, 0.5, 0.5, Pl(m.z_label).c_str());
}

void DrawLegend(const Panel& p) {
  std::vector<PLINT> opts, colours, text_colours, patterns, styles, symbol_numbers;
  std::vector<PLFLT> scales, widths, symbol_scales;
  std::vector<std::string> texts, symbols;
  int order = 0;
  for (const Series& s : p.series) {
    if (s.label.empty()) continue;
    const int c = ColourOf(s, order);
    PLINT opt = PL_LEGEND_LINE;
    if (s.style == Style::kMarkers) opt = PL_LEGEND_SYMBOL;
    if (s.style == Style::kLineMarkers) opt = PL_LEGEND_LINE | PL_LEGEND_SYMBOL;
    if (s.style == Style::kBars || s.style == Style::kPolygon) opt = PL_LEGEND_COLOR_BOX;
    opts.push_back(opt);
    colours.push_back(opt == PL_LEGEND_COLOR_BOX ? kTint + c : kPalette + c);
    text_colours.push_back(kInk);
    patterns.push_back(0);
    styles.push_back(s.dashed ? 2 : 1);
    symbol_numbers.push_back(1);
    scales.push_back(0.6);
    widths.push_back(1.6);
    symbol_scales.push_back(0.55);
    texts.push_back(Pl(s.label));
    symbols.push_back(kMarkers[static_cast<std::size_t>(MarkerOf(s, order))]);
    ++order;
  }
  if (texts.size() < 2) return;  // one series: the axis label says it
  std::vector<const char*> text_ptrs, symbol_ptrs;
  for (const auto& t : texts) text_ptrs.push_back(t.c_str());
  for (const auto& t : symbols) symbol_ptrs.push_back(t.c_str());
  PLINT position = PL_POSITION_VIEWPORT;
  switch (p.legend) {
    case LegendPlace::kTopRight: position |= PL_POSITION_TOP | PL_POSITION_RIGHT | PL_POSITION_INSIDE; break;
    case LegendPlace::kTopLeft: position |= PL_POSITION_TOP | PL_POSITION_LEFT | PL_POSITION_INSIDE; break;
    case LegendPlace::kBottomRight: position |= PL_POSITION_BOTTOM | PL_POSITION_RIGHT | PL_POSITION_INSIDE; break;
    case LegendPlace::kBottomLeft: position |= PL_POSITION_BOTTOM | PL_POSITION_LEFT | PL_POSITION_INSIDE; break;
    case LegendPlace::kOutsideRight: position |= PL_POSITION_RIGHT | PL_POSITION_OUTSIDE; break;
  }
  PLFLT w = 0, h = 0;
  Chr(0.8);
  pllegend(&w, &h, PL_LEGEND_BACKGROUND | PL_LEGEND_BOUNDING_BOX, position, 0.01, 0.01, 0.07, 0, kGridInk, 1, 0, 0,
           static_cast<PLINT>(texts.size()), opts.data(), 0.8, 0.8, 2.0, 0.0, text_colours.data(), text_ptrs.data(),
           colours.data(), patterns.data(), scales.data(), widths.data(), colours.data(), styles.data(), widths.data(),
           colours.data(), symbol_scales.data(), symbol_numbers.data(), symbol_ptrs.data());
}

/// One panel inside the page box [x0, x1] x [y0, y1] (normalised device coordinates).
void DrawPanel(const Panel& p, double x0, double x1, double y0, double y1, int page_w, int page_h) {
  const bool outside_legend = p.legend == LegendPlace::kOutsideRight && p.LabelledSeries() > 1;
  std::size_t longest = 0;
  for (const Series& s : p.series) longest = std::max(longest, s.label.size());
  const double legend_px = std::min(150.0 + 12.5 * static_cast<double>(longest), 0.5 * (x1 - x0) * page_w);
  const double right = outside_legend ? legend_px : (p.map ? 150.0 : 24.0);  // a map's colour bar and its label
  const double vx0 = x0 + 92.0 / page_w, vx1 = x1 - right / page_w;
  const double vy0 = y0 + 58.0 / page_h, vy1 = y1 - 34.0 / page_h;
  plvpor(vx0, vx1, vy0, vy1);
  Range rx = DataRange(p, true), ry = DataRange(p, false);
  if (p.equal_scale) {
    // One mm as long on both axes: the viewport shrinks to the data's aspect (centred in its box),
    // so the axes keep the ranges asked for (a drawing's axes fit the part, issue 53) instead of
    // one of them stretching to fill the box.
    const double pw = (vx1 - vx0) * page_w, ph = (vy1 - vy0) * page_h;
    const double dx = rx.hi - rx.lo, dy = ry.hi - ry.lo;
    if (dx / dy < pw / ph) {
      const double half = 0.5 * ph * dx / dy / page_w, c = 0.5 * (vx0 + vx1);
      plvpor(c - half, c + half, vy0, vy1);
    } else {
      const double half = 0.5 * pw * dy / dx / page_h, c = 0.5 * (vy0 + vy1);
      plvpor(vx0, vx1, c - half, c + half);
    }
  }
  plwind(rx.lo, rx.hi, ry.lo, ry.hi);
  Chr(0.7);
  const std::string lx = p.log_x ? "l" : "", ly = p.log_y ? "l" : "";
  if (p.map) DrawMap(*p.map);
  plcol0(kGridInk);
  if (!p.map) plbox(("g" + lx).c_str(), 0, 0, ("g" + ly).c_str(), 0, 0);
  int order = 0;
  for (const Series& s : p.series) {
    std::vector<double> x(s.x.size()), y(s.y.size());
    std::transform(s.x.begin(), s.x.end(), x.begin(), [&](double v) { return Axis(v, p.log_x); });
    std::transform(s.y.begin(), s.y.end(), y.begin(), [&](double v) { return Axis(v, p.log_y); });
    x.resize(std::min(x.size(), y.size())), y.resize(x.size());
    DrawSeries(s, order, x, y);
    if (!s.label.empty()) ++order;
  }
  Chr(0.6);
  // Vertical marks' labels (rotated, read downward from the top) never overlap: a label
  // closer than 4 % of the axis to the one before it, left to right, starts lower, below that
  // label's text.
  std::vector<std::pair<double, double>> placed;  // (x, lowest y) of the vertical labels so far
  std::vector<const Mark*> vertical;
  for (const Mark& m : p.marks) {
    if (m.axis == Mark::Axis::kVertical) vertical.push_back(&m);
  }
  std::stable_sort(vertical.begin(), vertical.end(), [](const Mark* a, const Mark* b) { return a->value < b->value; });
  std::map<const Mark*, double> label_top;
  for (const Mark* m : vertical) {
    const double v = Axis(m->value, p.log_x);
    double top = ry.hi - 0.02 * (ry.hi - ry.lo);
    for (const auto& [x, low] : placed) {
      if (std::abs(v - x) < 0.04 * (rx.hi - rx.lo)) top = std::min(top, low - 0.03 * (ry.hi - ry.lo));
    }
    // About 0.045 of the height per character at this size.
    const double bottom = top - 0.045 * (ry.hi - ry.lo) * static_cast<double>(m->label.size());
    if (!m->label.empty()) placed.emplace_back(v, bottom);
    label_top[m] = top;
  }
  for (const Mark& m : p.marks) {
    plcol0(kMarkInk);
    pllsty(m.dotted ? 8 : m.dashed ? 2 : 1);
    plwidth(1.2);
    if (m.axis == Mark::Axis::kHorizontal) {
      const double v = Axis(m.value, p.log_y);
      const std::array<double, 2> x = {rx.lo, rx.hi}, y = {v, v};
      plline(2, x.data(), y.data());
      plptex(rx.lo + 0.01 * (rx.hi - rx.lo), v + 0.022 * (ry.hi - ry.lo), 1, 0, 0.0, Pl(m.label).c_str());
    } else {
      const double v = Axis(m.value, p.log_x);
      const std::array<double, 2> x = {v, v}, y = {ry.lo, ry.hi};
      plline(2, x.data(), y.data());
      plptex(v - 0.012 * (rx.hi - rx.lo), label_top[&m], 0, -1, 0.0, Pl(m.label).c_str());
    }
    pllsty(1);
    plwidth(1.0);
  }
  plcol0(kInk);
  for (const Note& n : p.notes) {
    Chr(0.7 * n.size);
    plptex(Axis(n.x, p.log_x), Axis(n.y, p.log_y), 1, 0, n.justification, Pl(n.text).c_str());
  }
  Chr(0.7);
  plcol0(kInk);
  plbox(("bcnst" + lx).c_str(), 0, 0, ("bcnstv" + ly).c_str(), 0, 0);
  Chr(0.8);
  plmtex("b", 2.8, 0.5, 0.5, Pl(p.x_label).c_str());
  plmtex("l", 5.2, 0.5, 0.5, Pl(p.y_label).c_str());
  Chr(0.85);
  plmtex("t", 1.0, 0.5, 0.5, Pl(p.title).c_str());
  DrawLegend(p);
  if (p.map) DrawColourBar(*p.map, vx1 + 18.0 / page_w, vx1 + 36.0 / page_w, vy0, vy1);
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

void Draw(const Figure& f) {
  plscmap0n(kColours);
  plscol0(0, 255, 255, 255);
  plscol0(kInk, 0, 0, 0);
  plscol0(kMarkInk, 60, 60, 60);
  plscol0(kGridInk, 215, 215, 215);
  for (int i = 0; i < 8; ++i) {
    const auto& c = kRgb[static_cast<std::size_t>(i)];
    plscol0(kPalette + i, c[0], c[1], c[2]);
    plscol0(kTint + i, 255 - (255 - c[0]) * 2 / 5, 255 - (255 - c[1]) * 2 / 5, 255 - (255 - c[2]) * 2 / 5);
  }
  plspage(0, 0, f.width, f.height, 0, 0);
  plinit();
  pladv(0);
  PLFLT xmin = 0, xmax = 0, ymin = 0, ymax = 0;
  plgspa(&xmin, &xmax, &ymin, &ymax);  // the page in mm
  g_char_mm = xmax > xmin ? 17.0 * (xmax - xmin) / f.width : 0.0;
  plsxax(10, 0);  // plain tick labels: no "(x10^-1)" multiplier up to 10 digits
  plsyax(10, 0);
  // Title and caption in page coordinates.
  plvpor(0, 1, 0, 1);
  plwind(0, 1, 0, 1);
  plcol0(kInk);
  const auto caption = Lines(f.caption);
  const double line = 17.0 / f.height;
  // Long lines are set smaller to fit the page (at most about 12.5 px per character at scale 1).
  const auto fit = [&f](const std::string& text, double scale) {
    return std::min(scale, 0.97 * f.width / (12.5 * std::max<double>(1.0, static_cast<double>(std::min(text.size(), kMaxDrawnCharacters + 3)))));
  };
  Chr(fit(f.title, 0.95));
  plptex(0.5, 1.0 - 26.0 / f.height, 1, 0, 0.5, Pl(f.title).c_str());
  for (std::size_t i = 0; i < caption.size(); ++i) {
    Chr(fit(caption[i], 0.62));
    plptex(0.012, (10.0 / f.height) + line * static_cast<double>(caption.size() - 1 - i), 1, 0, 0.0, Pl(caption[i]).c_str());
  }
  const double top = 1.0 - 60.0 / f.height, bottom = 8.0 / f.height + line * static_cast<double>(caption.size());
  const int columns = std::max(1, f.columns);
  const int rows = std::max<int>(1, (static_cast<int>(f.panels.size()) + columns - 1) / columns);
  for (std::size_t i = 0; i < f.panels.size(); ++i) {
    const int r = static_cast<int>(i) / columns, c = static_cast<int>(i) % columns;
    const double cw = 1.0 / columns, ch = (top - bottom) / rows;
    DrawPanel(f.panels[i], c * cw, (c + 1) * cw, top - (r + 1) * ch, top - r * ch, f.width, f.height);
  }
  plend();
}

/// PLplot's SVG texts in fewer bytes, the same drawing (a sweep's markers are glyphs,
/// each a <text>): the opening tag's attributes one space apart and without fill-opacity="1"
/// (SVG's default), and the characters PLplot writes as references (&#x4c;) written as
/// themselves in UTF-8, but for the five that XML escapes.
std::string CompactTexts(const std::string& svg) {
  std::string out;
  out.reserve(svg.size());
  std::size_t at = 0;
  for (std::size_t open = svg.find("<text", at); open != std::string::npos; open = svg.find("<text", at)) {
    const std::size_t tag_end = svg.find('>', open);
    const std::size_t close = tag_end == std::string::npos ? tag_end : svg.find("</text>", tag_end);
    if (close == std::string::npos) break;
    out.append(svg, at, open - at);
    // The opening tag: whitespace runs to one space (its values hold no spaces but the transform's,
    // which are single), the default opacity dropped.
    std::string tag;
    bool space = false;
    for (std::size_t k = open; k < tag_end; ++k) {
      const bool is_space = std::isspace(static_cast<unsigned char>(svg[k])) != 0;
      if (is_space) {
        space = true;
        continue;
      }
      if (space) tag += ' ';
      space = false;
      tag += svg[k];
    }
    const std::string opacity = " fill-opacity=\"1.000000\"";
    if (const std::size_t o = tag.find(opacity); o != std::string::npos) tag.erase(o, opacity.size());
    out += tag;
    out += '>';
    // The body: character references decoded.
    for (std::size_t k = tag_end + 1; k < close;) {
      if (svg.compare(k, 3, "&#x") == 0) {
        const std::size_t semi = svg.find(';', k);
        if (semi != std::string::npos && semi < close && semi - k <= 9) {
          const unsigned long c = std::strtoul(svg.substr(k + 3, semi - k - 3).c_str(), nullptr, 16);
          const bool escaped = c == '<' || c == '>' || c == '&' || c == '"' || c == '\'';
          if (c >= 0x20 && c != 0x7f && c <= 0x10FFFF && !(c >= 0xD800 && c <= 0xDFFF) && !escaped) {
            if (c < 0x80) {
              out += static_cast<char>(c);
            } else if (c < 0x800) {
              out += static_cast<char>(0xC0 | (c >> 6));
              out += static_cast<char>(0x80 | (c & 0x3F));
            } else if (c < 0x10000) {
              out += static_cast<char>(0xE0 | (c >> 12));
              out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
              out += static_cast<char>(0x80 | (c & 0x3F));
            } else {
              out += static_cast<char>(0xF0 | (c >> 18));
              out += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
              out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
              out += static_cast<char>(0x80 | (c & 0x3F));
            }
            k = semi + 1;
            continue;
          }
        }
      }
      out += svg[k++];
    }
    at = close;
  }
  out.append(svg, at, std::string::npos);
  return out;
}

/// PLplot's SVG polylines with the attributes that state SVG's defaults left out (stroke-width 1,
/// stroke-opacity 1, fill-opacity 1, fill-rule nonzero: PLplot's groups carry only transforms and
/// clip paths, so nothing is inherited instead) and each element on one line: the same drawing in
/// about half the bytes (a map is thousands of cells).
std::string CompactPolylines(const std::string& svg) {
  static constexpr std::array<std::string_view, 4> kDefaults = {
      R"(stroke-width="1.000000e+00")", R"(stroke-opacity="1.000000")", R"(fill-opacity="1.000000")", R"(fill-rule="nonzero")"};
  std::string out;
  out.reserve(svg.size());
  std::size_t at = 0;
  for (std::size_t open = svg.find("<polyline", at); open != std::string::npos; open = svg.find("<polyline", at)) {
    const std::size_t close = svg.find("/>", open);
    if (close == std::string::npos) break;
    out.append(svg, at, open - at);
    // Attribute by attribute (whitespace-separated; PLplot's values hold spaces only in points="...").
    std::string element = "<polyline";
    bool shaped = true;  // name="value" pairs only, as PLplot writes them; else the element stays as it is
    std::size_t k = open + std::string_view("<polyline").size();
    while (k < close) {
      while (k < close && std::isspace(static_cast<unsigned char>(svg[k]))) ++k;
      if (k >= close) break;
      const std::size_t quote = svg.find('"', k);
      const std::size_t end_quote = quote >= close ? std::string::npos : svg.find('"', quote + 1);
      if (end_quote == std::string::npos || end_quote > close) {
        shaped = false;
        break;
      }
      const std::string_view attribute(svg.data() + k, end_quote + 1 - k);
      if (std::find(kDefaults.begin(), kDefaults.end(), attribute) == kDefaults.end()) {
        element += ' ';
        element += attribute;
      }
      k = end_quote + 1;
    }
    if (shaped) {
      out += element;
    } else {
      out.append(svg, open, close - open);
    }
    out += "/>";
    at = close + 2;
  }
  out.append(svg, at, std::string::npos);
  return out;
}

/// A closed polyline's points ("x,y x,y ...", PLplot's fill of four corners) that trace an
/// axis-aligned rectangle, as path data of one winding, "Mx0 y0Hx1Vy1Hx0Z" (x0 < x1, y0 < y1), so
/// that such rectangles merged into one path fill their union under the nonzero rule; empty for
/// any other shape.
std::string RectanglePath(std::string_view points) {
  std::array<std::string_view, 5> x{}, y{};
  std::size_t n = 0, at = 0;
  while (at < points.size()) {
    while (at < points.size() && points[at] == ' ') ++at;
    if (at >= points.size()) break;
    const std::size_t end = std::min(points.find(' ', at), points.size());
    const std::string_view pair = points.substr(at, end - at);
    const std::size_t comma = pair.find(',');
    if (n == 5 || comma == std::string_view::npos) return {};
    x[n] = pair.substr(0, comma);
    y[n] = pair.substr(comma + 1);
    ++n;
    at = end;
  }
  if (n != 5 || x[0] != x[4] || y[0] != y[4]) return {};
  // Edges alternate horizontal and vertical, from either first edge.
  const bool horizontal_first = y[0] == y[1] && x[1] == x[2] && y[2] == y[3] && x[3] == x[0];
  const bool vertical_first = x[0] == x[1] && y[1] == y[2] && x[2] == x[3] && y[3] == y[0];
  if (!horizontal_first && !vertical_first) return {};
  const auto number = [](std::string_view v) { return std::strtod(std::string(v).c_str(), nullptr); };
  std::string_view x0 = x[0], x1 = x[2], y0 = y[0], y1 = y[2];
  if (number(x1) < number(x0)) std::swap(x0, x1);
  if (number(y1) < number(y0)) std::swap(y0, y1);
  std::string d = "M";
  d.append(x0).append(" ").append(y0).append("H").append(x1).append("V").append(y1).append("H").append(x0).append("Z");
  return d;
}

/// Runs of unfilled polylines with the same attributes, one after another (PLplot draws a dashed
/// line, a grid or the ticks as one polyline a segment), as one <path> of as many subpaths: the
/// same pixels (an unfilled path's subpaths are stroked one by one, as the polylines were), a
/// fraction of the bytes (figures under 300 kB). Runs of filled axis-aligned
/// rectangles with the same attributes (a map's cells of one colour, which DrawMap draws
/// together; bars) likewise, each as RectanglePath: one winding, so the path fills their union
/// (nonzero rule) and strokes each outline as the polylines did.
std::string MergePolylines(const std::string& svg) {
  std::string out;
  out.reserve(svg.size());
  std::size_t at = 0;
  std::string attributes, d;  // the run being merged: its attributes and its path data
  std::size_t count = 0;
  const auto flush = [&]() {
    if (count == 0) return;
    out += "<path" + attributes + " d=\"" + d + "\"/>";
    attributes.clear(), d.clear(), count = 0;
  };
  for (std::size_t open = svg.find("<polyline", at); open != std::string::npos; open = svg.find("<polyline", at)) {
    const std::size_t close = svg.find("/>", open);
    if (close == std::string::npos) break;
    const std::string_view between(svg.data() + at, open - at);
    const bool adjacent = std::all_of(between.begin(), between.end(), [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; });
    const std::string element = svg.substr(open + std::string_view("<polyline").size(), close - open - std::string_view("<polyline").size());
    const std::size_t points = element.find(" points=\"");
    const std::size_t points_end = points == std::string::npos ? std::string::npos : element.find('"', points + 9);
    const bool unfilled = element.find("fill=\"none\"") != std::string::npos;
    const std::string rectangle = points == std::string::npos || points_end == std::string::npos || unfilled
                                      ? std::string()
                                      : RectanglePath(std::string_view(element).substr(points + 9, points_end - points - 9));
    const bool mergeable = points != std::string::npos && points_end != std::string::npos && (unfilled || !rectangle.empty());
    if (!mergeable) {
      flush();
      out.append(svg, at, close + 2 - at);
      at = close + 2;
      continue;
    }
    const std::string own = element.substr(0, points) + element.substr(points_end + 1);
    if (count > 0 && (!adjacent || own != attributes)) flush();
    if (count == 0) out.append(svg, at, open - at);
    if (count > 0) d += ' ';
    attributes = own;
    if (unfilled) {
      d += 'M';
      d.append(element, points + 9, points_end - points - 9);
    } else {
      d += rectangle;
    }
    ++count;
    at = close + 2;
  }
  flush();
  out.append(svg, at, std::string::npos);
  return out;
}

/// The <title>, <desc> and <metadata> that tests and scripts read (the drawing itself carries
/// every label as <text>).
std::string Metadata(const Figure& f) {
  std::string m = fmt::format("<title>{}</title>\n<desc>{}</desc>\n<metadata>\n<ltca:figure xmlns:ltca=\"urn:ltca:plots\" panels=\"{}\">\n",
                              XmlEscape(f.title), XmlEscape(f.caption), f.panels.size());
  for (const Panel& p : f.panels) {
    m += fmt::format("<ltca:panel title=\"{}\" x_label=\"{}\" y_label=\"{}\"{} series=\"{}\">\n", XmlEscape(p.title),
                     XmlEscape(p.x_label), XmlEscape(p.y_label),
                     p.map ? fmt::format(" z_label=\"{}\" cells=\"{}x{}\"", XmlEscape(p.map->z_label), p.map->x.size(), p.map->y.size())
                           : std::string(),
                     p.LabelledSeries());
    for (const Series& s : p.series) {
      if (!s.label.empty()) m += fmt::format("<ltca:series label=\"{}\" points=\"{}\"/>\n", XmlEscape(s.label), s.x.size());
    }
    m += "</ltca:panel>\n";
  }
  return m + "</ltca:figure>\n</metadata>\n";
}

}  // namespace

std::string XmlEscape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default:
        // XML 1.0 has no control characters but tab, newline and carriage return.
        if ((static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n' && c != '\r') || c == 0x7f) {
          out += ' ';
        } else {
          out += c;
        }
    }
  }
  return out;
}

std::size_t Panel::LabelledSeries() const {
  return static_cast<std::size_t>(std::count_if(series.begin(), series.end(), [](const Series& s) { return !s.label.empty(); }));
}

Format FormatForPath(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".png" || ext == ".PNG") return Format::kPng;
  if (ext == ".pdf" || ext == ".PDF") return Format::kPdf;
  return Format::kSvg;
}

const char* FormatName(Format format) {
  switch (format) {
    case Format::kPng: return "PNG";
    case Format::kPdf: return "PDF";
    case Format::kSvg: break;
  }
  return "SVG";
}

namespace {

/// HasDevice with the reason as an exception; the caller holds the lock.
void RequireDevice(Format format) {
  const char* device = Device(format);
  if (!HasDevice(device)) {
    throw std::runtime_error(fmt::format("cannot draw {}: PLplot has no '{}' device (install plplot-driver-cairo)",
                                         FormatName(format), device));
  }
}

}  // namespace

void RequireFormat(Format format) {
  const std::lock_guard<std::mutex> guard(Lock());
  RequireDevice(format);
}

void Write(const Figure& figure, std::ostream& os, Format format) {
  std::string bytes;
  {
    const std::lock_guard<std::mutex> guard(Lock());
    RequireDevice(format);
    const char* device = Device(format);
    std::string name = (std::filesystem::temp_directory_path() / "ltca_plot_XXXXXX").string();
    // An interrupt removes it (a figure of a long sweep can be large).
    if (!CreateTemporary(name, false)) {
      throw std::runtime_error("cannot create a temporary file for a plot in " + std::filesystem::temp_directory_path().string());
    }
    struct Remove {
      std::string path;
      ~Remove() {
        std::remove(path.c_str());
        ForgetTemporary(path);
      }
    } remove{name};
    plsdev(device);
    plsfnam(name.c_str());
    Draw(figure);
    std::ifstream in(name, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (bytes.empty()) throw std::runtime_error(fmt::format("PLplot wrote no {} for '{}'", FormatName(format), figure.title));
  }
  if (format == Format::kSvg) {
    const auto root = bytes.find("<svg");
    const auto end = root == std::string::npos ? root : bytes.find('>', root);
    if (end != std::string::npos) {
      std::string metadata = Metadata(figure);
      metadata.insert(metadata.begin(), '\n');
      bytes.insert(end + 1, metadata);
    }
    bytes = MergePolylines(CompactPolylines(CompactTexts(bytes)));
  }
  os.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace ltca::app::plots

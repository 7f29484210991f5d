// The figures' drawing by PLplot (docs/plots.md): the module ltca_plots.so, loaded the first time a
// figure is written (app/modules.hpp), so that PLplot and its libraries stay out of the start-up of
// every command (issue 54). PLplot keeps global state and is not thread-safe: its caller (Write in
// plots.cpp) serialises every call under one mutex.
#include "ltca/app/plots.hpp"

#include <plplot.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

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

}  // namespace
}  // namespace ltca::app::plots

/// The declarations this module was built from (plots.hpp, PlotsAbi): the loader compares them
/// with its own before it hands over a Figure.
extern "C" __attribute__((visibility("default"))) const char* ltca_plots_abi() {
  static const std::string abi = ltca::app::plots::PlotsAbi(LTCA_VERSION);
  return abi.c_str();
}

/// Whether PLplot has the device `name` ("svg", "pngcairo", "pdfcairo").
extern "C" __attribute__((visibility("default"))) bool ltca_plots_has_device(const char* name) {
  return ltca::app::plots::HasDevice(name);
}

/// Draws the figure with the device into the file `path`.
extern "C" __attribute__((visibility("default"))) void ltca_plots_draw(const ltca::app::plots::Figure* figure, const char* device,
                                                                     const char* path) {
  plsdev(device);
  plsfnam(path);
  ltca::app::plots::Draw(*figure);
}

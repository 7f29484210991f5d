// Figures drawn by PLplot (docs/plots.md), through the module ltca_plots.so (plots_plplot.cpp),
// which a run loads the first time it writes a figure. PLplot keeps global state and is not
// thread-safe: every call runs under one mutex. It writes to a named file: each figure is drawn
// into a temporary file, which is then copied to the stream (SVG with its metadata added).
#include "ltca/app/plots.hpp"

#include "ltca/app/modules.hpp"
#include "ltca/app/temporaries.hpp"

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

const char* Device(Format format) {
  switch (format) {
    case Format::kPng: return "pngcairo";
    case Format::kPdf: return "pdfcairo";
    case Format::kSvg: break;
  }
  return "svg";  // PLplot's own SVG driver (libplplot17), no cairo needed
}

std::mutex& Lock() {
  static std::mutex m;
  return m;
}

#ifndef LTCA_VERSION
#define LTCA_VERSION "unknown"
#endif

/// An entry point of the drawing module, once the module is known to be built from this ltca's
/// declarations (PlotsAbi): a module of another version would read the Figure it is handed with
/// another layout. Throws std::runtime_error naming both when they differ.
template <typename F>
F PlotsFunction(const char* symbol) {
  static const bool checked = [] {
    const std::string mine = PlotsAbi(LTCA_VERSION);
    const char* (*abi)() = nullptr;
    try {
      abi = ModuleFunction<const char* (*)()>("plots", "ltca_plots_abi");
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(std::string(e.what()) + ": it was built from another version of ltca (this one: " + mine +
                               "); rebuild or reinstall it with this ltca");
    }
    const std::string theirs = abi();
    if (theirs != mine) {
      throw std::runtime_error("the plots part of ltca (ltca_plots.so) was built from another version of ltca (" + theirs +
                               "; this one: " + mine + "); rebuild or reinstall it with this ltca");
    }
    return true;
  }();
  (void)checked;
  return ModuleFunction<F>("plots", symbol);
}

bool HasDevice(const char* name) { return PlotsFunction<bool (*)(const char*)>("ltca_plots_has_device")(name); }

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
    const ScratchFile remove(name);
    PlotsFunction<void (*)(const Figure*, const char*, const char*)>("ltca_plots_draw")(&figure, device, name.c_str());
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

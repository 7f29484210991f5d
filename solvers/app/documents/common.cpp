#include "documents/common.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cstring>
#include <iterator>
#include <system_error>

#include <fmt/format.h>
#include <fmt/ranges.h>

#ifndef LTCA_VERSION
#define LTCA_VERSION "unknown"
#endif

namespace ltca::app::documents {

std::string Dump(const nlohmann::json& doc, int indent) {
  return doc.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

void AppendJsonNumber(std::string& out, double v) {
  if (!std::isfinite(v)) {
    out += "null";
    return;
  }
  if (std::signbit(v)) out += '-', v = -v;
  if (v == 0.0) {
    out += "0.0";
    return;
  }
  // The shortest digits in scientific form, d[.ddd]e[+-]XX, then nlohmann's layout of them
  // (detail::format_buffer, kMinExp = -4, kMaxExp = digits10 = 15): k digits, the decimal point
  // after digit n = exponent + 1.
  std::array<char, 32> sci{};
  const std::to_chars_result r = std::to_chars(sci.data(), sci.data() + sci.size(), v, std::chars_format::scientific);
  char digits[24];
  int k = 0;
  const char* c = sci.data();
  for (; c != r.ptr && *c != 'e'; ++c) {
    if (*c != '.') digits[k++] = *c;
  }
  int exponent = 0;
  std::from_chars(c + 1 + (c[1] == '+' ? 1 : 0), r.ptr, exponent);
  const int n = exponent + 1;
  if (k <= n && n <= 15) {  // digits[000].0
    out.append(digits, static_cast<std::size_t>(k));
    out.append(static_cast<std::size_t>(n - k), '0');
    out += ".0";
  } else if (0 < n && n <= 15) {  // dig.its
    out.append(digits, static_cast<std::size_t>(n));
    out += '.';
    out.append(digits + n, static_cast<std::size_t>(k - n));
  } else if (-4 < n && n <= 0) {  // 0.[000]digits
    out += "0.";
    out.append(static_cast<std::size_t>(-n), '0');
    out.append(digits, static_cast<std::size_t>(k));
  } else {  // d[.igits]e+XX
    out += digits[0];
    if (k > 1) {
      out += '.';
      out.append(digits + 1, static_cast<std::size_t>(k - 1));
    }
    const int e = n - 1;
    out += e < 0 ? "e-" : "e+";
    const int a = e < 0 ? -e : e;
    if (a < 10) out += '0';
    out += std::to_string(a);
  }
}

void AppendJsonNumber(std::string& out, std::int64_t v) {
  char text[24];
  const std::to_chars_result r = std::to_chars(text, text + sizeof text, v);
  out.append(text, r.ptr);
}

void AppendJsonString(std::string& out, std::string_view s) {
  bool plain = true;  // printable ASCII without a quote or a backslash: written as it is
  for (const char ch : s) {
    const auto u = static_cast<unsigned char>(ch);
    if (u < 0x20 || u >= 0x80 || ch == '"' || ch == '\\') {
      plain = false;
      break;
    }
  }
  if (plain) {
    out += '"';
    out.append(s);
    out += '"';
  } else {
    out += Dump(nlohmann::json(std::string(s)), -1);
  }
}

std::string ShortestOrEmpty(double v) {
  if (!std::isfinite(v)) return {};
  char text[32];
  const std::to_chars_result r = std::to_chars(text, text + sizeof text, v);
  return std::string(text, r.ptr);
}

nlohmann::json FiniteOrNull(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

void Table::Add(const std::string& name, double value) { columns[name].values.push_back(std::isfinite(value) ? value : NAN); }

void Table::Add(const std::string& name, const std::vector<double>& values) {
  Column& column = columns[name];
  column.lists = true;
  std::vector<double>& row = column.rows.emplace_back();
  row.reserve(values.size());
  for (const double v : values) row.push_back(std::isfinite(v) ? v : NAN);
}

std::string FormatOrNa(double v, int decimals) {
  return std::isfinite(v) ? fmt::format("{:.{}f}", v, decimals) : std::string("n/a");
}

std::string Nested(const std::string& text) {
  std::string r;
  for (const char c : text) {
    r += c;
    if (c == '\n') r += "  ";
  }
  return r;
}

std::string OpenObject(const nlohmann::json& header) {
  std::string text = Dump(header);
  text.erase(text.rfind('}'));
  while (!text.empty() && text.back() == '\n') text.pop_back();
  return text;
}

void AddRunRecord(nlohmann::json& summary, const analysis::RunRecord& record) {
  summary["positions"] = record.positions();
  summary["succeeded_positions"] = record.succeeded;
  summary["failed_positions"] = record.failed;
  summary["wall_seconds"] = record.wall_seconds;
  summary["status"] = ToString(record.status());
  if (!record.first_failure.empty()) summary["first_failure"] = record.first_failure;
}

nlohmann::json CaseJson(const Deck& deck) {
  nlohmann::json j = {{"title", deck.info.title}, {"source", deck.info.source}, {"deck", deck.name}};
  if (!deck.source.overrides.empty()) j["overrides"] = OverrideArguments(deck);
  return j;
}

std::vector<std::string> OverrideArguments(const Deck& deck) {
  std::vector<std::string> out;
  out.reserve(deck.source.overrides.size());
  for (const std::string& o : deck.source.overrides) {  // the CLI's --unset value starts with '-'
    out.push_back(!o.empty() && o.front() == '-' ? "--unset " + o.substr(1) : "--set " + o);
  }
  return out;
}

std::string CaseTitle(const Deck& deck, std::size_t room) {
  const std::vector<std::string> given = OverrideArguments(deck);
  if (given.empty()) return deck.info.title;
  const std::string all = fmt::format("{}", fmt::join(given, " "));
  if (all.size() <= room) return fmt::format("{} ({})", deck.info.title, all);
  return fmt::format("{} (with {} override{})", deck.info.title, given.size(), given.size() == 1 ? "" : "s");
}

std::string CaseLines(const Deck& deck, int width) {
  std::string text = fmt::format("{:<{}}{}\n", "case", width, deck.info.title);
  const std::vector<std::string> given = OverrideArguments(deck);
  if (!given.empty()) text += fmt::format("{:<{}}{}\n", "overrides", width, fmt::join(given, " "));
  return text;
}

nlohmann::json ModelJson(const Deck::ModelInfo& model) {
  nlohmann::json j = {{"name", model.name}, {"slices", model.slices}, {"surface", model.surface}};
  if (!model.note.empty()) j["note"] = model.note;
  if (model.discs != 1) j["discs"] = model.discs;  // [second_disc]
  if (!model.reducer.empty()) j["stage"] = model.reducer;  // [output], [bearing]
  if (!model.scope.empty()) j["scope"] = model.scope;      // what is elastic, what rigid
  if (!model.pin_seat.empty()) j["pin_seat"] = model.pin_seat;  // [pins] seat
  if (!model.disc_body.empty()) j["disc_body"] = model.disc_body;  // [disc] body = "elastic"
  if (model.tip_relief_source != "none" || !model.tip_relief_note.empty()) {
    j["tip_relief"] = {{"truncation_mm", model.tip_relief.truncation},
                       {"rounding_radius_mm", model.tip_relief.rounding_radius},
                       {"source", model.tip_relief_source}};
    if (!model.tip_relief_note.empty()) j["tip_relief"]["note"] = model.tip_relief_note;
  }
  return j;
}

std::string ModelLine(const Deck& deck) {
  const Deck::ModelInfo m = deck.Model();
  std::string line =
      m.slices == 1
          ? fmt::format("model     {} (1 slice over the {:g} mm face width, {} surface)\n", m.name, deck.pair.face_width,
                        m.surface)
          : fmt::format("model     {} ({} slices of {:g} mm over the {:g} mm face width, {} surface)\n", m.name,
                        m.slices, deck.pair.face_width / m.slices, deck.pair.face_width, m.surface);
  if (!m.note.empty()) line += fmt::format("note      {}\n", m.note);
  if (!m.disc_body.empty()) line += fmt::format("disc      {}\n", m.disc_body);
  if (!m.scope.empty()) line += fmt::format("scope     {}\n", m.scope);
  if (m.tip_relief_source != "none") {
    line += fmt::format("tip       relief {} mm truncation, {} mm rounding radius (from the deck)\n", m.tip_relief.truncation,
                        m.tip_relief.rounding_radius);
  }
  if (!m.tip_relief_note.empty()) line += fmt::format("tip note  {}\n", m.tip_relief_note);
  return line;
}

std::string FigureCaption(const Deck& deck, const std::string& ran) {
  std::string caption = fmt::format("deck: {}", deck.name);
  if (!deck.info.source.empty()) caption += fmt::format("   source: {}", deck.info.source);
  if (const std::vector<std::string> given = OverrideArguments(deck); !given.empty()) {
    std::string all = fmt::format("{}", fmt::join(given, " "));
    constexpr std::size_t kRoom = 160;  // one caption line
    if (all.size() > kRoom) {
      std::size_t cut = kRoom - 3;
      while (cut > 0 && (static_cast<unsigned char>(all[cut]) & 0xC0) == 0x80) --cut;  // not inside a UTF-8 character
      all = all.substr(0, cut) + "...";
    }
    caption += "\nwith " + all;
  }
  if (!ran.empty()) caption += "\n" + ran;
  return caption + fmt::format("\nltca {}", LTCA_VERSION);
}

void MarkMeanAndPeakToPeak(plots::Panel& panel, const std::vector<double>& values, const std::string& unit, double mean) {
  double lo = INFINITY, hi = -INFINITY, sum = 0.0;
  int n = 0;
  for (const double v : values) {
    if (!std::isfinite(v)) continue;
    lo = std::min(lo, v), hi = std::max(hi, v), sum += v, ++n;
  }
  if (n == 0) return;
  using Mark = plots::Mark;
  if (!std::isfinite(mean)) mean = sum / n;
  panel.marks.push_back({Mark::Axis::kHorizontal, mean, fmt::format("mean {:.4f} {}", mean, unit), false});
  panel.marks.push_back({Mark::Axis::kHorizontal, hi, fmt::format("max {:.4f}: peak-to-peak {:.4f} {}", hi, hi - lo, unit), true});
  panel.marks.push_back({Mark::Axis::kHorizontal, lo, fmt::format("min {:.4f}", lo), true});
  const double pad = std::max(0.15 * (hi - lo), 1e-3 * std::max(1.0, std::abs(hi)));
  panel.y_min = lo - pad, panel.y_max = hi + 2 * pad;
}

DecimatedSeries::DecimatedSeries(std::int64_t expected, std::int64_t buckets)
    : stride_(std::max<std::int64_t>(1, (expected + buckets - 1) / std::max<std::int64_t>(1, buckets))) {}

void DecimatedSeries::Add(std::int64_t at, double x, double y, double value) {
  if (at / stride_ != run_) {
    Close();
    run_ = at / stride_;
  }
  const Point p{at, x, y, value};
  if (!std::isfinite(value)) {
    if (gap_.at < 0) gap_ = p;
    return;
  }
  if (least_.at < 0 || value < least_.value) least_ = p;  // the first of equals
  if (largest_.at < 0 || value > largest_.value) largest_ = p;
}

void DecimatedSeries::Close() {
  Point kept[3] = {least_, largest_, gap_};
  std::sort(std::begin(kept), std::end(kept), [](const Point& a, const Point& b) { return a.at < b.at; });
  std::int64_t last = -1;
  for (const Point& p : kept) {
    if (p.at < 0 || p.at == last) continue;  // none, or the least and the largest are one point
    last = p.at;
    x_.push_back(p.x);
    y_.push_back(p.y);
  }
  least_ = largest_ = gap_ = Point{};
}

const std::vector<double>& DecimatedSeries::x() {
  Close();
  return x_;
}

const std::vector<double>& DecimatedSeries::y() {
  Close();
  return y_;
}

}  // namespace ltca::app::documents

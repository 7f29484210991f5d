#include "ltca/app/deck.hpp"
#include "ltca/app/tip_relief_default.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <toml.hpp>

#include "ltca/contact/mesh_state.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/registry.hpp"

namespace ltca::app {
namespace {

/// Rejects text the TOML parser should never see: larger than a deck can be, or nested deeper
/// than any deck needs: [ ] and { } outside strings and comments, and the parts of a dotted key
/// (a.b.c = 1 is a nested table). toml11 handles both by recursion: 10,000 levels of brackets
/// or 100,000 dotted parts overflow the stack.
/// Offset of the first byte that is not part of a well-formed UTF-8 sequence (RFC 3629: no
/// overlong forms, no surrogates, nothing above U+10FFFF), or npos.
std::size_t FirstInvalidUtf8(std::string_view text) {
  const auto* b = reinterpret_cast<const unsigned char*>(text.data());
  const std::size_t n = text.size();
  std::size_t i = 0;
  while (i < n) {
    const unsigned c = b[i];
    std::size_t len = 0;
    unsigned lo = 0x80, hi = 0xBF;  // range of the second byte
    if (c < 0x80) len = 1;
    else if (c >= 0xC2 && c <= 0xDF) len = 2;
    else if (c >= 0xE0 && c <= 0xEF) len = 3, lo = c == 0xE0 ? 0xA0 : 0x80, hi = c == 0xED ? 0x9F : 0xBF;
    else if (c >= 0xF0 && c <= 0xF4) len = 4, lo = c == 0xF0 ? 0x90 : 0x80, hi = c == 0xF4 ? 0x8F : 0xBF;
    else return i;
    if (i + len > n) return i;
    for (std::size_t k = 1; k < len; ++k) {
      const unsigned cc = b[i + k];
      if (k == 1 ? (cc < lo || cc > hi) : (cc < 0x80 || cc > 0xBF)) return i;
    }
    i += len;
  }
  return std::string_view::npos;
}

void CheckTextShape(std::string_view text) {
  if (text.size() > DeckLimits::kMaxFileBytes) {
    throw std::invalid_argument(fmt::format(
        "the text is {} bytes; expected a deck of at most {} bytes (4 MiB; docs/decks.md, Limits)",
        text.size(), DeckLimits::kMaxFileBytes));
  }
  // TOML is UTF-8; toml11 3.7 reads past the end of its buffer on an invalid byte in a literal
  // string (found by the deck fuzzer, tests/fuzz/regressions/), so the text is checked first.
  if (const std::size_t bad = FirstInvalidUtf8(text); bad != std::string_view::npos) {
    const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(bad), '\n');
    // Name the key (or section header) of that line: the text before '=' or the [header].
    const std::size_t begin = text.rfind('\n', bad) == std::string_view::npos ? 0 : text.rfind('\n', bad) + 1;
    std::string_view where = text.substr(begin, std::min(text.find('\n', bad), text.size()) - begin);
    const std::size_t eq = where.find('=');
    where = where.substr(0, eq == std::string_view::npos ? where.size() : eq);
    while (!where.empty() && (where.back() == ' ' || where.back() == '\t')) where.remove_suffix(1);
    while (!where.empty() && (where.front() == ' ' || where.front() == '\t')) where.remove_prefix(1);
    where = where.substr(0, std::min(where.size(), FirstInvalidUtf8(where)));  // its valid part
    // and the [section] it stands in: the last header line before it
    std::string section;
    for (std::size_t from = 0; from < begin; from = text.find('\n', from) + 1) {
      const std::string_view header = text.substr(from, text.find('\n', from) - from);
      if (header.starts_with('[') && FirstInvalidUtf8(header) == std::string_view::npos) {
        section = std::string(header.substr(0, header.find(']') + 1));
      }
    }
    std::string context = section;
    if (!where.empty()) context += fmt::format("{}{}{}", context.empty() ? "" : " ", eq == std::string_view::npos ? "" : "key ", where);
    throw std::invalid_argument(fmt::format(
        "line {}{}: byte 0x{:02X} is not valid UTF-8; expected a UTF-8 text (TOML decks are UTF-8)", line,
        context.empty() ? "" : " (" + context + ")", static_cast<unsigned>(static_cast<unsigned char>(text[bad]))));
  }
  int depth = 0;
  int dots = 0;  // dots in the current run of key (or number) characters
  int line = 1;
  std::size_t i = 0;
  const std::size_t n = text.size();
  while (i < n) {
    const char c = text[i];
    if (c == '\n') {
      ++line, ++i, dots = 0;
    } else if (c == '#') {  // comment: to the end of the line
      while (i < n && text[i] != '\n') ++i;
      dots = 0;
    } else if (c == '"' || c == '\'') {  // basic or literal string, single- or multi-line
      const std::string_view triple = c == '"' ? std::string_view("\"\"\"") : std::string_view("'''");
      const bool multi = text.substr(i, 3) == triple;
      i += multi ? 3 : 1;
      while (i < n) {
        const char d = text[i];
        if (d == '\n') {
          if (!multi) break;  // an unterminated single-line string: the parser reports it
          ++line;
        } else if (c == '"' && d == '\\') {
          ++i;  // skip the escaped character
          if (i < n && text[i] == '\n') ++line;
        } else if (d == c && (!multi || text.substr(i, 3) == triple)) {
          i += multi ? 3 : 1;
          break;
        }
        ++i;
      }
    } else {
      if (c == '[' || c == '{') {
        if (++depth > DeckLimits::kMaxNesting) {
          throw std::invalid_argument(fmt::format(
              "line {}: arrays / tables ([ ] and {{ }}) nested deeper than {} levels; expected at "
              "most {} (docs/decks.md, Limits)",
              line, DeckLimits::kMaxNesting, DeckLimits::kMaxNesting));
        }
      } else if ((c == ']' || c == '}') && depth > 0) {
        --depth;
      }
      if (c == '.' && ++dots > DeckLimits::kMaxNesting) {
        throw std::invalid_argument(fmt::format(
            "line {}: a dotted key with more than {} parts; expected at most {} (docs/decks.md, "
            "Limits)",
            line, DeckLimits::kMaxNesting, DeckLimits::kMaxNesting));
      }
      if (c == '=' || c == ',' || c == '[' || c == ']' || c == '{' || c == '}') dots = 0;
      ++i;
    }
  }
}

std::string Trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t");
  return std::string(text.substr(first, last - first + 1));
}

/// One --set override, "section.key=value", with its value read as TOML.
struct Override {
  std::string text;  ///< as given, for messages
  std::string section;
  std::string key;
  toml::value value;
};

Override ParseOverride(const std::string& text) {
  const auto bad = [&](const std::string& why) {
    return std::invalid_argument(fmt::format(
        "--set '{}': {}; expected section.key=value, e.g. --set load.torque_nm=100", text, why));
  };
  const auto eq = text.find('=');
  if (eq == std::string::npos) throw bad("no '='");
  const std::string path = Trim(std::string_view(text).substr(0, eq));
  const std::string value_text = Trim(std::string_view(text).substr(eq + 1));
  const auto dot = path.find('.');
  if (dot == std::string::npos) throw bad(fmt::format("no '.' between section and key in '{}'", path));
  Override o;
  o.text = text;
  o.section = Trim(std::string_view(path).substr(0, dot));
  o.key = Trim(std::string_view(path).substr(dot + 1));
  if (o.section.empty() || o.key.empty() || o.key.find('.') != std::string::npos) {
    throw bad(fmt::format("'{}' is not one section and one key", path));
  }
  if (value_text.empty()) throw bad("no value after '='");
  if (value_text.find_first_of("\r\n") != std::string::npos) throw bad("the value spans lines");
  try {
    CheckTextShape(value_text);
  } catch (const std::invalid_argument& e) {
    throw bad(e.what());
  }
  try {
    std::istringstream stream("value = " + value_text + "\n");
    o.value = toml::parse(stream, "--set").as_table().at("value");
  } catch (const std::exception&) {
    o.value = toml::value(value_text);  // not a TOML value: a bare word, taken as a string
  }
  return o;
}

/// Applies the overrides to the parsed deck, creating a missing section; the sections are read
/// afterwards, so an override meets the same checks (known key, type, range) as the file.
void ApplyOverrides(toml::value& root, const std::vector<std::string>& overrides) {
  for (const std::string& text : overrides) {
    const Override o = ParseOverride(text);
    toml::table& table = root.as_table();
    auto it = table.find(o.section);
    if (it == table.end()) it = table.emplace(o.section, toml::table{}).first;
    if (!it->second.is_table()) {
      throw std::invalid_argument(fmt::format(
          "--set '{}': '{}' is a key of the deck, not a section; expected section.key=value",
          o.text, o.section));
    }
    it->second.as_table()[o.key] = o.value;
  }
}

/// Reads a regular file of at most `limit` bytes with a bounded read. `who` starts every
/// message ("deck 'x.toml'", "[errors] profile_measured_csv = ..."), `noun` says what the file
/// should be ("deck file (TOML)") and `kind` names it in the size message ("a deck").
/// What the path is is checked before anything opens it: opening a FIFO blocks, a device never
/// ends.
std::string ReadBoundedFile(const std::filesystem::path& path, const std::string& who, const std::string& noun,
                            std::uintmax_t limit, const std::string& kind) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (status.type() == fs::file_type::not_found) {
    throw std::invalid_argument(fmt::format("{}: no such file; expected a {}", who, noun));
  }
  if (ec) {
    throw std::invalid_argument(fmt::format("{}: cannot open the file: {}", who, ec.message()));
  }
  if (fs::is_directory(status)) {
    throw std::invalid_argument(fmt::format("{} is a directory; expected a {}", who, noun));
  }
  if (!fs::is_regular_file(status)) {
    const char* type = fs::is_character_file(status) ? "a character device"
                       : fs::is_block_file(status)   ? "a block device"
                       : fs::is_fifo(status)         ? "a FIFO (named pipe)"
                       : fs::is_socket(status)       ? "a socket"
                                                     : "not a regular file";
    throw std::invalid_argument(fmt::format("{} is {}; expected a regular {}", who, type, noun));
  }
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) {
    throw std::invalid_argument(fmt::format("{}: cannot open the file: {}", who, ec.message()));
  }
  if (size > limit) {
    throw std::invalid_argument(fmt::format(
        "{}: the file is {} bytes; expected {} of at most {} bytes ({} MiB; docs/decks.md, Limits)", who, size, kind,
        limit, limit >> 20));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw std::invalid_argument(fmt::format("{}: cannot open the file", who));
  }
  // A bounded read: one byte more than the size seen, so a file that grew is noticed and the
  // caller's checks reject it if it now exceeds the limit.
  std::string text(static_cast<std::size_t>(size) + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (in.bad()) {
    throw std::invalid_argument(fmt::format("{}: cannot read the file", who));
  }
  if (text.size() > limit) {
    throw std::invalid_argument(fmt::format(
        "{}: the file grew to more than {} bytes while it was read; expected {} of at most {} bytes", who, limit, kind,
        limit));
  }
  return text;
}

/// The "looks like an absolute value" rule: a modification or manufacturing error is a small
/// change of the geometry, at most DeckLimits::kMaxDeviationFraction of the pin radius.
void RequireSmallDeviation(double value, const std::string& section, const std::string& key,
                           const geometry::PairParameters& pair, const std::string& shown = "") {
  const double limit = DeckLimits::kMaxDeviationFraction * pair.pin_radius;
  if (std::isfinite(value) && std::abs(value) > limit) {
    throw std::invalid_argument(fmt::format(
        "[{}] {} = {}: looks like an absolute value; a modification or manufacturing error is a "
        "small change of the geometry, at most {:g} % of [pair] pin_radius_mm = {} ({:.6g} mm){} "
        "(docs/decks.md, Limits)",
        section, key, shown.empty() ? fmt::format("{}", value) : shown,
        100.0 * DeckLimits::kMaxDeviationFraction, pair.pin_radius, limit,
        shown.empty() ? "" : fmt::format("; this one moves the profile by {:.6g} mm", std::abs(value))));
  }
}

/// One section of the deck: typed access to its keys, and a final check that every key present
/// was one the program knows.
class Section {
 public:
  Section(const toml::value* value, std::string name, std::vector<std::string> known)
      : name_(std::move(name)), known_(std::move(known)) {
    if (value != nullptr) {
      if (!value->is_table()) {
        throw std::invalid_argument(fmt::format("[{}] must be a table (section)", name_));
      }
      table_ = &value->as_table();
    }
    for (const auto& [key, unused] : Table()) {
      if (std::find(known_.begin(), known_.end(), key) == known_.end()) {
        throw std::invalid_argument(fmt::format("[{}] unknown key '{}'; expected one of: {}",
                                                name_, key, fmt::join(known_, ", ")));
      }
    }
  }

  bool Present() const { return table_ != nullptr; }
  bool Has(const std::string& key) const { return Table().count(key) != 0; }

  double Real(const std::string& key, const char* what) const {
    const toml::value& v = Get(key, what);
    if (v.is_integer()) return static_cast<double>(v.as_integer());
    if (v.is_floating()) return v.as_floating();
    throw std::invalid_argument(
        fmt::format("[{}] {} = {}: expected a number ({})", name_, key, toml::format(v), what));
  }
  double Real(const std::string& key, double fallback, const char* what) const {
    return Has(key) ? Real(key, what) : fallback;
  }
  std::vector<double> RealList(const std::string& key, const char* what) const {
    if (!Has(key)) return {};
    const toml::value& v = Get(key, what);
    if (!v.is_array()) {
      throw std::invalid_argument(fmt::format("[{}] {}: expected an array of numbers ({})", name_, key, what));
    }
    std::vector<double> out;
    for (const toml::value& item : v.as_array()) {
      if (item.is_integer()) out.push_back(static_cast<double>(item.as_integer()));
      else if (item.is_floating()) out.push_back(item.as_floating());
      else throw std::invalid_argument(fmt::format("[{}] {}: expected numbers only ({})", name_, key, what));
    }
    return out;
  }
  int Integer(const std::string& key, const char* what) const {
    const toml::value& v = Get(key, what);
    if (!v.is_integer() || v.as_integer() < std::numeric_limits<int>::min() ||
        v.as_integer() > std::numeric_limits<int>::max()) {
      throw std::invalid_argument(fmt::format("[{}] {} = {}: expected an integer ({})", name_,
                                              key, toml::format(v), what));
    }
    return static_cast<int>(v.as_integer());
  }
  int Integer(const std::string& key, int fallback, const char* what) const {
    return Has(key) ? Integer(key, what) : fallback;
  }
  /// An integer >= 0 (up to the TOML limit 2^63 - 1).
  std::uint64_t Unsigned(const std::string& key, std::uint64_t fallback, const char* what) const {
    if (!Has(key)) return fallback;
    const toml::value& v = Get(key, what);
    if (!v.is_integer() || v.as_integer() < 0) {
      throw std::invalid_argument(fmt::format("[{}] {} = {}: expected an integer >= 0 ({})", name_, key,
                                              toml::format(v), what));
    }
    return static_cast<std::uint64_t>(v.as_integer());
  }
  std::string String(const std::string& key, const char* what) const {
    const toml::value& v = Get(key, what);
    if (!v.is_string()) {
      throw std::invalid_argument(fmt::format("[{}] {} = {}: expected a string ({})", name_, key,
                                              toml::format(v), what));
    }
    return v.as_string().str;
  }
  std::string String(const std::string& key, const std::string& fallback, const char* what) const {
    return Has(key) ? String(key, what) : fallback;
  }

 private:
  const toml::table& Table() const {
    static const toml::table kEmpty;
    return table_ != nullptr ? *table_ : kEmpty;
  }
  const toml::value& Get(const std::string& key, const char* what) const {
    const auto it = Table().find(key);
    if (it == Table().end()) {
      throw std::invalid_argument(
          fmt::format("[{}] missing required key '{}' ({})", name_, key, what));
    }
    return it->second;
  }

  const toml::table* table_ = nullptr;
  std::string name_;
  std::vector<std::string> known_;
};

const toml::value* Find(const toml::table& root, const std::string& key) {
  const auto it = root.find(key);
  return it == root.end() ? nullptr : &it->second;
}

Section RequiredSection(const toml::table& root, const std::string& name,
                        std::vector<std::string> known) {
  const toml::value* v = Find(root, name);
  if (v == nullptr) throw std::invalid_argument(fmt::format("missing required section [{}]", name));
  return Section(v, name, std::move(known));
}

CaseInfo ReadCase(const Section& s) {
  CaseInfo info;
  info.title = s.String("title", "a short title of the case");
  info.source = s.String("source", "", "provenance: paper, table / section");
  return info;
}

geometry::PairParameters ReadPair(const Section& s) {
  geometry::PairParameters p;
  p.pin_count = s.Integer("pin_count", "number of pins z_p");
  p.tooth_count = s.Integer("tooth_count", "number of cycloid teeth z_c");
  p.pin_radius = s.Real("pin_radius_mm", "pin radius r_rp in mm");
  p.pin_circle_radius = s.Real("pin_circle_radius_mm", "pin-circle radius R_p in mm");
  p.eccentricity = s.Real("eccentricity_mm", "eccentricity e in mm");
  p.face_width = s.Real("face_width_mm", "face width B_c in mm");
  if (p.pin_count > DeckLimits::kMaxPins) {
    throw std::invalid_argument(fmt::format(
        "[pair] pin_count = {}: expected at most {} pins (docs/decks.md, Limits)", p.pin_count,
        DeckLimits::kMaxPins));
  }
  p.Validate();
  return p;
}

geometry::Modification ReadModification(const Section& s, const geometry::PairParameters& pair) {
  geometry::Modification m;
  m.pin_radius = s.Real("pin_radius_mm", 0.0, "isometric modification dR_rp in mm");
  m.pin_circle_radius = s.Real("pin_circle_radius_mm", 0.0, "offset modification dR_p in mm");
  m.rotation = units::DegToRad(s.Real("rotation_deg", 0.0, "angle-rotation modification in deg"));
  m.tip_relief.truncation = s.Real("tip_truncation_mm", 0.0, "tip truncation in mm along the tooth axis (issue 12)");
  m.tip_relief.rounding_radius = s.Real("tip_rounding_radius_mm", 0.0, "tip rounding radius in mm (issue 12)");
  m.Validate(pair);
  RequireSmallDeviation(m.pin_radius, "modification", "pin_radius_mm", pair);
  RequireSmallDeviation(m.pin_circle_radius, "modification", "pin_circle_radius_mm", pair);
  // The rotation moves the profile along the pin circle by R_p * angle.
  RequireSmallDeviation(pair.pin_circle_radius * m.rotation, "modification", "rotation_deg", pair,
                        fmt::format("{}", units::RadToDeg(m.rotation)));
  return m;
}

/// [errors] profile_measured_csv: the trace, read from `directory` when the path is relative.
geometry::MeasuredProfile ReadMeasuredProfile(const std::string& value, const std::filesystem::path& directory) {
  const std::string key = fmt::format("[errors] profile_measured_csv = \"{}\"", value);
  if (value.empty()) {
    throw std::invalid_argument(fmt::format("{}: expected the path of a CSV file (relative to the deck's directory)", key));
  }
  const std::filesystem::path path = std::filesystem::path(value).is_relative() ? directory / value : std::filesystem::path(value);
  const std::string text = ReadBoundedFile(
      path, path.string() == value ? key : fmt::format("{} (read as '{}')", key, path.string()),
      "CSV file of a measured profile (profile_angle_deg or arc_length_mm, deviation_um)",
      DeckLimits::kMaxProfileCsvBytes, "a profile trace");
  return geometry::ParseMeasuredProfile(text, key);
}

geometry::ManufacturingErrors ReadErrors(const Section& s, const geometry::PairParameters& pair,
                                         const std::filesystem::path& directory) {
  geometry::ManufacturingErrors e;
  e.pin_circle_deviation = s.Real("pin_circle_deviation_mm", 0.0, "pin-circle deviation delta_Rp of Liu eq. 5 in mm");
  e.pin_circle_reading = geometry::ParsePinCircleReading(
      s.String("pin_circle_reading", "radius", "how eq. 5 applies delta_Rp: radius | diameter"));
  e.profile_layer = s.Real("cycloid_profile_layer_mm", 0.0, "uniform layer on the cycloid profile in mm");
  e.cumulative_pitch_deviation = s.RealList("cumulative_pitch_deviation_mm", "one cumulative pitch deviation per pin in mm");
  e.pin_radius_deviations = s.RealList("pin_radius_deviations_mm", "one pin radius deviation per pin in mm");
  e.pin_radial_deviations = s.RealList("pin_radial_deviations_mm", "one radial pin position deviation per pin in mm");
  e.lead_crowning = units::UmToMm(s.Real("lead_crowning_um", 0.0, "lead crowning of the cycloid in um"));
  e.lead_slope = units::UmToMm(s.Real("lead_slope_um", 0.0, "lead slope error of the cycloid over the face width in um"));
  auto& random = e.profile_random;
  random.zone = units::UmToMm(s.Real("profile_random_zone_um", 0.0, "full width of the random profile tolerance zone in um"));
  random.elements = s.Integer("profile_random_elements", random.elements, "random profile elements per tooth space");
  random.seed = s.Unsigned("profile_random_seed", random.seed, "seed of the random profile deviation");
  random.distribution = geometry::ParseProfileRandomDistribution(
      s.String("profile_random_distribution", "uniform", "uniform | normal"));
  random.spacing = geometry::ParseProfileElementSpacing(
      s.String("profile_random_spacing", "arc_length", "arc_length | parameter"));
  random.Validate(pair.tooth_count);
  if (s.Has("profile_measured_csv")) {
    e.profile_measured = ReadMeasuredProfile(
        s.String("profile_measured_csv", "path of a measured profile trace, relative to the deck"), directory);
  }
  e.Validate(pair.pin_count);
  RequireSmallDeviation(e.pin_circle_deviation, "errors", "pin_circle_deviation_mm", pair);
  RequireSmallDeviation(random.zone, "errors", "profile_random_zone_um", pair, fmt::format("{}", units::MmToUm(random.zone)));
  if (e.profile_measured) {
    for (std::size_t i = 0; i < e.profile_measured->deviation.size(); ++i) {
      const double v = e.profile_measured->deviation[i];
      RequireSmallDeviation(v, "errors",
                            fmt::format("profile_measured_csv (line {} of the file, deviation_um)", e.profile_measured->line[i]),
                            pair, fmt::format("{}", units::MmToUm(v)));
    }
  }
  RequireSmallDeviation(e.profile_layer, "errors", "cycloid_profile_layer_mm", pair);
  for (const auto& [key, list] : {std::pair{"cumulative_pitch_deviation_mm", &e.cumulative_pitch_deviation},
                                  std::pair{"pin_radius_deviations_mm", &e.pin_radius_deviations},
                                  std::pair{"pin_radial_deviations_mm", &e.pin_radial_deviations}}) {
    for (std::size_t j = 0; j < list->size(); ++j) {
      RequireSmallDeviation((*list)[j], "errors", fmt::format("{}[{}]", key, j), pair);
    }
  }
  RequireSmallDeviation(e.lead_crowning, "errors", "lead_crowning_um", pair, fmt::format("{}", units::MmToUm(e.lead_crowning)));
  RequireSmallDeviation(e.lead_slope, "errors", "lead_slope_um", pair, fmt::format("{}", units::MmToUm(e.lead_slope)));
  return e;
}

geometry::AssemblyErrors ReadAssembly(const Section& s, const geometry::PairParameters& pair) {
  geometry::AssemblyErrors a;
  a.centre_dx = s.Real("centre_dx_mm", 0.0, "frame-fixed offset of the cycloid centre along X in mm");
  a.centre_dy = s.Real("centre_dy_mm", 0.0, "frame-fixed offset of the cycloid centre along Y in mm");
  a.eccentricity_deviation = s.Real("eccentricity_deviation_mm", 0.0, "eccentricity deviation in mm");
  a.misalignment_xz = units::DegToRad(s.Real("misalignment_xz_deg", 0.0, "tilt phi of the cycloid axis in the XZ plane in deg"));
  a.misalignment_yz = units::DegToRad(s.Real("misalignment_yz_deg", 0.0, "tilt gamma of the cycloid axis in the YZ plane in deg"));
  a.pivot = geometry::ParseMisalignmentPivot(s.String("misalignment_pivot", "face", "face | mid"));
  a.Validate();
  RequireSmallDeviation(a.centre_dx, "errors", "centre_dx_mm", pair);
  RequireSmallDeviation(a.centre_dy, "errors", "centre_dy_mm", pair);
  RequireSmallDeviation(a.eccentricity_deviation, "errors", "eccentricity_deviation_mm", pair);
  // The largest shift of a slice centre: over the face width from the pivot.
  for (const auto& [key, angle] : {std::pair{"misalignment_xz_deg", a.misalignment_xz},
                                   std::pair{"misalignment_yz_deg", a.misalignment_yz}}) {
    RequireSmallDeviation(pair.face_width * std::tan(angle), "errors", key, pair, fmt::format("{}", units::RadToDeg(angle)));
  }
  return a;
}

contact::ContactSettings ReadContact(const Section& s) {
  contact::ContactSettings c;
  c.law = contact::ParseLawKind(s.String("law", "hertz-line", "hertz-line | sagitta | linear"));
  c.rho_convention = contact::ParseRhoConvention(s.String("rho_convention", "signed", "signed | absolute"));
  c.stiffness_per_length = s.Real("stiffness_n_per_mm2", 0.0, "linear law: stiffness per mm of contact length");
  c.log_radius_cap = s.Real("log_radius_cap_mm", 0.0, "largest cycloid radius in the hertz-line logarithm, mm");
  c.Validate();
  return c;
}

geometry::GeometrySettings ReadGeometry(const Section& s) {
  geometry::GeometrySettings g;
  const std::string mode = s.String("geometry_mode", "analytic", "analytic | elements (Liu's discrete surface)");
  if (mode == "analytic") g.mode = geometry::GeometrySettings::Mode::kAnalytic;
  else if (mode == "elements") g.mode = geometry::GeometrySettings::Mode::kElements;
  else throw std::invalid_argument(fmt::format("[geometry] geometry_mode = \"{}\": expected \"analytic\" or \"elements\"", mode));
  g.profile_elements = s.Integer("profile_elements", g.profile_elements, "elements along one tooth space");
  g.width_slices = s.Integer("width_slices", g.width_slices, "slices across the face width");
  g.Validate();
  return g;
}

SolverOptions ReadSolver(const Section& s) {
  SolverOptions o;
  if (s.Has("preset")) o = ApplyPreset(o, s.String("preset", "a named preset: liu2021"));
  o.name = s.String("name", o.name, "bisection | energy-qp | energy-groups | compatibility");
  solvers::MakeSolver(o.name);  // rejects an unknown name, listing the valid ones
  const std::string kinematics = s.String("kinematics", "linearised", "linearised | exact");
  if (kinematics == "linearised") o.kinematics = contact::ContactKinematics::kLinearised;
  else if (kinematics == "exact") o.kinematics = contact::ContactKinematics::kExact;
  else throw std::invalid_argument(fmt::format("[solver] kinematics = \"{}\": expected \"linearised\" or \"exact\"", kinematics));
  o.torque_tolerance = s.Real("torque_tolerance", o.torque_tolerance, "relative torque tolerance");
  o.max_iterations = s.Integer("max_iterations", o.max_iterations, "iteration limit");
  o.nlopt_algorithm = s.String("nlopt_algorithm", o.nlopt_algorithm, "compatibility: NLopt algorithm name");
  o.Validate();
  return o;
}

contact::Material ReadMaterial(const Section& s) {
  contact::Material m;
  m.young_modulus = s.Real("young_modulus_mpa", "Young's modulus of the cycloid in MPa");
  m.poisson_ratio = s.Real("poisson_ratio", "Poisson's ratio of the cycloid");
  m.pin_young_modulus =
      s.Real("pin_young_modulus_mpa", m.young_modulus, "Young's modulus of the pins in MPa");
  m.pin_poisson_ratio = s.Real("pin_poisson_ratio", m.poisson_ratio, "Poisson's ratio of the pins");
  m.contact_stress_limit = s.Real("contact_stress_limit_mpa", m.contact_stress_limit,
                                  "contact stress above which a result is flagged, MPa");
  m.Validate();
  return m;
}

LoadCase ReadLoad(const Section& s) {
  LoadCase load;
  load.torque = units::NmToNmm(s.Real("torque_nm", "torque on this cycloid gear in N*m"));
  load.Validate();
  return load;
}

Sweep ReadSweep(const Section& s, const geometry::PairParameters& pair) {
  Sweep sweep;
  const double period_deg = 360.0 / pair.pin_count;
  sweep.crank_start = units::DegToRad(s.Real("crank_start_deg", 0.0, "first crank angle in deg"));
  sweep.crank_end = units::DegToRad(
      s.Real("crank_end_deg", units::RadToDeg(sweep.crank_start) + period_deg,
             "last crank angle in deg (inclusive)"));
  sweep.positions = s.Integer("positions", 91, "number of crank positions");
  sweep.Validate();
  return sweep;
}

StiffnessSettings ReadStiffness(const Section& s) {
  StiffnessSettings st;
  st.steps = s.Integer("steps_per_branch", st.steps, "torque levels per branch from -T to +T, odd");
  const std::string rigidity = s.String("rigidity", "secant", "secant | tangent");
  if (rigidity == "secant") st.rigidity = StiffnessSettings::Rigidity::kSecant;
  else if (rigidity == "tangent") st.rigidity = StiffnessSettings::Rigidity::kTangent;
  else throw std::invalid_argument(fmt::format("[stiffness] rigidity = \"{}\": expected \"secant\" or \"tangent\"", rigidity));
  if (s.Has("tangent_torque_nm")) {
    st.tangent_torque = units::NmToNmm(s.Real("tangent_torque_nm", "torque of the tangent rigidity in N*m"));
  }
  st.lost_motion_fraction =
      s.Real("lost_motion_fraction", st.lost_motion_fraction, "fraction of T at which lost motion is read");
  if (s.Has("crank_deg")) st.crank = units::DegToRad(s.Real("crank_deg", "one crank angle in deg"));
  st.Validate();
  return st;
}

}  // namespace

void StiffnessSettings::Validate() const {
  if (steps < 3 || steps > kMaxSteps || steps % 2 == 0) {
    throw std::invalid_argument(fmt::format(
        "[stiffness] steps_per_branch = {}: expected an odd integer from 3 to {} (torque levels from -T to +T, "
        "zero among them)",
        steps, kMaxSteps));
  }
  if (rigidity == Rigidity::kTangent && !(std::isfinite(tangent_torque) && tangent_torque != 0.0)) {
    throw std::invalid_argument(fmt::format(
        "[stiffness] tangent_torque_nm = {}: expected a finite torque other than 0 in N*m with rigidity = \"tangent\" "
        "(the free play at zero torque has no slope)",
        units::NmmToNm(tangent_torque)));
  }
  if (!(lost_motion_fraction > 0.0 && lost_motion_fraction < 1.0)) {
    throw std::invalid_argument(fmt::format(
        "[stiffness] lost_motion_fraction = {}: expected a fraction of the rated torque between 0 and 1 "
        "(exclusive; catalogues use 0.03)",
        lost_motion_fraction));
  }
  const double max_crank = units::DegToRad(DeckLimits::kMaxCrankDeg);
  if (crank && !(std::isfinite(*crank) && std::abs(*crank) <= max_crank)) {
    throw std::invalid_argument(fmt::format(
        "[stiffness] crank_deg = {}: expected a finite crank angle within +-{} deg (docs/decks.md, Limits)",
        units::RadToDeg(*crank), DeckLimits::kMaxCrankDeg));
  }
}

void LoadCase::Validate() const {
  if (!std::isfinite(torque)) {
    throw std::invalid_argument(fmt::format(
        "[load] torque_nm = {}: expected a finite torque in N*m (its sign picks the flank, "
        "docs/conventions.md)",
        units::NmmToNm(torque)));
  }
}

void Sweep::Validate() const {
  if (positions < 1 || positions > DeckLimits::kMaxPositions) {
    throw std::invalid_argument(fmt::format(
        "[sweep] positions = {}: expected an integer from 1 to {} (docs/decks.md, Limits)",
        positions, DeckLimits::kMaxPositions));
  }
  const double max_crank = units::DegToRad(DeckLimits::kMaxCrankDeg);
  for (const auto& [key, value] : {std::pair{"crank_start_deg", crank_start}, std::pair{"crank_end_deg", crank_end}}) {
    if (!std::isfinite(value) || std::abs(value) > max_crank) {
      throw std::invalid_argument(fmt::format(
          "[sweep] {} = {}: expected a finite crank angle within +-{} deg (docs/decks.md, Limits)",
          key, units::RadToDeg(value), DeckLimits::kMaxCrankDeg));
    }
  }
  if (positions > 1 && crank_end <= crank_start) {
    throw std::invalid_argument(fmt::format(
        "[sweep] crank_end_deg = {}: expected an angle above crank_start_deg = {} when "
        "positions > 1",
        units::RadToDeg(crank_end), units::RadToDeg(crank_start)));
  }
}

std::vector<double> Sweep::CrankAngles() const {
  std::vector<double> angles(static_cast<std::size_t>(positions));
  for (int i = 0; i < positions; ++i) {
    angles[static_cast<std::size_t>(i)] =
        positions == 1 ? crank_start
                       : crank_start + (crank_end - crank_start) * i / (positions - 1);
  }
  return angles;
}

Deck::ModelInfo Deck::Model() const {
  // The rule of contact::MeshModel: slices when something varies along the face width.
  ModelInfo m;
  m.surface = geometry.mode == geometry::GeometrySettings::Mode::kElements ? "elements" : "analytic";
  if (pins) {
    m.name = "slices+pin-bending";
    m.slices = geometry.width_slices;
  } else if (errors.VariesAlongWidth() || assembly.VariesAlongWidth()) {
    m.name = "slices";
    m.slices = geometry.width_slices;
  } else {
    m.name = "plane";
    m.slices = 1;
    if (width_slices_given && geometry.width_slices != 1) {
      m.note = fmt::format("width_slices = {} not used: nothing varies along the face width, so the plane model ran",
                           geometry.width_slices);
    }
  }
  for (const std::string& note : notes) m.note += (m.note.empty() ? "" : "; ") + note;
  m.tip_relief = modification.tip_relief;
  m.tip_relief_source = tip_relief_source;
  m.tip_relief_note = tip_relief_note;
  return m;
}

solvers::LoadProblem::CheckedCoupling Deck::MakeCoupling(const contact::MeshModel& model) const {
  if (!pins) return {};
  const contact::PinBeam beam(*pins, RequireMaterial(), pair.pin_radius);
  const std::vector<contact::PinContact> points = model.Evaluate(sweep.crank_start).pins;
  contact::FactoredPinBending f = contact::PinBendingFactors(points, beam, pair.face_width);
  return solvers::LoadProblem::CheckCoupling(contact::PinBendingCoupling(points, beam, pair.face_width),
                                             model.point_count(),
                                             {std::move(f.stiffness), std::move(f.loads), std::move(f.local)});
}

solvers::LoadProblem Deck::MakeProblem(const std::shared_ptr<const contact::MeshModel>& model, double crank,
                                       contact::ContactKinematics kinematics) const {
  solvers::LoadProblem problem(model, crank, contact, RequireMaterial(), RequireLoad().torque, kinematics);
  if (!pins) return problem;
  return problem.WithCoupling(MakeCoupling(*model));
}

const contact::Material& Deck::RequireMaterial() const {
  if (!material) {
    throw std::invalid_argument(
        fmt::format("deck '{}': missing required section [material] for this command", name));
  }
  return *material;
}

const LoadCase& Deck::RequireLoad() const {
  if (!load) {
    throw std::invalid_argument(
        fmt::format("deck '{}': missing required section [load] for this command", name));
  }
  return *load;
}

Deck ParseDeck(std::string_view toml_text, const std::string& name, const std::vector<std::string>& overrides,
               const std::filesystem::path& directory) {
  Deck deck;
  deck.name = name;
  try {
    CheckTextShape(toml_text);
    std::istringstream stream{std::string(toml_text)};
    toml::value root_value = toml::parse(stream, name);
    ApplyOverrides(root_value, overrides);
    const toml::table& root = root_value.as_table();
    const std::vector<std::string> sections = {"case",     "pair", "modification", "errors", "contact", "geometry",
                                               "material", "pins", "load",         "sweep",  "solver", "stiffness"};
    for (const auto& [key, unused] : root) {
      if (std::find(sections.begin(), sections.end(), key) == sections.end()) {
        throw std::invalid_argument(fmt::format("unknown section or key '{}'; expected one of: {}",
                                                key, fmt::join(sections, ", ")));
      }
    }
    deck.info = ReadCase(RequiredSection(root, "case", {"title", "source"}));
    deck.pair = ReadPair(RequiredSection(
        root, "pair",
        {"pin_count", "tooth_count", "pin_radius_mm", "pin_circle_radius_mm", "eccentricity_mm",
         "face_width_mm"}));
    const Section modification(
        Find(root, "modification"), "modification",
        {"pin_radius_mm", "pin_circle_radius_mm", "rotation_deg", "tip_truncation_mm", "tip_rounding_radius_mm"});
    deck.modification = ReadModification(modification, deck.pair);
    const Section errors(Find(root, "errors"), "errors",
                         {"pin_circle_deviation_mm", "pin_circle_reading", "cycloid_profile_layer_mm",
                          "cumulative_pitch_deviation_mm", "pin_radius_deviations_mm", "pin_radial_deviations_mm",
                          "lead_crowning_um", "lead_slope_um", "centre_dx_mm", "centre_dy_mm",
                          "eccentricity_deviation_mm", "misalignment_xz_deg", "misalignment_yz_deg",
                          "misalignment_pivot", "profile_random_zone_um", "profile_random_elements",
                          "profile_random_seed", "profile_random_distribution", "profile_random_spacing",
                          "profile_measured_csv"});
    deck.errors = ReadErrors(errors, deck.pair, directory);
    deck.assembly = ReadAssembly(errors, deck.pair);
    // Keys given without effect are reported (in the model's note), not silently dropped.
    if (deck.errors.profile_random.zone == 0.0) {
      for (const char* key : {"profile_random_elements", "profile_random_seed", "profile_random_distribution",
                              "profile_random_spacing"}) {
        if (errors.Has(key)) deck.notes.push_back(fmt::format("[errors] {} not used: profile_random_zone_um is 0", key));
      }
    }
    if (!deck.assembly.VariesAlongWidth() && errors.Has("misalignment_pivot")) {
      deck.notes.push_back("[errors] misalignment_pivot not used: no misalignment");
    }
    deck.contact = ReadContact(Section(Find(root, "contact"), "contact",
                                       {"law", "rho_convention", "stiffness_n_per_mm2",
                                        "log_radius_cap_mm"}));
    const Section geometry(Find(root, "geometry"), "geometry", {"geometry_mode", "profile_elements", "width_slices"});
    deck.geometry = ReadGeometry(geometry);
    deck.width_slices_given = geometry.Has("width_slices");
    deck.solver = ReadSolver(Section(Find(root, "solver"), "solver",
                                     {"name", "kinematics", "torque_tolerance", "max_iterations", "preset", "nlopt_algorithm"}));
    const Section material(Find(root, "material"), "material",
                           {"young_modulus_mpa", "poisson_ratio", "pin_young_modulus_mpa",
                            "pin_poisson_ratio", "contact_stress_limit_mpa"});
    if (material.Present()) deck.material = ReadMaterial(material);
    const Section pins(Find(root, "pins"), "pins", {"span_mm", "support", "face_offset_mm"});
    if (pins.Present()) {
      contact::PinSupport p;
      p.span = pins.Real("span_mm", "distance between the two supports of a pin in mm");
      p.support = contact::ParsePinSupport(pins.String("support", "simply-supported", "simply-supported | clamped"));
      p.face_offset = pins.Real("face_offset_mm", "from the first support to face B of the cycloid in mm");
      p.Validate(deck.pair.face_width);
      deck.pins = p;
    }
    const Section load(Find(root, "load"), "load", {"torque_nm"});
    if (load.Present()) deck.load = ReadLoad(load);
    deck.sweep = ReadSweep(
        Section(Find(root, "sweep"), "sweep", {"crank_start_deg", "crank_end_deg", "positions"}),
        deck.pair);
    deck.stiffness = ReadStiffness(Section(Find(root, "stiffness"), "stiffness",
                                           {"steps_per_branch", "rigidity", "tangent_torque_nm",
                                            "lost_motion_fraction", "crank_deg"}));
    // The geometry must be realisable: this rejects undercut (looped) profiles, also when the
    // profile layer of [errors] is what makes them loop.
    const geometry::RealPair real = deck.MakeRealPair();  // analytic: cheap to check
    if (modification.Has("tip_truncation_mm") || modification.Has("tip_rounding_radius_mm")) {
      deck.tip_relief_source = "deck";
    } else if (std::abs(deck.pair.ToothDifference()) >= 2) {
      ChooseDefaultTipRelief(deck);
    }
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("deck '{}': {}", name, e.what()));
  } catch (const std::exception& e) {  // TOML syntax errors and the like
    throw std::invalid_argument(fmt::format("deck '{}': {}", name, e.what()));
  }
  return deck;
}

Deck LoadDeck(const std::filesystem::path& path, const std::vector<std::string>& overrides) {
  const std::string name = path.string();
  const std::string text = ReadBoundedFile(path, fmt::format("deck '{}'", name), "deck file (TOML)",
                                           DeckLimits::kMaxFileBytes, "a deck");
  // Relative paths in the deck (profile_measured_csv) are read from the deck's own directory.
  return ParseDeck(text, name, overrides, path.parent_path());
}

Deck DefaultDeck(const std::vector<std::string>& overrides) {
  return ParseDeck(DefaultDeckText(), "built-in default (Liu 2021 Table 1)", overrides);
}

}  // namespace ltca::app

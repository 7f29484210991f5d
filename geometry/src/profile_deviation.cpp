#include "ltca/geometry/profile_deviation.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>

#include <fmt/format.h>

#include "ltca/geometry/arc_length.hpp"
#include "ltca/geometry/counter_rng.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::geometry {
namespace {

// Rounding allowance for measured points beyond the ends of the flank, relative to half the flank.
constexpr double kEndTolerance = 1e-3;

constexpr std::string_view kAngleHeader = "profile_angle_deg";
constexpr std::string_view kArcHeader = "arc_length_mm";
constexpr std::string_view kDeviationHeader = "deviation_um";

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::string_view Trim(std::string_view s) {
  while (!s.empty() && IsSpace(s.front())) s.remove_prefix(1);
  while (!s.empty() && IsSpace(s.back())) s.remove_suffix(1);
  return s;
}

// The fields of a line: split at commas when there is one (each field trimmed, empty fields
// kept so that they are reported), otherwise at runs of whitespace.
std::vector<std::string_view> Fields(std::string_view line) {
  std::vector<std::string_view> fields;
  if (line.find(',') != std::string_view::npos) {
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = line.find(',', start);
      fields.push_back(Trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    return fields;
  }
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && IsSpace(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !IsSpace(line[i])) ++i;
    if (i > start) fields.push_back(line.substr(start, i - start));
  }
  return fields;
}

// A whole field as a double (a leading '+' allowed); false if it is not a number.
bool ParseNumber(std::string_view field, double& value) {
  if (field.size() > 1 && field.front() == '+' && field[1] != '-' && field[1] != '+') field.remove_prefix(1);
  if (field.empty()) return false;
  const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (end != field.data() + field.size()) return false;
  if (ec == std::errc::result_out_of_range) {
    // A number beyond double's range: overflow to +-inf (reported as not finite), underflow to 0.
    value = std::strtod(std::string(field).c_str(), nullptr);
    return true;
  }
  return ec == std::errc();
}

std::string ExpectedHeader() {
  return fmt::format("a header line naming the columns, \"{}, {}\" or \"{}, {}\"", kAngleHeader, kDeviationHeader,
                     kArcHeader, kDeviationHeader);
}

// The draw of element e of tooth space k (the counter layout of the header).
double DrawElement(const RandomProfileDeviation& random, int tooth_space, int element) {
  const std::uint64_t stream = kRandomProfileStream + static_cast<std::uint64_t>(tooth_space);
  const std::uint64_t base = static_cast<std::uint64_t>(element) * kRandomProfileAttempts;
  if (random.distribution == ProfileRandomDistribution::kUniform) {
    return random.zone * (rng::Uniform01(random.seed, stream, base) - 0.5);
  }
  // Truncation by rejection along the counter: the first draw within +-3 sigma, so that the zone
  // is never left and the shape inside it is the normal's (a part outside its tolerance is
  // rejected at inspection; clipping would pile 0.27 % of the elements onto the zone's edges).
  double z = 0.0;
  for (std::uint64_t a = 0; a < kRandomProfileAttempts; ++a) {
    z = rng::StandardNormal(random.seed, stream, base + a);
    if (std::abs(z) <= 3.0) return random.zone / 6.0 * z;
  }
  return random.zone / 6.0 * std::clamp(z, -3.0, 3.0);
}

}  // namespace

ProfileRandomDistribution ParseProfileRandomDistribution(const std::string& text) {
  if (text == "uniform") return ProfileRandomDistribution::kUniform;
  if (text == "normal") return ProfileRandomDistribution::kNormal;
  throw std::invalid_argument(fmt::format(
      "[errors] profile_random_distribution = \"{}\": expected \"uniform\" or \"normal\"", text));
}

ProfileElementSpacing ParseProfileElementSpacing(const std::string& text) {
  if (text == "arc_length") return ProfileElementSpacing::kArcLength;
  if (text == "parameter") return ProfileElementSpacing::kParameter;
  throw std::invalid_argument(fmt::format(
      "[errors] profile_random_spacing = \"{}\": expected \"arc_length\" or \"parameter\"", text));
}

void RandomProfileDeviation::Validate(int tooth_count) const {
  if (!std::isfinite(zone) || zone < 0.0) {
    throw std::invalid_argument(fmt::format(
        "[errors] profile_random_zone_um = {}: expected a finite tolerance zone width >= 0 in um", units::MmToUm(zone)));
  }
  if (elements < 1 || elements > kMaxElements) {
    throw std::invalid_argument(fmt::format(
        "[errors] profile_random_elements = {}: expected 1 .. {} elements per tooth space (Liu: 800)", elements,
        kMaxElements));
  }
  const long long values = static_cast<long long>(elements) * tooth_count;
  if (values > kMaxValues) {
    throw std::invalid_argument(fmt::format(
        "[errors] profile_random_elements = {}: with {} tooth spaces that is {} random values, expected at most {}",
        elements, tooth_count, values, kMaxValues));
  }
}

MeasuredProfile ParseMeasuredProfile(const std::string& text, const std::string& source_name) {
  MeasuredProfile trace;
  trace.source = source_name;
  const auto fail = [&](int line, const std::string& what) {
    throw std::invalid_argument(fmt::format("{}: line {}: {}", source_name, line, what));
  };
  std::string_view rest(text);
  if (rest.substr(0, 3) == "\xEF\xBB\xBF") rest.remove_prefix(3);  // a UTF-8 byte-order mark
  bool have_header = false;
  int line_number = 0;
  double previous_x = 0.0;  // as written, for messages
  while (!rest.empty()) {
    const std::size_t newline = rest.find('\n');
    const std::string_view raw = rest.substr(0, newline);
    rest = newline == std::string_view::npos ? std::string_view() : rest.substr(newline + 1);
    ++line_number;
    const std::string_view line = Trim(raw);
    if (line.empty() || line.front() == '#') continue;
    const auto fields = Fields(line);
    if (!have_header) {
      if (fields.size() != 2 || (fields[0] != kAngleHeader && fields[0] != kArcHeader) || fields[1] != kDeviationHeader) {
        fail(line_number, fmt::format("\"{}\": expected {} before the data", line, ExpectedHeader()));
      }
      trace.abscissa = fields[0] == kAngleHeader ? MeasuredProfile::Abscissa::kProfileAngle
                                                 : MeasuredProfile::Abscissa::kArcLength;
      have_header = true;
      continue;
    }
    const std::string_view x_name = trace.abscissa == MeasuredProfile::Abscissa::kProfileAngle ? kAngleHeader : kArcHeader;
    if (fields.size() != 2) {
      fail(line_number, fmt::format("\"{}\" has {} fields: expected two numbers, {} and {}, separated by a comma or "
                                    "whitespace",
                                    line, fields.size(), x_name, kDeviationHeader));
    }
    double x = 0.0, deviation_um = 0.0;
    if (!ParseNumber(fields[0], x)) fail(line_number, fmt::format("{} \"{}\": expected a number", x_name, fields[0]));
    if (!ParseNumber(fields[1], deviation_um)) {
      fail(line_number, fmt::format("{} \"{}\": expected a number", kDeviationHeader, fields[1]));
    }
    if (!std::isfinite(x)) fail(line_number, fmt::format("{} = {}: expected a finite number", x_name, x));
    if (!std::isfinite(deviation_um)) {
      fail(line_number, fmt::format("{} = {}: expected a finite number", kDeviationHeader, deviation_um));
    }
    if (!trace.x.empty() && !(x > previous_x)) {
      fail(line_number, fmt::format("{} = {} after {} on line {}: expected strictly increasing abscissae", x_name, x,
                                    previous_x, trace.line.back()));
    }
    previous_x = x;
    trace.x.push_back(trace.abscissa == MeasuredProfile::Abscissa::kProfileAngle ? units::DegToRad(x) : x);
    trace.deviation.push_back(units::UmToMm(deviation_um));
    trace.line.push_back(line_number);
  }
  if (!have_header) fail(std::max(line_number, 1), fmt::format("end of the text without a header: expected {}", ExpectedHeader()));
  if (trace.x.size() < 2) {
    fail(line_number, fmt::format("end of the text after {} data row(s): expected at least 2", trace.x.size()));
  }
  return trace;
}

ProfileDeviation ProfileDeviation::Random(const RandomProfileDeviation& random, const CycloidProfile& profile) {
  const int teeth = profile.pair().tooth_count;
  random.Validate(teeth);
  if (random.zone == 0.0) return {};
  const int n = random.elements;
  const double phi = profile.phi_max();
  auto table = std::make_shared<Table>();
  table->per_tooth_space = true;
  table->knots.resize(static_cast<std::size_t>(n));
  if (random.spacing == ProfileElementSpacing::kParameter) {
    for (int e = 0; e < n; ++e) table->knots[static_cast<std::size_t>(e)] = -phi + 2.0 * phi * (e + 0.5) / n;
  } else {
    const ProfileArcLength arc(profile);
    const double length = arc.end() - arc.begin();
    for (int e = 0; e < n; ++e) {
      table->knots[static_cast<std::size_t>(e)] = arc.ParameterAt(arc.begin() + length * (e + 0.5) / n);
    }
  }
  table->values.resize(static_cast<std::size_t>(n) * static_cast<std::size_t>(teeth));
  for (int k = 0; k < teeth; ++k) {
    for (int e = 0; e < n; ++e) {
      table->values[static_cast<std::size_t>(k) * static_cast<std::size_t>(n) + static_cast<std::size_t>(e)] =
          DrawElement(random, k, e);
    }
  }
  ProfileDeviation result;
  result.terms_.push_back(std::move(table));
  result.tooth_count_ = teeth;
  return result;
}

ProfileDeviation ProfileDeviation::Measured(const MeasuredProfile& trace, const CycloidProfile& profile) {
  const std::size_t rows = trace.x.size();
  if (rows < 2 || trace.deviation.size() != rows || trace.line.size() != rows) {
    throw std::invalid_argument(fmt::format(
        "{}: {} abscissae, {} deviations and {} line numbers: expected at least 2 rows, each with all three",
        trace.source, rows, trace.deviation.size(), trace.line.size()));
  }
  const bool angle = trace.abscissa == MeasuredProfile::Abscissa::kProfileAngle;
  const std::string_view x_name = angle ? kAngleHeader : kArcHeader;
  const double phi = profile.phi_max();
  auto table = std::make_shared<Table>();
  table->knots.reserve(rows);
  table->values = trace.deviation;
  std::unique_ptr<ProfileArcLength> arc;
  if (!angle) arc = std::make_unique<ProfileArcLength>(profile);
  for (std::size_t i = 0; i < rows; ++i) {
    const double x = trace.x[i];
    const int line = trace.line[i];
    if (!std::isfinite(x) || !std::isfinite(trace.deviation[i])) {
      throw std::invalid_argument(fmt::format("{}: line {}: expected finite values", trace.source, line));
    }
    double u = 0.0;
    if (angle) {
      if (std::abs(x) > phi * (1.0 + kEndTolerance)) {
        throw std::invalid_argument(fmt::format(
            "{}: line {}: {} = {} is off the flank: expected within [{:.6f}, {:.6f}] deg (the tooth space, u = "
            "+-phi_max)",
            trace.source, line, x_name, units::RadToDeg(x), -units::RadToDeg(phi), units::RadToDeg(phi)));
      }
      u = x;
    } else {
      const double band = kEndTolerance * 0.5 * (arc->end() - arc->begin());
      if (x > arc->end() + band || x < arc->begin() - band) {
        throw std::invalid_argument(fmt::format(
            "{}: line {}: {} = {} is off the flank: expected within [{:.6f}, {:.6f}] mm (the arc length from the root "
            "centre to the ends of the tooth space, u = +-phi_max)",
            trace.source, line, x_name, x, arc->begin(), arc->end()));
      }
      // Within the rounding band beyond an end: continued from the end at the end's speed.
      if (x > arc->end()) {
        u = phi + (x - arc->end()) / arc->Speed(phi);
      } else if (x < arc->begin()) {
        u = -phi + (x - arc->begin()) / arc->Speed(-phi);
      } else {
        u = arc->ParameterAt(x);
      }
    }
    if (!table->knots.empty() && !(u > table->knots.back())) {
      throw std::invalid_argument(fmt::format(
          "{}: line {}: {} = {} does not come after the line before on the profile: expected strictly increasing "
          "abscissae, points far enough apart to be told apart",
          trace.source, line, x_name, angle ? units::RadToDeg(x) : x));
    }
    table->knots.push_back(u);
  }
  if (std::all_of(table->values.begin(), table->values.end(), [](double v) { return v == 0.0; })) return {};
  ProfileDeviation result;
  result.terms_.push_back(std::move(table));
  result.tooth_count_ = profile.pair().tooth_count;
  return result;
}

ProfileDeviation ProfileDeviation::Sum(const ProfileDeviation& a, const ProfileDeviation& b) {
  if (a.IsZero()) return b;
  if (b.IsZero()) return a;
  if (a.tooth_count_ != b.tooth_count_) {
    throw std::invalid_argument(fmt::format(
        "profile deviations built for {} and {} tooth spaces: expected both for the same profile", a.tooth_count_,
        b.tooth_count_));
  }
  ProfileDeviation result = a;
  result.terms_.insert(result.terms_.end(), b.terms_.begin(), b.terms_.end());
  return result;
}

double ProfileDeviation::Interpolate(const Table& table, int row, double u) {
  const std::vector<double>& knots = table.knots;
  const std::size_t n = knots.size();
  const double* v = table.values.data() + static_cast<std::size_t>(row) * n;
  if (std::isnan(u)) return u;
  if (u <= knots.front()) return v[0];
  if (u >= knots.back()) return v[n - 1];
  const std::size_t i = static_cast<std::size_t>(std::upper_bound(knots.begin(), knots.end(), u) - knots.begin()) - 1;
  const double t = (u - knots[i]) / (knots[i + 1] - knots[i]);
  return v[i] + t * (v[i + 1] - v[i]);
}

double ProfileDeviation::At(int tooth_space, double u) const {
  double sum = 0.0;
  for (const auto& term : terms_) {
    int row = 0;
    if (term->per_tooth_space) {
      row = tooth_space % tooth_count_;
      if (row < 0) row += tooth_count_;
    }
    sum += Interpolate(*term, row, u);
  }
  return sum;
}

void ProfileDeviation::NodesIn(double lo, double hi, std::vector<double>* nodes) const {
  const std::size_t first = nodes->size();
  for (const auto& term : terms_) {
    const auto begin = std::upper_bound(term->knots.begin(), term->knots.end(), lo);
    const auto end = std::lower_bound(begin, term->knots.end(), hi);
    nodes->insert(nodes->end(), begin, end);
  }
  if (terms_.size() > 1) {
    const auto from = nodes->begin() + static_cast<std::ptrdiff_t>(first);
    std::sort(from, nodes->end());
    nodes->erase(std::unique(from, nodes->end()), nodes->end());
  }
}

double ProfileDeviation::MaxAbs() const {
  double bound = 0.0;
  for (const auto& term : terms_) {
    double largest = 0.0;
    for (const double v : term->values) largest = std::max(largest, std::abs(v));
    bound += largest;
  }
  return bound;
}

}  // namespace ltca::geometry

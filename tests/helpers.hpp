#pragma once
// The helpers every layer's tests share (no ltca library needed): the decks of cases/, reading a
// file, the message of an invalid_argument, sample moments. tests/pairs.hpp adds the papers' pairs
// (geometry) and tests/problems.hpp their load cases (contact and solvers).
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace ltca::test {

/// The largest magnitude of a vector's entries (0 for an empty one).
inline double MaxAbs(const std::vector<double>& v) {
  double m = 0.0;
  for (const double x : v) m = std::max(m, std::abs(x));
  return m;
}

/// The largest entry-wise difference of two vectors; infinite when their sizes differ.
inline double MaxDifference(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return std::numeric_limits<double>::infinity();
  double m = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

/// The path of a deck in cases/ (LTCA_CASES_DIR, a compile definition of every test suite).
inline std::string Case(const std::string& rel) { return std::string(LTCA_CASES_DIR) + "/" + rel; }

/// The whole file, byte for byte ("" when it cannot be read).
inline std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The message of the std::invalid_argument that f() throws; "" when it throws none.
template <class F>
std::string InvalidArgumentMessage(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

/// tests/app/check_svg.py --file: the SVG parsed by an XML parser, its panels and series counted;
/// 0 when it has them.
inline int CheckSvg(const std::filesystem::path& svg, int panels, int series) {
  const std::string script = std::string(LTCA_CASES_DIR) + "/../tests/app/check_svg.py";
  return std::system(("python3 \"" + script + "\" --file \"" + svg.string() + "\" " + std::to_string(panels) + " " +
                      std::to_string(series))
                         .c_str());
}

/// Mean and variance (1/n normalisation: the samples here are large).
struct Moments {
  double mean = 0.0;
  double variance = 0.0;
};
inline Moments MomentsOf(const std::vector<double>& x) {
  Moments m;
  for (const double v : x) m.mean += v;
  m.mean /= static_cast<double>(x.size());
  for (const double v : x) m.variance += (v - m.mean) * (v - m.mean);
  m.variance /= static_cast<double>(x.size());
  return m;
}

}  // namespace ltca::test

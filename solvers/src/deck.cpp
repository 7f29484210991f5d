#include "ltca/solvers/deck.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <toml.hpp>

#include "ltca/contact/mesh_state.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::solvers {
namespace {

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
  p.Validate();
  return p;
}

geometry::Modification ReadModification(const Section& s, const geometry::PairParameters& pair) {
  geometry::Modification m;
  m.pin_radius = s.Real("pin_radius_mm", 0.0, "isometric modification dR_rp in mm");
  m.pin_circle_radius = s.Real("pin_circle_radius_mm", 0.0, "offset modification dR_p in mm");
  m.rotation = units::DegToRad(s.Real("rotation_deg", 0.0, "angle-rotation modification in deg"));
  m.Validate(pair);
  return m;
}

geometry::ManufacturingErrors ReadErrors(const Section& s) {
  geometry::ManufacturingErrors e;
  e.pin_circle_deviation = s.Real("pin_circle_deviation_mm", 0.0, "pin-circle deviation delta_Rp of Liu eq. 5 in mm");
  e.pin_circle_reading = geometry::ParsePinCircleReading(
      s.String("pin_circle_reading", "radius", "how eq. 5 applies delta_Rp: radius | diameter"));
  e.profile_layer = s.Real("cycloid_profile_layer_mm", 0.0, "uniform layer on the cycloid profile in mm");
  e.cumulative_pitch_deviation = s.RealList("cumulative_pitch_deviation_mm", "one cumulative pitch deviation per pin in mm");
  return e;
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
  MakeSolver(o.name);  // rejects an unknown name, listing the valid ones
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

}  // namespace

void LoadCase::Validate() const {
  if (!std::isfinite(torque) || torque < 0.0) {
    throw std::invalid_argument(fmt::format(
        "[load] torque_nm = {}: expected a finite torque >= 0 N*m (the loaded flank is fixed by "
        "the conventions in docs/conventions.md)",
        units::NmmToNm(torque)));
  }
}

void Sweep::Validate() const {
  if (positions < 1) {
    throw std::invalid_argument(
        fmt::format("[sweep] positions = {}: expected an integer >= 1", positions));
  }
  if (!std::isfinite(crank_start) || !std::isfinite(crank_end)) {
    throw std::invalid_argument("[sweep] crank_start_deg / crank_end_deg: expected finite angles");
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

Deck ParseDeck(std::string_view toml_text, const std::string& name) {
  Deck deck;
  deck.name = name;
  try {
    std::istringstream stream{std::string(toml_text)};
    const toml::value root_value = toml::parse(stream, name);
    const toml::table& root = root_value.as_table();
    const std::vector<std::string> sections = {"case", "pair",     "modification", "errors", "contact",
                                               "geometry", "material", "load", "sweep",  "solver"};
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
    deck.modification = ReadModification(
        Section(Find(root, "modification"), "modification",
                {"pin_radius_mm", "pin_circle_radius_mm", "rotation_deg"}),
        deck.pair);
    deck.errors = ReadErrors(Section(Find(root, "errors"), "errors",
                                     {"pin_circle_deviation_mm", "pin_circle_reading",
                                      "cycloid_profile_layer_mm", "cumulative_pitch_deviation_mm"}));
    deck.errors.Validate(deck.pair.pin_count);
    deck.contact = ReadContact(Section(Find(root, "contact"), "contact",
                                       {"law", "rho_convention", "stiffness_n_per_mm2",
                                        "log_radius_cap_mm"}));
    deck.geometry = ReadGeometry(Section(Find(root, "geometry"), "geometry",
                                         {"geometry_mode", "profile_elements", "width_slices"}));
    deck.solver = ReadSolver(Section(Find(root, "solver"), "solver",
                                     {"name", "kinematics", "torque_tolerance", "max_iterations", "preset", "nlopt_algorithm"}));
    const Section material(Find(root, "material"), "material",
                           {"young_modulus_mpa", "poisson_ratio", "pin_young_modulus_mpa",
                            "pin_poisson_ratio"});
    if (material.Present()) deck.material = ReadMaterial(material);
    const Section load(Find(root, "load"), "load", {"torque_nm"});
    if (load.Present()) deck.load = ReadLoad(load);
    deck.sweep = ReadSweep(
        Section(Find(root, "sweep"), "sweep", {"crank_start_deg", "crank_end_deg", "positions"}),
        deck.pair);
    // The geometry must be realisable: this rejects undercut (looped) profiles, also when the
    // profile layer of [errors] is what makes them loop.
    const contact::MeshModel model(deck.pair, deck.modification, deck.errors);  // analytic: cheap to check
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("deck '{}': {}", name, e.what()));
  } catch (const std::exception& e) {  // TOML syntax errors and the like
    throw std::invalid_argument(fmt::format("deck '{}': {}", name, e.what()));
  }
  return deck;
}

Deck LoadDeck(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw std::invalid_argument(fmt::format("deck '{}': cannot open the file", path.string()));
  }
  std::ostringstream text;
  text << in.rdbuf();
  return ParseDeck(text.str(), path.string());
}

Deck DefaultDeck() { return ParseDeck(DefaultDeckText(), "built-in default (Liu 2021 Table 1)"); }

}  // namespace ltca::solvers

#pragma once
// The deck's keys, each described once: section, name, unit, type, default, what it is,
// per pin or not, whether [second_disc] may give its own, whether [tolerances] may vary it, the
// limit it is held to, and, for the numbers of [modification] and [errors], where the value goes.
// The deck reader, the second disc's split, the tolerance study's Apply, the key reference of
// docs/decks.md and the fuzz dictionary (`ltca keys`) are driven by this table. Data only: no TOML.
#include <string>
#include <string_view>
#include <vector>

#include "ltca/geometry/errors.hpp"
#include "ltca/geometry/pair.hpp"

namespace ltca::contact {
struct BearingSettings;
struct ContactSettings;
struct Cranks;
struct Material;
struct OutputPins;
struct PinSeat;
struct PinSupport;
}  // namespace ltca::contact
namespace ltca::geometry {
struct GeometrySettings;
}  // namespace ltca::geometry
namespace ltca::solvers {
struct SolverOptions;
}  // namespace ltca::solvers

namespace ltca::analysis {

struct Sweep;
struct StiffnessSettings;
struct OperationSettings;
struct FrictionSettings;
struct OptimiseSettings;

/// The parts of one disc a key of [modification] or [errors] writes to (a second disc has its own).
struct DiscParts {
  geometry::Modification* modification;
  geometry::ManufacturingErrors* errors;
  geometry::AssemblyErrors* assembly;
};

/// The settings of one deck the numbers of the other sections write to ([pair], [contact],
/// [geometry], [material], [pins], [output], [bearing], [sweep], [solver], [stiffness], [operation],
/// [friction], [optimise]);
/// nullptr: that section is not being read.
struct SettingsParts {
  geometry::PairParameters* pair = nullptr;
  contact::ContactSettings* contact = nullptr;
  geometry::GeometrySettings* geometry = nullptr;
  contact::Material* material = nullptr;
  contact::PinSupport* pin_support = nullptr;  ///< [pins] held at their ends (span_mm, face_offset_mm)
  contact::PinSeat* pin_seat = nullptr;        ///< [pins] seated in housing grooves
  /// [output]: the output pins or the crankshafts (one of the two, by its kind); its keys common
  /// to both kinds fill the one given.
  contact::OutputPins* output_pins = nullptr;
  contact::Cranks* cranks = nullptr;
  contact::BearingSettings* bearing = nullptr;
  Sweep* sweep = nullptr;
  solvers::SolverOptions* solver = nullptr;
  StiffnessSettings* stiffness = nullptr;
  OperationSettings* operation = nullptr;
  FrictionSettings* friction = nullptr;
  OptimiseSettings* optimise = nullptr;
};

/// The field a key of SettingsParts fills: a number (internal unit) or an integer, by the key's type.
struct SettingField {
  SettingField(double* r) : real(r) {}  // NOLINT(google-explicit-constructor): the binders return a member's address
  SettingField(int* i) : integer(i) {}  // NOLINT(google-explicit-constructor)
  double* real = nullptr;
  int* integer = nullptr;
};

struct DeckKey {
  enum class Type { kReal, kRealList, kInteger, kUnsigned, kText, kBool, kTable };
  /// The rule that tells a modification or an error from an absolute value (docs/decks.md, Limits):
  /// the change it makes to the geometry is at most DeckKey::kMaxDeviationFraction of the pin radius.
  enum class Limit {
    kNone,
    kLength,    ///< the value itself (mm once converted)
    kRotation,  ///< an angle that turns the profile along the pin circle: R_p x angle
    kTilt,      ///< a tilt of the axis: the shift over the face width, B tan(angle)
  };
  static constexpr double kMaxDeviationFraction = 0.05;

  const char* section;
  const char* name;
  Type type;
  const char* unit;           ///< the unit its name ends with ("mm", "um", "deg", ...), "" none
  const char* meaning;        ///< what it is: messages name it, docs/decks.md lists it
  const char* default_value;  ///< as a deck writes it; "" required or absent by default
  const char* choices = "";   ///< a text key's values, "a | b"
  bool per_pin = false;       ///< one value per pin
  bool disc = false;          ///< a key of one disc: [second_disc] may give its own (else the pin ring's)
  int tolerance_stream = -1;  ///< >= 0: [tolerances] may vary it; its random stream (order fixed forever)
  Limit limit = Limit::kNone;
  /// Where a number of [modification] or [errors] goes (nullptr: read by its section's reader).
  double* (*real)(const DiscParts&) = nullptr;
  std::vector<double>* (*list)(const DiscParts&) = nullptr;
  /// Where a number of the other sections goes (nullptr: read by its section's reader). A key not
  /// given keeps the field's value: the struct's default, which is default_value in the internal unit.
  SettingField (*setting)(const SettingsParts&) = nullptr;
  /// A key the deck must give when its section is present (a reader names it as missing).
  bool required = false;

  /// The deck's unit to the internal one (mm, rad, N*mm, rad/s, MPa*s, 1/MPa): um -> mm, deg -> rad,
  /// N*m -> N*mm, rpm -> rad/s, Pa*s -> MPa*s, 1/GPa -> 1/MPa (geometry/units.hpp); others unchanged.
  double ToInternal(double value) const;
  double FromInternal(double value) const;
  /// Its name in [tolerances]: keys of [modification], [output] and [bearing] carry their section
  /// as a prefix ("modification_pin_radius_mm", "output_hole_radius_mm").
  std::string ToleranceName() const;
  /// The change the value (internal units) makes to the pair's geometry, mm (Limit).
  double Reach(double internal, const geometry::PairParameters& pair) const;
};

/// The rule of DeckKey::Limit (docs/decks.md, Limits): a modification or a manufacturing error is a
/// small change of the geometry, its reach (mm, DeckKey::Reach) at most
/// DeckKey::kMaxDeviationFraction of [pair] pin_radius_mm. Throws std::invalid_argument
/// "[section] key = value: looks like an absolute value; ..." otherwise; `shown` is the value as the
/// deck gives it when that is not the reach in mm ("" : the reach). NaN and infinities pass (the
/// part's own Validate() names them).
void RequireSmallDeviation(double reach, std::string_view section, std::string_view key,
                           const geometry::PairParameters& pair, const std::string& shown = "");
/// The rule on every number of the table's section `table_section` ([modification] or [errors])
/// that has a Limit, as the disc's parts hold it (internal units), named as a key of [section]
/// (a second disc's are keys of [second_disc]); a list's values as key[j].
void RequireSmallDeviations(std::string_view section, std::string_view table_section, const DiscParts& parts,
                            const geometry::PairParameters& pair);

/// Every key of every section, in the order of docs/decks.md.
const std::vector<DeckKey>& DeckKeys();
/// The sections, in that order.
std::vector<std::string> DeckSections();
/// The names of one section's keys, in table order.
std::vector<std::string> SectionKeys(std::string_view section);
/// The key, or nullptr.
const DeckKey* FindKey(std::string_view section, std::string_view name);
/// The keys [tolerances] may vary, in the order of their random streams.
std::vector<const DeckKey*> ToleranceVariableKeys();
/// The key [tolerances] names (ToleranceName()), or nullptr.
const DeckKey* FindToleranceKey(std::string_view tolerance_name);
const char* ToString(DeckKey::Type type);

}  // namespace ltca::analysis

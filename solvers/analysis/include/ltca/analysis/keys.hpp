#pragma once
// The deck's keys, each described once: section, name, unit, type, default, what it is,
// per pin or not, whether [second_disc] may give its own, whether [tolerances] may vary it, the
// limit it is held to, its choices, and where the value goes (a disc's part for the numbers of
// [modification] and [errors], a field of the deck's settings for every other key a field takes).
// The deck reader, the second disc's split, the tolerance study's Apply, the key reference of
// docs/decks.md and the fuzz dictionary (`ltca keys`) are driven by this table. Data only: no TOML.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "ltca/geometry/errors.hpp"
#include "ltca/geometry/pair.hpp"

namespace ltca::contact {
struct BearingSettings;
struct ContactSettings;
struct Cranks;
struct DiscBodySettings;
struct Material;
struct OutputPins;
struct PinSeat;
struct PinSupport;
}  // namespace ltca::contact
namespace ltca::geometry {
struct GeometrySettings;
}  // namespace ltca::geometry
namespace ltca::contact {
enum class ContactKinematics;
}  // namespace ltca::contact
namespace ltca::solvers {
struct SolverOptions;
struct ReducerSettings;
}  // namespace ltca::solvers

namespace ltca::analysis {

struct CaseInfo;
struct LoadCase;
struct SecondDisc;
struct Sweep;
struct StiffnessSettings;
struct OperationSettings;
struct FrictionSettings;
struct OptimiseSettings;
struct ToleranceSettings;
struct AllowablesSettings;
struct InspectionSettings;

/// The parts of one disc a key of [modification] or [errors] writes to (a second disc has its own).
struct DiscParts {
  geometry::Modification* modification;
  geometry::ManufacturingErrors* errors;
  geometry::AssemblyErrors* assembly;
};

/// The settings of one deck the keys of a section write to: every key of [case], [pair], [contact],
/// [geometry], [material], [pins], [output], [bearing], [load], [sweep], [solver], [stiffness],
/// [second_disc] (its own key), [tolerances], [operation], [friction], [optimise], [inspection] and [allowables] but the tables
/// and lists their readers take apart, and the keys of [modification] and [errors] that are not
/// real numbers (those go by DeckKey::real and DeckKey::list);
/// nullptr: that part is not being read (the binder gives no field).
struct SettingsParts {
  CaseInfo* info = nullptr;
  geometry::PairParameters* pair = nullptr;
  geometry::ManufacturingErrors* errors = nullptr;  ///< [errors] (or a [second_disc]'s): its texts and integers
  geometry::AssemblyErrors* assembly = nullptr;     ///< [errors] misalignment_pivot
  contact::ContactSettings* contact = nullptr;
  geometry::GeometrySettings* geometry = nullptr;
  contact::Material* material = nullptr;
  contact::PinSupport* pin_support = nullptr;  ///< [pins] held at their ends (span_mm, face_offset_mm)
  contact::PinSeat* pin_seat = nullptr;        ///< [pins] seated in housing grooves
  contact::DiscBodySettings* disc_body = nullptr;  ///< [disc] the disc body, rigid or elastic
  solvers::ReducerSettings* reducer = nullptr;    ///< [output] kind and [bearing] kind
  /// [output]: the output pins or the crankshafts (one of the two, by its kind); its keys common
  /// to both kinds fill the one given.
  contact::OutputPins* output_pins = nullptr;
  contact::Cranks* cranks = nullptr;
  contact::BearingSettings* bearing = nullptr;
  LoadCase* load = nullptr;
  Sweep* sweep = nullptr;
  solvers::SolverOptions* solver = nullptr;
  contact::ContactKinematics* kinematics = nullptr;  ///< [solver] kinematics (the stage design's)
  std::string* preset = nullptr;                     ///< [solver] preset, applied before the section's other keys
  StiffnessSettings* stiffness = nullptr;
  SecondDisc* second_disc = nullptr;
  ToleranceSettings* tolerances = nullptr;
  OperationSettings* operation = nullptr;
  FrictionSettings* friction = nullptr;
  OptimiseSettings* optimise = nullptr;
  InspectionSettings* inspection = nullptr;  ///< [inspection]
  AllowablesSettings* allowables = nullptr;  ///< [allowables]
};

/// The field a key of SettingsParts fills, one kind by the key's type: a number (internal unit),
/// an optional number (absent unless given), an integer (int: the TOML integer must fit an int;
/// std::int64_t for a count kept in 64 bits, read within the same int range), an integer >= 0
/// (std::uint64_t), true | false, a text, or a choice (a text key with DeckKey::choices): the
/// choice's name into a std::string, or its position among the choices into an enum (Choice()).
/// None: the key's part is not being read.
struct SettingField {
  SettingField() = default;
  SettingField(double* r) : real(r) {}  // NOLINT(google-explicit-constructor): the binders return a member's address
  SettingField(std::optional<double>* r) : optional_real(r) {}  // NOLINT(google-explicit-constructor)
  SettingField(int* i) : integer(i) {}  // NOLINT(google-explicit-constructor)
  SettingField(std::int64_t* i) : int64(i) {}  // NOLINT(google-explicit-constructor)
  SettingField(std::uint64_t* u) : uint64(u) {}  // NOLINT(google-explicit-constructor)
  SettingField(bool* b) : boolean(b) {}  // NOLINT(google-explicit-constructor)
  SettingField(std::string* t) : text(t) {}  // NOLINT(google-explicit-constructor)

  /// An enum field that takes the k-th of DeckKey::choices as kValues[k] (the values in the order
  /// of the choices).
  template <auto... kValues, class E>
  static SettingField Choice(E* field) {
    static_assert(std::is_enum_v<E> && (std::is_same_v<decltype(kValues), E> && ...));
    SettingField f;
    f.choice = field;
    f.choice_count = sizeof...(kValues);
    f.choose = [](void* to, std::size_t k) {
      static constexpr E kAll[] = {kValues...};
      *static_cast<E*>(to) = kAll[k];
    };
    f.chosen = [](const void* from) {
      static constexpr E kAll[] = {kValues...};
      std::size_t k = 0;
      while (k < sizeof...(kValues) && kAll[k] != *static_cast<const E*>(from)) ++k;
      return k;
    };
    return f;
  }
  bool empty() const {
    return real == nullptr && optional_real == nullptr && integer == nullptr && int64 == nullptr && uint64 == nullptr &&
           boolean == nullptr && text == nullptr && choice == nullptr;
  }

  double* real = nullptr;
  std::optional<double>* optional_real = nullptr;
  int* integer = nullptr;
  std::int64_t* int64 = nullptr;
  std::uint64_t* uint64 = nullptr;
  bool* boolean = nullptr;
  std::string* text = nullptr;
  void* choice = nullptr;                          ///< the enum field of Choice()
  std::size_t choice_count = 0;                    ///< its values, one per choice
  void (*choose)(void* field, std::size_t k) = nullptr;  ///< sets the k-th value
  std::size_t (*chosen)(const void* field) = nullptr;    ///< which value it holds (choice_count: none)
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
  /// One value per hole of a disc ([output] count: output pins or crank holes); [tolerances] draws
  /// it per hole and, with [second_disc], per disc.
  bool per_hole = false;
  bool disc = false;          ///< a key of one disc: [second_disc] may give its own (else the pin ring's)
  int tolerance_stream = -1;  ///< >= 0: [tolerances] may vary it; its random stream (order fixed forever)
  Limit limit = Limit::kNone;
  /// Where a real number (or list) of [modification] or [errors] goes, in a disc's parts.
  double* (*real)(const DiscParts&) = nullptr;
  std::vector<double>* (*list)(const DiscParts&) = nullptr;
  /// Where a key of the other sections (and a text or integer of [modification] and [errors]) goes
  /// (nullptr: a table or list its section's reader takes apart). A key not given keeps the field's
  /// value: the struct's default, which is default_value in the internal unit.
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

/// The choices of a text key, in the table's order ("a | b" -> {"a", "b"}; none: any text).
std::vector<std::string> Choices(const DeckKey& key);
/// The one message of a text key given a value that is not one of its choices:
/// `[section] key = "value": expected "a", "b" or "c"` (section: where the deck gives it).
std::string ChoiceMessage(std::string_view section, const DeckKey& key, std::string_view value);

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

#include "ltca/app/deck.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <tuple>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <toml.hpp>

#include "ltca/analysis/keys.hpp"
#include "ltca/contact/mesh_state.hpp"
#include "ltca/geometry/kinematics.hpp"
#include "ltca/geometry/profile.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/registry.hpp"
#include "ltca/solvers/reducer.hpp"

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

/// One override: --set "section.key=value", with its value read as TOML, or --unset
/// "-section[.key]" (remove: `key` empty for the whole section).
struct Override {
  std::string text;  ///< as given, for messages
  std::string section;
  std::string key;
  toml::value value;
  bool remove = false;
};

/// An --unset, "-section" or "-section.key" (the CLI puts the '-' before the option's value).
Override ParseRemoval(const std::string& text) {
  const std::string path = Trim(std::string_view(text).substr(1));
  const auto bad = [&](const std::string& why) {
    return std::invalid_argument(fmt::format("--unset '{}': {}; expected section or section.key, e.g. --unset friction "
                                             "or --unset load.torque_nm", path, why));
  };
  Override o;
  o.text = text;
  o.remove = true;
  const auto dot = path.find('.');
  o.section = Trim(std::string_view(path).substr(0, dot));
  if (dot != std::string::npos) o.key = Trim(std::string_view(path).substr(dot + 1));
  if (o.section.empty() || (dot != std::string::npos && o.key.empty()) || o.key.find('.') != std::string::npos ||
      path.find('=') != std::string::npos) {
    throw bad("not one section or one section and one key");
  }
  return o;
}

Override ParseOverride(const std::string& text) {
  if (!text.empty() && text.front() == '-' && text.find('=') == std::string::npos) return ParseRemoval(text);
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
    if (o.remove) {
      // Removing what the deck does not have is a typing error to show, not a silent no-op.
      const auto section = table.find(o.section);
      if (section == table.end()) {
        throw std::invalid_argument(fmt::format("--unset '{}': the deck has no [{}]", o.text.substr(1), o.section));
      }
      if (o.key.empty()) {
        table.erase(section);
        continue;
      }
      if (!section->second.is_table()) {
        throw std::invalid_argument(fmt::format("--unset '{}': [{}] is not one table (a list of tables or a key); "
                                                "expected --unset {} for all of it", o.text.substr(1), o.section, o.section));
      }
      if (section->second.as_table().erase(o.key) == 0) {
        throw std::invalid_argument(fmt::format("--unset '{}': [{}] has no key '{}'", o.text.substr(1), o.section, o.key));
      }
      continue;
    }
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

/// One section of the deck: typed access to its keys, and a final check that every key present
/// was one the program knows.
class Section {
 public:
  const std::string& name() const { return name_; }
  /// The keys of the section in the table of deck keys (analysis::SectionKeys).
  Section(const toml::value* value, const std::string& name) : Section(value, name, analysis::SectionKeys(name)) {}
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
  /// Whether the deck gives the key; a key the section does not know (not in the table of deck
  /// keys) is a bug of the reader: std::logic_error.
  bool Has(const std::string& key) const {
    Known(key);
    return Table().count(key) != 0;
  }

  double Real(const std::string& key) const {
    const toml::value& v = Get(key);
    if (v.is_integer()) return static_cast<double>(v.as_integer());
    if (v.is_floating()) return v.as_floating();
    throw std::invalid_argument(
        fmt::format("[{}] {} = {}: expected a number ({})", name_, key, toml::format(v), Meaning(key)));
  }
  double Real(const std::string& key, double fallback) const { return Has(key) ? Real(key) : fallback; }
  std::vector<double> RealList(const std::string& key) const {
    if (!Has(key)) return {};
    const toml::value& v = Get(key);
    if (!v.is_array()) {
      throw std::invalid_argument(fmt::format("[{}] {}: expected an array of numbers ({})", name_, key, Meaning(key)));
    }
    std::vector<double> out;
    for (const toml::value& item : v.as_array()) {
      if (item.is_integer()) out.push_back(static_cast<double>(item.as_integer()));
      else if (item.is_floating()) out.push_back(item.as_floating());
      else throw std::invalid_argument(fmt::format("[{}] {}: expected numbers only ({})", name_, key, Meaning(key)));
    }
    return out;
  }
  int Integer(const std::string& key) const {
    const toml::value& v = Get(key);
    if (!v.is_integer() || v.as_integer() < std::numeric_limits<int>::min() ||
        v.as_integer() > std::numeric_limits<int>::max()) {
      throw std::invalid_argument(fmt::format("[{}] {} = {}: expected an integer ({})", name_,
                                              key, toml::format(v), Meaning(key)));
    }
    return static_cast<int>(v.as_integer());
  }
  /// An integer >= 0 (up to the TOML limit 2^63 - 1).
  std::uint64_t Unsigned(const std::string& key) const {
    const toml::value& v = Get(key);
    if (!v.is_integer() || v.as_integer() < 0) {
      throw std::invalid_argument(fmt::format("[{}] {} = {}: expected an integer >= 0 ({})", name_, key,
                                              toml::format(v), Meaning(key)));
    }
    return static_cast<std::uint64_t>(v.as_integer());
  }
  bool Bool(const std::string& key) const {
    const toml::value& v = Get(key);
    if (!v.is_boolean()) {
      throw std::invalid_argument(fmt::format("[{}] {} = {}: expected true or false ({})", name_, key, toml::format(v), Meaning(key)));
    }
    return v.as_boolean();
  }
  std::string String(const std::string& key) const {
    const toml::value& v = Get(key);
    if (!v.is_string()) {
      throw std::invalid_argument(fmt::format("[{}] {} = {}: expected a string ({})", name_, key,
                                              toml::format(v), Meaning(key)));
    }
    const std::string& text = v.as_string().str;
    // Printed to terminals and written into SVG/XML, neither of which takes control characters
    // (an ESC would drive the terminal, a NUL ends a C string).
    for (std::size_t i = 0; i < text.size(); ++i) {
      const auto c = static_cast<unsigned char>(text[i]);
      if (c < 0x20 || c == 0x7f) {
        throw std::invalid_argument(fmt::format(
            "[{}] {}: a control character (U+{:04X}) at byte {}: expected printable text ({})", name_, key, c, i + 1,
            Meaning(key)));
      }
    }
    return text;
  }

  /// What the key is (analysis::DeckKeys()): [second_disc] takes the disc keys of [modification] and [errors].
  const char* Meaning(const std::string& key) const {
    // An entry of an array of tables is named "section #i": its keys are the section's.
    const std::string own = name_.substr(0, name_.find(" #"));
    for (const char* section : {own.c_str(), "modification", "errors"}) {
      if (const analysis::DeckKey* k = analysis::FindKey(section, key)) return k->meaning;
      if (name_ != "second_disc") break;
    }
    throw std::logic_error(fmt::format("[{}] {}: not in the table of deck keys (analysis/keys.cpp)", name_, key));
  }

 private:
  const toml::table& Table() const {
    static const toml::table kEmpty;
    return table_ != nullptr ? *table_ : kEmpty;
  }
  void Known(const std::string& key) const {
    if (std::find(known_.begin(), known_.end(), key) == known_.end()) {
      throw std::logic_error(fmt::format("[{}] {}: read, but not a key of the section in the table of deck keys "
                                         "(analysis/keys.cpp)", name_, key));
    }
  }
  const toml::value& Get(const std::string& key) const {
    Known(key);
    const auto it = Table().find(key);
    if (it == Table().end()) {
      throw std::invalid_argument(
          fmt::format("[{}] missing required key '{}' ({})", name_, key, Meaning(key)));
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

Section RequiredSection(const toml::table& root, const std::string& name) {
  const toml::value* v = Find(root, name);
  if (v == nullptr) throw std::invalid_argument(fmt::format("missing required section [{}]", name));
  return Section(v, name);
}

/// One key into its field (analysis::SettingField), checked for its type; a text key with choices
/// must be one of them (analysis::ChoiceMessage).
void ReadField(const Section& s, const analysis::DeckKey& k, const analysis::SettingField& f) {
  const std::string key = k.name;
  if (f.real != nullptr) *f.real = k.ToInternal(s.Real(key));
  else if (f.optional_real != nullptr) *f.optional_real = k.ToInternal(s.Real(key));
  else if (f.integer != nullptr) *f.integer = s.Integer(key);
  else if (f.int64 != nullptr) *f.int64 = s.Integer(key);
  else if (f.uint64 != nullptr) *f.uint64 = s.Unsigned(key);
  else if (f.boolean != nullptr) *f.boolean = s.Bool(key);
  else {
    const std::string text = s.String(key);
    const std::vector<std::string> choices = analysis::Choices(k);
    const auto it = std::find(choices.begin(), choices.end(), text);
    if (!choices.empty() && it == choices.end()) throw std::invalid_argument(analysis::ChoiceMessage(s.name(), k, text));
    if (f.text != nullptr) *f.text = text;
    else f.choose(f.choice, static_cast<std::size_t>(it - choices.begin()));
  }
}

/// The keys of the section that the table binds to a setting (DeckKey::setting), in table order,
/// into `parts` (numbers in internal units, DeckKey::ToInternal): a key given is checked for its
/// type (and its choices); a required key missing is named; a key not given keeps the field's
/// value (the struct's default, the table's default_value), or takes the value of the key its
/// default_value names (pin_young_modulus_mpa = young_modulus_mpa). A key whose part `parts` does
/// not give is not read. `table_section`: the table's section when it is not the deck's (a
/// [second_disc]'s [errors] keys). `choices_only`: only the keys with choices (a kind whose rules
/// refuse or require the section's other keys before their values are read).
void ReadSettings(const Section& s, const analysis::SettingsParts& parts, std::string_view table_section = {},
                  bool choices_only = false) {
  const std::string_view section = table_section.empty() ? std::string_view(s.name()) : table_section;
  for (const analysis::DeckKey& k : analysis::DeckKeys()) {
    if (section != k.section || k.setting == nullptr || (choices_only && k.choices[0] == '\0')) continue;
    const analysis::SettingField field = k.setting(parts);
    if (field.empty()) continue;  // its part is not being read
    const bool read = s.Has(k.name) || k.required;
    if (read) {
      ReadField(s, k, field);
      continue;
    }
    const analysis::DeckKey* named = analysis::FindKey(k.section, k.default_value);
    if (named == nullptr || named->setting == nullptr) continue;  // keeps the field
    const analysis::SettingField from = named->setting(parts);
    if (field.integer != nullptr) *field.integer = *from.integer;
    else if (field.real != nullptr) *field.real = *from.real;
  }
}

/// Keys a section needs in the form it takes (a bearing's kind, the way pins are held): the first
/// missing one is named as a missing required key.
void RequireKeys(const Section& s, std::initializer_list<const char*> keys) {
  for (const char* key : keys) {
    if (!s.Has(key)) (void)s.Real(key);  // throws "[section] missing required key ..."
  }
}

analysis::CaseInfo ReadCase(const Section& s) {
  analysis::CaseInfo info;
  ReadSettings(s, {.info = &info});
  return info;
}

geometry::PairParameters ReadPair(const Section& s) {
  geometry::PairParameters p;
  ReadSettings(s, {.pair = &p});
  if (p.pin_count > DeckLimits::kMaxPins) {
    throw std::invalid_argument(fmt::format(
        "[pair] pin_count = {}: expected at most {} pins (docs/decks.md, Limits)", p.pin_count,
        DeckLimits::kMaxPins));
  }
  p.Validate();
  return p;
}

/// The numbers of a section of the table (analysis::DeckKeys: [modification] or [errors]) that have a
/// field, read into a disc's parts in internal units; a key not given keeps the part's value.
void ReadNumbers(const Section& s, std::string_view section, const analysis::DiscParts& parts) {
  for (const analysis::DeckKey& k : analysis::DeckKeys()) {
    if (k.section != section) continue;
    if (k.real != nullptr) {
      double* field = k.real(parts);
      *field = k.ToInternal(s.Real(k.name, k.FromInternal(*field)));
    } else if (k.list != nullptr && s.Has(k.name)) {
      std::vector<double>* list = k.list(parts);
      *list = s.RealList(k.name);
      for (double& v : *list) v = k.ToInternal(v);
    }
  }
}

geometry::Modification ReadModification(const Section& s, const geometry::PairParameters& pair) {
  geometry::Modification m;
  const analysis::DiscParts parts{&m, nullptr, nullptr};
  ReadNumbers(s, "modification", parts);
  try {
    m.Validate(pair);
  } catch (const std::invalid_argument& e) {  // name the section the keys were read from ([second_disc])
    std::string message = e.what();
    if (s.name() != "modification" && message.rfind("[modification]", 0) == 0) {
      message.replace(0, std::string("[modification]").size(), "[" + s.name() + "]");
    }
    throw std::invalid_argument(message);
  }
  analysis::RequireSmallDeviations(s.name(), "modification", parts, pair);
  return m;
}

/// The files the deck being read opens beyond itself (its measured traces), for Deck::source.files;
/// set by ReadParsed for the duration of one read on this thread.
thread_local std::vector<std::filesystem::path>* tl_files_read = nullptr;
/// The in-memory files of the deck being read (MemoryFiles; null: none), set by ReadParsed likewise.
thread_local const MemoryFiles* tl_memory_files = nullptr;

/// [errors] profile_measured_csv: the trace, an in-memory file of that name (MemoryFiles) or the
/// file, read from `directory` when the path is relative.
geometry::MeasuredProfile ReadMeasuredProfile(const std::string& value, const std::filesystem::path& directory) {
  const std::string key = fmt::format("[errors] profile_measured_csv = \"{}\"", value);
  if (value.empty()) {
    throw std::invalid_argument(fmt::format("{}: expected the path of a CSV file (relative to the deck's directory)", key));
  }
  if (tl_memory_files != nullptr) {
    if (const auto file = tl_memory_files->find(value); file != tl_memory_files->end()) {
      if (file->second.size() > DeckLimits::kMaxProfileCsvBytes) {
        throw std::invalid_argument(fmt::format(
            "{}: the trace is {} bytes; expected a profile trace of at most {} bytes ({} MiB; docs/decks.md, Limits)", key,
            file->second.size(), DeckLimits::kMaxProfileCsvBytes, DeckLimits::kMaxProfileCsvBytes >> 20));
      }
      return geometry::ParseMeasuredProfile(file->second, key);
    }
  }
  const std::filesystem::path path = std::filesystem::path(value).is_relative() ? directory / value : std::filesystem::path(value);
  const std::string text = ReadBoundedFile(
      path, path.string() == value ? key : fmt::format("{} (read as '{}')", key, path.string()),
      "CSV file of a measured profile (profile_angle_deg or arc_length_mm, deviation_um)",
      DeckLimits::kMaxProfileCsvBytes, "a profile trace");
  if (tl_files_read != nullptr) tl_files_read->push_back(path);
  return geometry::ParseMeasuredProfile(text, key);
}

/// [errors] (or a [second_disc]'s): the manufacturing and the assembly errors of a disc and the pin ring.
void ReadErrors(const Section& s, const geometry::PairParameters& pair, const std::filesystem::path& directory,
                geometry::ManufacturingErrors* errors, geometry::AssemblyErrors* assembly) {
  geometry::ManufacturingErrors& e = *errors;
  geometry::AssemblyErrors& a = *assembly;
  e = {};
  a = {};
  const analysis::DiscParts parts{nullptr, &e, &a};
  ReadNumbers(s, "errors", parts);
  ReadSettings(s, {.errors = &e, .assembly = &a}, "errors");
  e.profile_random.Validate(pair.tooth_count);
  if (s.Has("profile_measured_csv")) {
    e.profile_measured = ReadMeasuredProfile(s.String("profile_measured_csv"), directory);
  }
  e.Validate(pair.pin_count);
  a.Validate();
  analysis::RequireSmallDeviations(s.name(), "errors", parts, pair);
  if (e.profile_measured) {
    for (std::size_t i = 0; i < e.profile_measured->deviation.size(); ++i) {
      const double v = e.profile_measured->deviation[i];
      analysis::RequireSmallDeviation(v, s.name(),
                            fmt::format("profile_measured_csv (line {} of the file, deviation_um)", e.profile_measured->line[i]),
                            pair, fmt::format("{}", units::MmToUm(v)));
    }
  }
}

contact::ContactSettings ReadContact(const Section& s) {
  contact::ContactSettings c;
  ReadSettings(s, {.contact = &c});
  c.Validate();
  return c;
}

geometry::GeometrySettings ReadGeometry(const Section& s) {
  geometry::GeometrySettings g;
  ReadSettings(s, {.geometry = &g});
  g.Validate();
  return g;
}

SolverOptions ReadSolver(const Section& s, contact::ContactKinematics* kinematics) {
  SolverOptions o;
  std::string preset;
  ReadSettings(s, {.solver = &o, .kinematics = kinematics, .preset = &preset});
  if (!preset.empty()) {  // the preset's values, and the section's keys over them
    o = ApplyPreset(SolverOptions{}, preset);
    ReadSettings(s, {.solver = &o});
  }
  o.Validate();
  return o;
}

contact::Material ReadMaterial(const Section& s) {
  contact::Material m;
  ReadSettings(s, {.material = &m});
  m.Validate();
  return m;
}

analysis::LoadCase ReadLoad(const Section& s) {
  analysis::LoadCase load;
  ReadSettings(s, {.load = &load});
  load.Validate();
  return load;
}

/// [[load_spectrum]]: an array of tables, each entry a bin (torque_nm, speed_rpm, time_share, all
/// required); its messages name the entry, counted from 1. The bins are validated together
/// (analysis::ValidateSpectrum: the shares add to 1, not normalised).
std::vector<analysis::LoadBin> ReadLoadSpectrum(const toml::value& v) {
  // A single [load_spectrum] table (or --set load_spectrum.key=...): its keys checked first, so a
  // key that is not one is named as unknown.
  if (v.is_table()) (void)Section(&v, "load_spectrum");
  if (!v.is_array() || v.as_array().empty()) {
    throw std::invalid_argument("[[load_spectrum]]: expected an array of tables, one [[load_spectrum]] entry per bin "
                                "(torque_nm, speed_rpm, time_share)");
  }
  std::vector<analysis::LoadBin> bins;
  const toml::array& entries = v.as_array();
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (!entries[i].is_table()) throw std::invalid_argument(fmt::format("[[load_spectrum]] #{}: expected a table (torque_nm, speed_rpm, time_share)", i + 1));
    const Section s(&entries[i], fmt::format("load_spectrum #{}", i + 1), analysis::SectionKeys("load_spectrum"));
    analysis::LoadBin b;
    b.torque = units::NmToNmm(s.Real("torque_nm"));
    b.input_speed = units::RpmToRadPerS(s.Real("speed_rpm"));
    b.time_share = s.Real("time_share");
    bins.push_back(b);
  }
  analysis::ValidateSpectrum(bins);
  return bins;
}

analysis::Sweep ReadSweep(const Section& s, const geometry::PairParameters& pair) {
  analysis::Sweep sweep;
  const double period_deg = 360.0 / pair.pin_count;
  ReadSettings(s, {.sweep = &sweep});
  // By default one mesh period from the start.
  if (!s.Has("crank_end_deg")) sweep.crank_end = units::DegToRad(units::RadToDeg(sweep.crank_start) + period_deg);
  sweep.Validate(pair.tooth_count);
  return sweep;
}

analysis::StiffnessSettings ReadStiffness(const Section& s) {
  analysis::StiffnessSettings st;
  ReadSettings(s, {.stiffness = &st});
  st.Validate();
  return st;
}


// --- reading [tolerances] ---------------------------------------------------------------------
/// A number of a section's nested value (where: "limits.x.max"); else an error naming it.
double Number(const toml::value& v, const std::string& where, const char* what, const char* section = "tolerances") {
  if (v.is_integer()) return static_cast<double>(v.as_integer());
  if (v.is_floating()) return v.as_floating();
  throw std::invalid_argument(fmt::format("[{}] {} = {}: expected a number ({})", section, where, toml::format(v), what));
}

/// Limits on figures, { figure = max } or { figure = { min = .., max = .. } }: [tolerances] limits
/// and [optimise] constraints. The figures' names are checked by their users.
std::vector<analysis::ToleranceLimit> ReadLimits(const toml::value& v, const char* section, const std::string& key, const char* example) {
  if (!v.is_table()) {
    throw std::invalid_argument(fmt::format("[{}] {} = {}: expected an inline table, e.g. {}", section, key, toml::format(v), example));
  }
  std::vector<analysis::ToleranceLimit> limits;
  for (const auto& [figure, limit] : v.as_table()) {
    analysis::ToleranceLimit l;
    l.figure = figure;
    const std::string where = key + "." + figure;
    if (limit.is_table()) {
      for (const auto& [name, bound] : limit.as_table()) {
        if (name == "min") l.min = Number(bound, where + ".min", "lower limit of the figure", section);
        else if (name == "max") l.max = Number(bound, where + ".max", "upper limit of the figure", section);
        else throw std::invalid_argument(fmt::format("[{}] {}: unknown key '{}'; expected min, max", section, where, name));
      }
    } else {
      l.max = Number(limit, where, "upper limit of the figure, or { min = .., max = .. }", section);
    }
    limits.push_back(l);
  }
  return limits;
}

analysis::ToleranceDistribution ReadDistribution(const std::string& key, bool per_pin, const toml::value& v) {
  const std::string expected =
      "expected an inline table, e.g. { distribution = \"normal\", sigma = 0.002 } or "
      "{ distribution = \"uniform\", tolerance = 0.005 } (docs/tolerance.md)";
  if (!v.is_table()) throw std::invalid_argument(fmt::format("[tolerances] {} = {}: {}", key, toml::format(v), expected));
  analysis::ToleranceDistribution d;
  d.key = key;
  d.per_pin = per_pin;
  const toml::table& t = v.as_table();
  for (const auto& [name, unused] : t) {
    if (name != "distribution" && name != "sigma" && name != "tolerance" && name != "mean") {
      throw std::invalid_argument(fmt::format("[tolerances] {}: unknown key '{}'; expected distribution, sigma, tolerance, mean",
                                              key, name));
    }
  }
  const auto it = t.find("distribution");
  if (it == t.end() || !it->second.is_string()) {
    throw std::invalid_argument(fmt::format("[tolerances] {}: missing distribution = \"normal\" | \"uniform\"; {}", key, expected));
  }
  const std::string kind = it->second.as_string().str;
  if (kind == "normal") d.kind = analysis::ToleranceDistribution::Kind::kNormal;
  else if (kind == "uniform") d.kind = analysis::ToleranceDistribution::Kind::kUniform;
  else throw std::invalid_argument(fmt::format("[tolerances] {}.distribution = \"{}\": expected \"normal\" or \"uniform\"", key, kind));
  const bool has_sigma = t.count("sigma") != 0, has_tolerance = t.count("tolerance") != 0;
  if (d.kind == analysis::ToleranceDistribution::Kind::kNormal) {
    if (has_sigma == has_tolerance) {
      throw std::invalid_argument(fmt::format(
          "[tolerances] {}: a normal distribution takes one of sigma or tolerance (+-tolerance read as 3 sigma), {}", key,
          has_sigma ? "not both" : "none was given"));
    }
    if (has_sigma) d.sigma = Number(t.at("sigma"), key + ".sigma", "standard deviation in the key's unit");
    else {
      d.tolerance = Number(t.at("tolerance"), key + ".tolerance", "+-tolerance in the key's unit, read as 3 sigma (the normal truncated there)");
      d.sigma = d.tolerance / 3.0;
    }
  } else {
    if (has_sigma) throw std::invalid_argument(fmt::format("[tolerances] {}: a uniform distribution takes tolerance (+-), not sigma", key));
    if (!has_tolerance) throw std::invalid_argument(fmt::format("[tolerances] {}: missing tolerance (the uniform half-width, +-)", key));
    d.tolerance = Number(t.at("tolerance"), key + ".tolerance", "half-width of the uniform distribution in the key's unit");
  }
  if (t.count("mean") != 0) d.mean = Number(t.at("mean"), key + ".mean", "offset of the centre from the deck's value in the key's unit");
  return d;
}

analysis::ToleranceSettings ReadTolerances(const toml::value& value, const geometry::PairParameters& pair) {
  // Its own keys and one distribution per key it may vary (the table of deck keys).
  std::vector<std::string> known = analysis::SectionKeys("tolerances");
  const auto& keys = analysis::ToleranceSettings::ToleranceKeys();
  for (const auto& k : keys) known.push_back(k.first);
  const Section section(&value, "tolerances", known);
  analysis::ToleranceSettings s;
  const toml::table& t = value.as_table();
  for (const auto& [key, per_pin] : keys) {  // in the fixed order of the key table
    if (const auto it = t.find(key); it != t.end()) s.distributions.push_back(ReadDistribution(key, per_pin, it->second));
  }
  ReadSettings(section, {.tolerances = &s});
  if (const auto it = t.find("limits"); it != t.end()) {
    s.limits = ReadLimits(it->second, "tolerances", "limits", "{ lost_motion_arcmin = 1.0, contacts_min = { min = 4 } }");
  }
  if (const auto it = t.find("chains"); it != t.end()) {
    const std::string example =
        "expected chains = { NAME = [ { link = \"pin tooth diameter\", kind = \"decreasing\", upper_um = 0, lower_um = -13 }, "
        "... ] } (docs/tolerance.md)";
    if (!it->second.is_table()) throw std::invalid_argument(fmt::format("[tolerances] chains = {}: {}", toml::format(it->second), example));
    for (const auto& [name, links] : it->second.as_table()) {
      analysis::DimensionChain chain;
      chain.name = name;
      if (!links.is_array() || links.as_array().empty()) {
        throw std::invalid_argument(fmt::format("[tolerances] chains.{}: {}", name, example));
      }
      for (std::size_t k = 0; k < links.as_array().size(); ++k) {
        const toml::value& l = links.as_array()[k];
        const std::string where = fmt::format("chains.{}[{}]", name, k);
        if (!l.is_table()) throw std::invalid_argument(fmt::format("[tolerances] {}: {}", where, example));
        analysis::DimensionLink link;
        for (const auto& [field, value] : l.as_table()) {
          if (field == "link" && value.is_string()) link.name = value.as_string().str;
          else if (field == "kind" && value.is_string() && (value.as_string().str == "increasing" || value.as_string().str == "decreasing")) {
            link.increasing = value.as_string().str == "increasing";
          } else if (field == "upper_um") link.upper = Number(value, where + ".upper_um", "upper deviation in um");
          else if (field == "lower_um") link.lower = Number(value, where + ".lower_um", "lower deviation in um");
          else {
            throw std::invalid_argument(fmt::format("[tolerances] {}.{} = {}: expected link (a name), kind = \"increasing\" | "
                                                    "\"decreasing\", upper_um, lower_um",
                                                    where, field, toml::format(value)));
          }
        }
        for (const char* field : {"kind", "upper_um", "lower_um"}) {
          if (l.as_table().count(field) == 0) throw std::invalid_argument(fmt::format("[tolerances] {}: missing {}; {}", where, field, example));
        }
        if (!(std::isfinite(link.upper) && std::isfinite(link.lower) && link.lower <= link.upper)) {
          throw std::invalid_argument(fmt::format("[tolerances] {}: lower_um = {} and upper_um = {}: expected finite deviations with lower <= upper",
                                                  where, link.lower, link.upper));
        }
        chain.links.push_back(link);
      }
      s.chains.push_back(std::move(chain));
    }
    // A TOML table has no order: by name, so that the output (and the chain's random stream) does not
    // depend on the parser.
    std::sort(s.chains.begin(), s.chains.end(), [](const analysis::DimensionChain& a, const analysis::DimensionChain& b) { return a.name < b.name; });
  }
  s.Validate();
  // The "looks like an absolute value" rule of [errors] and [modification], on the reach of a
  // distribution: its offset plus its worst-case half-width (3 sigma for a normal one).
  for (const analysis::ToleranceDistribution& d : s.distributions) {
    const double reach = std::abs(d.mean) + d.WorstCaseHalfWidth();
    const std::string shown = fmt::format("{{ mean {} +- {} }}", d.mean, d.WorstCaseHalfWidth());
    const analysis::DeckKey& k = *analysis::FindToleranceKey(d.key);  // a known key (checked above)
    // A tilt's shift over the face width, taken at 45 deg at most (tan grows without bound).
    const double internal = k.ToInternal(k.limit == analysis::DeckKey::Limit::kTilt ? std::min(reach, 45.0) : reach);
    analysis::RequireSmallDeviation(k.Reach(internal, pair), "tolerances", d.key, pair, shown);
  }
  return s;
}
// --- end of reading [tolerances] -----------------------------------------------------------------

// --- [operation] and [friction] -------------------------------------------------------------------
/// [operation]: the crank speed is input_speed_rpm, or follows from motor_speed_rpm through an RV's
/// first stage (CrankSpeedFromMotor, once [output] is read).
analysis::OperationSettings ReadOperation(const Section& s) {
  analysis::OperationSettings o;
  ReadSettings(s, {.operation = &o});
  const bool motor = s.Has("motor_speed_rpm");
  if (motor && s.Has("input_speed_rpm")) {
    throw std::invalid_argument("[operation] input_speed_rpm and motor_speed_rpm: expected one of the two (the crank speed, or "
                                "the motor's with [output] first_stage_teeth)");
  }
  if (motor) {
    const double rpm = s.Real("motor_speed_rpm");
    if (!std::isfinite(rpm) || rpm <= 0.0 || rpm > analysis::OperationSettings::kMaxSpeedRpm) {
      throw std::invalid_argument(fmt::format("[operation] motor_speed_rpm = {}: expected a motor speed > 0 and <= {} rpm", rpm,
                                              analysis::OperationSettings::kMaxSpeedRpm));
    }
    o.input_speed = units::RpmToRadPerS(rpm);  // the motor's until CrankSpeedFromMotor turns it into the cranks'
    return o;
  }
  if (!s.Has("input_speed_rpm")) (void)s.Real("input_speed_rpm");  // "[operation] missing required key 'input_speed_rpm' (...)"
  o.Validate();
  return o;
}

/// [operation] motor_speed_rpm through an RV's first stage ([output] first_stage_teeth, or
/// crank_turns_per_output_turn = 1 + k > 1): with the sun at the motor's speed w_m, the output (the
/// carrier) at w_c / I (I the pair's transmission ratio, the disc turning 1/I of a crank turn) and
/// the spur gear on each crankshaft meshing with the sun in the carrier's frame,
/// w_c - w_c / I = -k (w_m - w_c / I), k = z_sun / z_spur: the cranks turn
/// w_c = -k w_m / (1 - (1 + k) / I) (RV-40E-like, k = 1/3, z_c = 39: 0.3223 w_m, the output
/// w_m / 121). A magnitude: the lives and the losses need the rate.
void CrankSpeedFromMotor(const Section& s, Deck* deck) {
  if (!s.Present() || !s.Has("motor_speed_rpm") || !deck->operation) return;
  const double rpm = s.Real("motor_speed_rpm");
  const solvers::ReducerSettings* r = deck->reducer ? &*deck->reducer : nullptr;
  const double k = r != nullptr && r->kind == solvers::OutputKind::kCranks ? r->cranks.turns_per_output_turn - 1.0 : 0.0;
  if (!(k > 0.0)) {
    throw std::invalid_argument(fmt::format("[operation] motor_speed_rpm = {}: the crank speed follows from the motor's only "
                                            "through an RV's first stage; expected [output] kind = \"cranks\" with "
                                            "first_stage_teeth, or input_speed_rpm (the crank speed)",
                                            rpm));
  }
  const double ratio = geometry::Kinematics(deck->pair).TransmissionRatio();
  deck->operation->input_speed = units::RpmToRadPerS(rpm) * k / std::abs(1.0 - (1.0 + k) / ratio);
  deck->operation->Validate();
  deck->speed_from_motor = true;
  if (!deck->load_spectrum.empty()) {
    // A bin's speed_rpm is a crank speed: beside a motor speed a user would read it as the motor's.
    throw std::invalid_argument("[[load_spectrum]] with [operation] motor_speed_rpm: a bin's speed_rpm is the crank speed; "
                                "expected [operation] input_speed_rpm (the crank speed) beside a load spectrum, and each "
                                "bin's crank speed (the motor's times k / |1 - (1 + k) / I|, docs/stage.md)");
  }
}

// --- reading [optimise] ---------------------------------------------------------------------------
analysis::OptimiseSettings ReadOptimise(const Section& s, const toml::value& value, const std::optional<analysis::ToleranceSettings>& tolerances) {
  analysis::OptimiseSettings o;
  const toml::table& t = value.as_table();
  if (const auto it = t.find("variables"); it != t.end()) {
    if (!it->second.is_table()) {
      throw std::invalid_argument(fmt::format(
          "[optimise] variables = {}: expected an inline table, e.g. {{ \"modification.pin_radius_mm\" = [-0.03, 0.0] }}",
          toml::format(it->second)));
    }
    for (const auto& [key, bounds] : it->second.as_table()) {
      if (!bounds.is_array() || bounds.as_array().size() != 2) {
        throw std::invalid_argument(fmt::format("[optimise] variables.\"{}\" = {}: expected [lower, upper]", key, toml::format(bounds)));
      }
      analysis::OptimiseVariable v;
      v.key = key;
      v.lower = Number(bounds.as_array()[0], "variables.\"" + key + "\"", "the lower bound", "optimise");
      v.upper = Number(bounds.as_array()[1], "variables.\"" + key + "\"", "the upper bound", "optimise");
      o.variables.push_back(v);
    }
  }
  if (const auto it = t.find("constraints"); it != t.end()) {
    o.constraints = ReadLimits(it->second, "optimise", "constraints", "{ mean_backlash_arcsec = { min = 20, max = 40 } }");
  }
  ReadSettings(s, {.optimise = &o});
  if (o.robust) {
    if (!tolerances) {
      throw std::invalid_argument("[optimise] robust = true: expected a [tolerances] section (the distributions every design is run over)");
    }
    o.tolerances = *tolerances;
  }
  o.Validate();
  return o;
}

analysis::FrictionSettings ReadFriction(const Section& s, const geometry::PairParameters& pair) {
  analysis::FrictionSettings f;
  ReadSettings(s, {.friction = &f});
  // Coulomb's law needs its coefficient; jiang-mixed does without.
  if (f.model == analysis::FrictionSettings::Model::kCoulomb && !s.Has("coefficient")) (void)s.Real("coefficient");  // names it missing
  f.Validate(pair);
  return f;
}
// --- end of [operation] and [friction] ---------------------------------------------------------------

}  // namespace

Deck::ModelInfo Deck::Model() const {
  ModelInfo m;
  static_cast<analysis::ModelInfo&>(m) = StageDesign::Model();
  if (m.name.rfind("plane", 0) == 0 && width_slices_given && geometry.width_slices != 1) {
    m.note = fmt::format("width_slices = {} not used: nothing varies along the face width, so the plane model ran",
                         geometry.width_slices);
  }
  for (const std::string& note : notes) m.note += (m.note.empty() ? "" : "; ") + note;
  m.tip_relief = modification.tip_relief;
  m.tip_relief_source = tip_relief_source;
  m.tip_relief_note = tip_relief_note;
  return m;
}

analysis::Stage Deck::MakeStage(std::vector<double> cranks) const {
  RequireMaterial();
  return analysis::Stage(*this, std::move(cranks));
}

analysis::ToleranceCase Deck::MakeToleranceCase() const {
  RequireMaterial();
  return {*this, sweep, RequireLoad().torque, stiffness, friction, operation};
}

void Deck::ValidateSettings() const {
  if (tolerances && tolerances->profile_random_per_sample && errors.profile_random.zone == 0.0) {
    throw std::invalid_argument(
        "[tolerances] profile_random_per_sample = true: [errors] profile_random_zone_um is 0; expected a random profile "
        "zone to draw per sample");
  }
  if (friction && friction->model == analysis::FrictionSettings::Model::kJiangMixed && !operation) {
    throw std::invalid_argument(
        "[friction] model = \"jiang-mixed\": expected an [operation] section (input_speed_rpm, the oil, the "
        "roughness) for the film thickness");
  }
  if (friction && !reducer && friction->stage_friction()) {
    throw std::invalid_argument(fmt::format(
        "[friction] output_pin_coefficient = {:g}, bearing_coefficient = {:g}, bearing_viscous_factor = {:g}: expected an "
        "[output] section (the stage whose output pins and bearings they are), or 0",
        friction->output_pin_coefficient, friction->bearing_coefficient, friction->bearing_viscous_factor));
  }
  if (friction && reducer && reducer->kind != solvers::OutputKind::kPins && friction->output_pin_coefficient > 0.0) {
    throw std::invalid_argument(fmt::format(
        "[friction] output_pin_coefficient = {:g}: expected [output] kind = \"pins\" (the crankshafts' bearings take "
        "bearing_coefficient)",
        friction->output_pin_coefficient));
  }
  if (operation && operation->kinematic_viscosity) {
    // ISO 281's modified life rates a roller bearing of known pitch diameter, rating and C_u.
    const contact::BearingSettings* b = reducer ? &reducer->bearing : nullptr;
    const std::string asked = fmt::format("[operation] oil_kinematic_viscosity_mm2_per_s = {:g} (ISO 281's modified life a_ISO L10)",
                                          *operation->kinematic_viscosity);
    if (b == nullptr || b->kind != contact::BearingKind::kRollers || !(b->pitch_diameter > 0.0) || !(b->dynamic_load_rating > 0.0)) {
      throw std::invalid_argument(asked + ": expected [output] with [bearing] kind = \"rollers\", pitch_diameter_mm and "
                                          "dynamic_load_rating_n");
    }
    if (!(b->fatigue_load_limit > 0.0) && std::isnan(contact::FatigueLoadLimitEstimate(b->static_load_rating, b->pitch_diameter))) {
      throw std::invalid_argument(fmt::format(
          "{}: [bearing] fatigue_load_limit_n is 0 and ISO 281 Annex B's estimate C_0r / 8.2 needs static_load_rating_n > 0 "
          "and pitch_diameter_mm <= {:g} mm (given {:g} N, {:g} mm); expected fatigue_load_limit_n (C_u, the bearing maker's)",
          asked, contact::kFatigueLoadLimitEstimateMaxPitchDiameter, b->static_load_rating, b->pitch_diameter));
    }
  }
}

const analysis::FrictionSettings& Deck::RequireFriction() const {
  if (!friction) {
    throw std::invalid_argument(fmt::format(
        "deck '{}': missing required section [friction] for this command (e.g. --set friction.coefficient=0.05)",
        name));
  }
  return *friction;
}

const analysis::OperationSettings& Deck::RequireOperation() const {
  if (!operation) {
    throw std::invalid_argument(fmt::format(
        "deck '{}': missing required section [operation] for this command (e.g. --set "
        "operation.input_speed_rpm=1500)",
        name));
  }
  return *operation;
}

const contact::Material& Deck::RequireMaterial() const {
  if (!material) {
    throw std::invalid_argument(
        fmt::format("deck '{}': missing required section [material] for this command", name));
  }
  return *material;
}

const analysis::LoadCase& Deck::RequireLoad() const {
  if (!load) {
    throw std::invalid_argument(
        fmt::format("deck '{}': missing required section [load] for this command", name));
  }
  return *load;
}

namespace {

// The keys of [modification] and [errors] from the table: those of a disc (a second disc may give
// its own) and those of the pin ring (common to both discs).
std::vector<std::string> DiscKeys(const char* section, bool disc) {
  std::vector<std::string> out;
  for (const analysis::DeckKey& k : analysis::DeckKeys()) {
    if (std::string_view(k.section) == section && k.disc == disc) out.emplace_back(k.name);
  }
  return out;
}

std::vector<std::string> ConcatKeys(const std::vector<std::string>& a, const std::vector<std::string>& b) {
  std::vector<std::string> out = a;
  out.insert(out.end(), b.begin(), b.end());
  return out;
}

bool Contains(const std::vector<std::string>& keys, const std::string& key) {
  return std::find(keys.begin(), keys.end(), key) != keys.end();
}

// [second_disc]: the first disc's [modification] and [errors] tables with the keys the
// section gives put over them, read by the same readers; the first disc's tip relief (given or
// chosen) unless the section gives its own.
void ReadSecondDisc(const toml::table& root, const toml::value& section, const std::filesystem::path& directory,
                    Deck* deck) {
  const std::vector<std::string> kModificationKeys = DiscKeys("modification", true);
  const std::vector<std::string> kRingErrorKeys = DiscKeys("errors", false);
  const std::vector<std::string> kDiscErrorKeys = DiscKeys("errors", true);
  const std::vector<std::string> kOwnKeys = analysis::SectionKeys("second_disc");
  if (!section.is_table()) {
    throw std::invalid_argument("[second_disc]: expected a table of the second disc's keys");
  }
  const auto table_of = [&](const char* name) {
    const toml::value* v = Find(root, name);
    return v != nullptr && v->is_table() ? v->as_table() : toml::table{};
  };
  toml::table modification = table_of("modification"), errors = table_of("errors");
  bool relief_given = false;
  for (const auto& [key, value] : section.as_table()) {
    if (Contains(kModificationKeys, key)) {
      modification[key] = value;
      relief_given = relief_given || key == "tip_truncation_mm" || key == "tip_rounding_radius_mm";
    } else if (Contains(kDiscErrorKeys, key)) {
      errors[key] = value;
    } else if (Contains(kRingErrorKeys, key)) {
      throw std::invalid_argument(fmt::format(
          "[second_disc] {}: the pin ring is common to both discs; expected it in [errors] (a second disc takes the "
          "[modification] keys, the disc's [errors] keys and indexing_deviation_mm)",
          key));
    } else if (!Contains(kOwnKeys, key)) {
      throw std::invalid_argument(fmt::format(
          "[second_disc] unknown key '{}'; expected {}, a key of [modification] ({}) or a disc key of [errors] ({})",
          key, fmt::join(kOwnKeys, ", "), fmt::join(kModificationKeys, ", "), fmt::join(kDiscErrorKeys, ", ")));
    }
  }
  const toml::value given(section);
  const Section own(&given, "second_disc", ConcatKeys(ConcatKeys(kModificationKeys, kDiscErrorKeys), kOwnKeys));
  analysis::SecondDisc disc;
  ReadSettings(own, {.second_disc = &disc});
  if (!std::isfinite(disc.indexing_deviation)) {
    throw std::invalid_argument(fmt::format(
        "[second_disc] indexing_deviation_mm = {}: expected a finite length in mm along the pin circle", disc.indexing_deviation));
  }
  const toml::value modification_value(modification), errors_value(errors);
  disc.modification = ReadModification(Section(&modification_value, "second_disc", kModificationKeys), deck->pair);
  if (!relief_given) disc.modification.tip_relief = deck->modification.tip_relief;
  const Section error_section(&errors_value, "second_disc", ConcatKeys(kRingErrorKeys, kDiscErrorKeys));
  ReadErrors(error_section, deck->pair, directory, &disc.errors, &disc.assembly);
  // The indexing deviation turns the disc in the sense of +T: counterclockwise for d > 0.
  const double load_direction = deck->pair.ToothDifference() > 0 ? 1.0 : -1.0;
  disc.modification.rotation += load_direction * disc.indexing_deviation / deck->pair.pin_circle_radius;
  analysis::RequireSmallDeviation(disc.indexing_deviation, "second_disc", "indexing_deviation_mm", deck->pair);
  disc.modification.Validate(deck->pair);
  deck->second_disc = std::move(disc);
  const geometry::RealPair realisable = deck->MakeSecondRealPair();  // rejects an undercut second disc
  (void)realisable;
}

}  // namespace

namespace {

/// [output] and [bearing]: the reducer stage's elements. A key of the other kind is an
/// error, not ignored.
/// A disc's hole position deviations from its section ([output], or [second_disc] for the second
/// disc's own): one radial and one tangential value per hole, either list alone (the other zero);
/// none when neither is given. Small, as every manufacturing error is.
contact::HoleDeviations ReadHoleDeviations(const Section& section, int count, const geometry::PairParameters& pair) {
  const std::vector<double> radial = section.RealList("hole_radial_deviations_mm");
  const std::vector<double> tangential = section.RealList("hole_tangential_deviations_mm");
  contact::HoleDeviations deviations;
  if (radial.empty() && tangential.empty()) return deviations;
  for (const auto& [key, list] : {std::pair{"hole_radial_deviations_mm", &radial},
                                  std::pair{"hole_tangential_deviations_mm", &tangential}}) {
    if (!list->empty() && static_cast<int>(list->size()) != count) {
      throw std::invalid_argument(fmt::format("[{}] {}: {} values; expected one per hole ([output] count = {})", section.name(),
                                              key, list->size(), count));
    }
    for (std::size_t j = 0; j < list->size(); ++j) {
      if (!std::isfinite((*list)[j])) {
        throw std::invalid_argument(
            fmt::format("[{}] {}[{}] = {}: expected a finite deviation in mm", section.name(), key, j, (*list)[j]));
      }
      analysis::RequireSmallDeviation((*list)[j], section.name(), fmt::format("{}[{}]", key, j), pair);
    }
  }
  deviations.assign(static_cast<std::size_t>(count), Eigen::Vector2d::Zero());
  for (int j = 0; j < count; ++j) {
    const auto k = static_cast<std::size_t>(j);
    deviations[k] = Eigen::Vector2d(radial.empty() ? 0.0 : radial[k], tangential.empty() ? 0.0 : tangential[k]);
  }
  return deviations;
}

/// [second_disc]'s own stage elements (discs are machined one by one): its holes' position
/// deviations and its bearing's play, over the first disc's ([output], [bearing]) in
/// ReducerSettings::second_disc_holes and second_disc_bearing_clearance. Requires [output].
void ReadSecondDiscElements(const toml::value& section, Deck* deck) {
  const std::vector<std::string> kKeys = {"hole_radial_deviations_mm", "hole_tangential_deviations_mm",
                                          "bearing_radial_clearance_mm"};
  toml::table own;
  for (const auto& [key, value] : section.as_table()) {
    if (Contains(kKeys, key)) own[key] = value;
  }
  if (own.empty()) return;
  if (!deck->reducer) {
    throw std::invalid_argument(fmt::format("[second_disc] {}: a key of the reducer stage's elements; expected an [output] "
                                            "section",
                                            own.begin()->first));
  }
  const toml::value given(own);
  const Section elements(&given, "second_disc", kKeys);
  solvers::ReducerSettings& s = *deck->reducer;
  const bool pins = s.kind == solvers::OutputKind::kPins;
  if (elements.Has("hole_radial_deviations_mm") || elements.Has("hole_tangential_deviations_mm")) {
    s.second_disc_holes = ReadHoleDeviations(elements, pins ? s.pins.count : s.cranks.count, deck->pair);
  }
  if (elements.Has("bearing_radial_clearance_mm")) {
    const double c = elements.Real("bearing_radial_clearance_mm");
    if (s.bearing.kind == contact::BearingKind::kRigid) {
      throw std::invalid_argument("[second_disc] bearing_radial_clearance_mm: a rigid [bearing] has no play; expected a linear or "
                                  "rollers bearing");
    }
    if (!std::isfinite(c)) {
      throw std::invalid_argument(fmt::format("[second_disc] bearing_radial_clearance_mm = {}: expected a finite radial play in mm "
                                              "(negative: a preload)", c));
    }
    analysis::RequireSmallDeviation(c, "second_disc", "bearing_radial_clearance_mm", deck->pair);
    s.second_disc_bearing_clearance = c;
  }
  s.Validate(deck->pair.eccentricity);
}

solvers::ReducerSettings ReadReducer(const Section& output, const Section& bearing, const geometry::PairParameters& pair) {
  solvers::ReducerSettings s;
  ReadSettings(output, {.reducer = &s});
  const bool pins = s.kind == solvers::OutputKind::kPins;
  const auto reject = [&](std::initializer_list<const char*> keys, const char* kind) {
    for (const char* key : keys) {
      if (output.Has(key)) {
        throw std::invalid_argument(fmt::format("[output] {}: not a key of kind = \"{}\"", key, kind));
      }
    }
  };
  // The keys its kind needs, named when missing; then every number given, into the pins or the cranks.
  if (pins) {
    reject({"shaft_stiffness_n_per_mm", "crank_turns_per_output_turn", "first_stage_teeth", "shaft_diameter_mm",
            "shaft_span_mm", "eccentric_positions_mm", "support_stiffness_n_per_mm"},
           "pins");
    RequireKeys(output, {"count", "circle_radius_mm", "pin_radius_mm", "hole_radius_mm"});
    ReadSettings(output, {.output_pins = &s.pins});
  } else {
    reject({"pin_radius_mm", "hole_radius_mm"}, "cranks");
    RequireKeys(output, {"count", "circle_radius_mm"});
    ReadSettings(output, {.cranks = &s.cranks});
    if (output.Has("shaft_stiffness_n_per_mm") && !std::isfinite(s.cranks.shaft_stiffness)) {
      throw std::invalid_argument("[output] shaft_stiffness_n_per_mm: expected a finite stiffness in N/mm (leave the "
                                  "key out for a rigid shaft)");
    }
    // Crankshafts as beams (docs/stage.md, "Crankshafts as beams"): the diameter, the span and both
    // eccentrics' positions together; the supports rigid unless given.
    if (output.Has("shaft_diameter_mm") || output.Has("shaft_span_mm") || output.Has("eccentric_positions_mm") ||
        output.Has("support_stiffness_n_per_mm")) {
      const std::vector<double> a = output.RealList("eccentric_positions_mm");
      RequireKeys(output, {"shaft_diameter_mm", "shaft_span_mm", "eccentric_positions_mm"});
      if (a.size() != 2) {
        throw std::invalid_argument(fmt::format("[output] eccentric_positions_mm = [{}]: expected [a_1, a_2], the first "
                                                "and the second disc's eccentric from the first support in mm",
                                                fmt::join(a, ", ")));
      }
      s.cranks.beam.eccentric = {a[0], a[1]};
      s.cranks.beam.Validate();  // a diameter of 0 too: the keys given are a beam
      if (output.Has("support_stiffness_n_per_mm") && !std::isfinite(s.cranks.beam.support_stiffness)) {
        throw std::invalid_argument("[output] support_stiffness_n_per_mm: expected a finite stiffness in N/mm (leave the "
                                    "key out for rigid supports)");
      }
    }
    // The RV's first stage (docs/stage.md, "The first stage"): the eccentrics' turn with the input
    // locked follows from the tooth counts; the turns as a number are the other way to give it.
    if (output.Has("first_stage_teeth")) {
      if (output.Has("crank_turns_per_output_turn")) {
        throw std::invalid_argument("[output] first_stage_teeth and crank_turns_per_output_turn: both set the eccentrics' "
                                    "turn with the input locked; expected one of the two");
      }
      const std::vector<double> teeth = output.RealList("first_stage_teeth");
      const auto whole = [](double z) { return std::isfinite(z) && z >= 1.0 && z <= 1e6 && z == std::floor(z); };
      if (teeth.size() != 2 || !whole(teeth[0]) || !whole(teeth[1])) {
        throw std::invalid_argument(fmt::format("[output] first_stage_teeth = [{}]: expected [z_sun, z_spur], two whole "
                                                "tooth counts >= 1 (the input's sun gear and each crankshaft's spur gear)",
                                                fmt::join(teeth, ", ")));
      }
      s.cranks.sun_teeth = static_cast<int>(teeth[0]);
      s.cranks.spur_teeth = static_cast<int>(teeth[1]);
      s.cranks.turns_per_output_turn = contact::FirstStageTurns(s.cranks.sun_teeth, s.cranks.spur_teeth);
    }
  }
  if (output.Has("carrier_torsional_stiffness_nm_per_arcmin") && !std::isfinite(s.carrier_stiffness)) {
    throw std::invalid_argument("[output] carrier_torsional_stiffness_nm_per_arcmin: expected a finite stiffness in "
                                "N*m/arcmin (leave the key out for a rigid carrier)");
  }
  // Each hole's position deviation in the disc (both discs alike, unless [second_disc] gives its
  // own): one radial and one tangential value per hole.
  (pins ? s.pins.hole_deviation : s.cranks.hole_deviation) = ReadHoleDeviations(output, pins ? s.pins.count : s.cranks.count, pair);
  contact::BearingSettings& b = s.bearing;
  ReadSettings(bearing, {.bearing = &b}, {}, /*choices_only=*/true);
  const auto bearing_reject = [&](std::initializer_list<const char*> keys) {
    for (const char* key : keys) {
      if (bearing.Has(key)) {
        throw std::invalid_argument(fmt::format("[bearing] {}: not a key of kind = \"{}\"", key, contact::ToString(b.kind)));
      }
    }
  };
  if (b.kind != contact::BearingKind::kLinear) bearing_reject({"radial_stiffness_n_per_mm"});
  if (b.kind != contact::BearingKind::kRollers) bearing_reject({"roller_count", "roller_diameter_mm", "roller_length_mm", "pitch_diameter_mm"});
  if (b.kind == contact::BearingKind::kRigid) bearing_reject({"radial_clearance_mm"});
  // The keys its kind needs, named when missing; then every number given.
  if (b.kind == contact::BearingKind::kLinear) RequireKeys(bearing, {"radial_stiffness_n_per_mm"});
  if (b.kind == contact::BearingKind::kRollers) RequireKeys(bearing, {"roller_count", "roller_diameter_mm", "roller_length_mm"});
  ReadSettings(bearing, {.bearing = &b});
  s.Validate(pair.eccentricity);
  // Limits of physical sense (docs/decks.md, Limits). The holes lie inside the disc: within its
  // root circle, the profile's nearest point to the disc centre (u = 0, the root of a tooth space).
  const double root = geometry::CycloidProfile(pair).Position(0.0).norm();
  const double reach = pins ? s.pins.circle_radius + s.pins.hole_radius : s.cranks.circle_radius;
  if (!(reach < root)) {
    throw std::invalid_argument(fmt::format(
        "[output] circle_radius_mm = {}: the {} reach {:.6g} mm from the disc centre; expected them inside the disc, within "
        "its root circle of {:.6g} mm",
        pins ? s.pins.circle_radius : s.cranks.circle_radius, pins ? "holes (circle_radius_mm + hole_radius_mm)" : "crank holes' centres",
        reach, root));
  }
  // The stage's elements are linearised about their unloaded pose: a play that moves the disc by
  // more than a small fraction of the pin radius is beyond the model (1 mm of play moved the disc
  // 1.04 mm, and the linearised and exact forces differed by 80 %).
  const double play_limit = DeckLimits::kMaxDeviationFraction * pair.pin_radius;
  if (std::abs(b.radial_clearance) > play_limit) {
    throw std::invalid_argument(fmt::format(
        "[bearing] radial_clearance_mm = {}: expected a radial play (negative: a preload) of at most {:.6g} mm either way ({:g} % "
        "of [pair] pin_radius_mm = {}): the stage's model holds for small displacements of the disc (docs/decks.md, Limits)",
        b.radial_clearance, play_limit, 100.0 * DeckLimits::kMaxDeviationFraction, pair.pin_radius));
  }
  if (pins) {
    const double clearance = s.pins.hole_radius - s.pins.pin_radius - pair.eccentricity;
    if (std::abs(clearance) > play_limit) {
      throw std::invalid_argument(fmt::format(
          "[output] hole_radius_mm = {}: its clearance hole_radius_mm - pin_radius_mm - eccentricity_mm = {:.6g} mm; expected "
          "at most {:.6g} mm either way (negative: a preload; {:g} % of [pair] pin_radius_mm): the stage's model holds for "
          "small displacements of the disc "
          "(docs/decks.md, Limits)",
          s.pins.hole_radius, clearance, play_limit, 100.0 * DeckLimits::kMaxDeviationFraction));
    }
  }
  return s;
}

}  // namespace

namespace {
/// A deck value as TOML writes it on one line (a table inline, a string quoted).
/// A TOML basic string: quotes, backslashes and control characters escaped (TOML 1.0, "String").
std::string TomlString(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (u < 0x20 || u == 0x7f) {
      out += fmt::format("\\u{:04X}", static_cast<unsigned>(u));
    } else {
      out += c;
    }
  }
  return out + "\"";
}

/// A TOML key: bare when it is only A-Z a-z 0-9 _ -, else quoted.
std::string TomlKey(const std::string& key) {
  const bool bare = !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
  return bare ? key : TomlString(key);
}

std::string GivenText(const toml::value& v) {
  if (v.is_string()) return TomlString(v.as_string().str);
  if (v.is_table()) {
    std::vector<std::string> parts;
    for (const auto& [key, item] : v.as_table()) parts.push_back(TomlKey(key) + " = " + GivenText(item));
    return "{ " + fmt::format("{}", fmt::join(parts, ", ")) + " }";
  }
  if (v.is_array()) {
    std::vector<std::string> parts;
    for (const auto& item : v.as_array()) parts.push_back(GivenText(item));
    return "[" + fmt::format("{}", fmt::join(parts, ", ")) + "]";
  }
  if (v.is_floating()) return fmt::format("{}", v.as_floating());  // the shortest text that reads back the same
  if (v.is_integer()) return fmt::format("{}", v.as_integer());
  std::ostringstream out;
  out << toml::format(v);
  std::string text = out.str();
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  return text;
}

/// A float as TOML: the shortest text that reads back the same double, always a float.
std::string TomlFloat(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  std::string text = fmt::format("{}", x);
  if (text.find_first_of(".eE") == std::string::npos) text += ".0";
  return text;
}

}  // namespace

std::string TomlKeyText(const std::string& key) { return TomlKey(key); }

std::string TomlText(const TomlValue& value) {
  struct Writer {
    std::string operator()(bool b) const { return b ? "true" : "false"; }
    std::string operator()(std::int64_t i) const { return fmt::format("{}", i); }
    std::string operator()(double x) const { return TomlFloat(x); }
    std::string operator()(const std::string& s) const { return TomlString(s); }
    std::string operator()(const TomlValue::Array& a) const {
      std::vector<std::string> parts;
      for (const TomlValue& item : a) parts.push_back(TomlText(item));
      return "[" + fmt::format("{}", fmt::join(parts, ", ")) + "]";
    }
    std::string operator()(const TomlValue::Table& t) const {
      std::vector<std::string> parts;
      for (const auto& [key, item] : t) parts.push_back(TomlKey(key) + " = " + TomlText(item));
      return "{ " + fmt::format("{}", fmt::join(parts, ", ")) + " }";
    }
  };
  return std::visit(Writer{}, value.value);
}

std::string TomlDeckText(const std::vector<std::pair<std::string, TomlValue::Table>>& sections) {
  std::string text;
  for (const auto& [section, keys] : sections) {
    text += "[" + TomlKey(section) + "]\n";
    for (const auto& [key, value] : keys) text += TomlKey(key) + " = " + TomlText(value) + "\n";
    text += "\n";
  }
  return text;
}

namespace {

/// The TOML of a deck's text, its shape checked first; errors name the deck.
toml::value ParseText(std::string_view toml_text, const std::string& name) {
  try {
    CheckTextShape(toml_text);
    std::istringstream stream{std::string(toml_text)};
    return toml::parse(stream, name);
  } catch (const std::exception& e) {  // the shape, TOML syntax errors and the like
    throw std::invalid_argument(fmt::format("deck '{}': {}", name, e.what()));
  }
}

/// The deck of parsed TOML with the overrides applied (to this copy of it).
Deck ReadParsed(toml::value root_value, const std::string& name, const std::vector<std::string>& overrides,
                const std::filesystem::path& directory, std::string_view text,
                const std::shared_ptr<const MemoryFiles>& memory = nullptr) {
  Deck deck;
  deck.name = name;
  deck.source.text = std::string(text);
  deck.source.overrides = overrides;
  deck.source.directory = directory;
  deck.source.memory = memory;
  struct FilesRead {  // collects the traces this read opens and offers its in-memory files, on every way out
    FilesRead(std::vector<std::filesystem::path>* files, const MemoryFiles* memory)
        : previous(tl_files_read), previous_memory(tl_memory_files) {
      tl_files_read = files;
      tl_memory_files = memory;
    }
    ~FilesRead() {
      tl_files_read = previous;
      tl_memory_files = previous_memory;
    }
    FilesRead(const FilesRead&) = delete;
    FilesRead& operator=(const FilesRead&) = delete;
    std::vector<std::filesystem::path>* previous;
    const MemoryFiles* previous_memory;
  } files_read(&deck.source.files, memory.get());
  try {
    ApplyOverrides(root_value, overrides);
    const toml::table& root = root_value.as_table();
    const std::vector<std::string> sections = analysis::DeckSections();
    for (const auto& [key, unused] : root) {
      if (std::find(sections.begin(), sections.end(), key) == sections.end()) {
        throw std::invalid_argument(fmt::format("unknown section or key '{}'; expected one of: {}",
                                                key, fmt::join(sections, ", ")));
      }
    }
    // Every value the deck gives (after --set), as it gives it: the report's inputs.
    for (const auto& [section, value] : root) {
      if (!value.is_table()) continue;
      for (const auto& [key, v] : value.as_table()) deck.given.push_back({section, key, GivenText(v)});
    }
    deck.info = ReadCase(RequiredSection(root, "case"));
    deck.pair = ReadPair(RequiredSection(root, "pair"));
    const Section modification(Find(root, "modification"), "modification");
    deck.modification = ReadModification(modification, deck.pair);
    const Section errors(Find(root, "errors"), "errors");
    ReadErrors(errors, deck.pair, directory, &deck.errors, &deck.assembly);
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
    deck.contact = ReadContact(Section(Find(root, "contact"), "contact"));
    const Section geometry(Find(root, "geometry"), "geometry");
    deck.geometry = ReadGeometry(geometry);
    deck.width_slices_given = geometry.Has("width_slices");
    deck.solver = ReadSolver(Section(Find(root, "solver"), "solver"), &deck.kinematics);
    const Section material(Find(root, "material"), "material");
    if (material.Present()) deck.material = ReadMaterial(material);
    const Section pins(Find(root, "pins"), "pins");
    if (pins.Present()) {
      // Two ways a pin is held: at its two ends, bending between them (span_mm,
      // support, face_offset_mm: pin bending), or seated along its length in a housing groove (seat).
      const bool bending = pins.Has("span_mm") || pins.Has("face_offset_mm") || pins.Has("support");
      contact::PinSeat& seat = deck.contact.seat;
      contact::PinSupport p;
      ReadSettings(pins, {.pin_support = &p, .pin_seat = &seat}, {}, /*choices_only=*/true);
      const auto seat_reject = [&](std::initializer_list<const char*> keys) {
        for (const char* key : keys) {
          if (pins.Has(key)) {
            throw std::invalid_argument(fmt::format("[pins] {}: not a key of seat = \"{}\"", key, contact::ToString(seat.kind)));
          }
        }
      };
      if (seat.kind != contact::PinSeat::Kind::kLinear) seat_reject({"seat_stiffness_n_per_mm2"});
      if (seat.kind != contact::PinSeat::Kind::kGroove) {
        seat_reject({"groove_radius_mm", "housing_young_modulus_mpa", "housing_poisson_ratio"});
      }
      if (bending && seat.seated()) {
        throw std::invalid_argument(fmt::format(
            "[pins] seat = \"{}\" with span_mm: a pin seated along its length in a groove is not also held at its "
            "ends and bending between them (pin bending); expected one of the two",
            contact::ToString(seat.kind)));
      }
      if (!bending && !seat.seated()) {
        throw std::invalid_argument("[pins]: expected span_mm and face_offset_mm (pins held at their ends, bending) or "
                                    "seat = \"linear\" | \"groove\" (pins seated in housing grooves)");
      }
      // The keys of the way the pins are held, named when missing; then every key given.
      if (bending) RequireKeys(pins, {"span_mm", "face_offset_mm"});
      if (seat.kind == contact::PinSeat::Kind::kLinear) RequireKeys(pins, {"seat_stiffness_n_per_mm2"});
      if (seat.kind == contact::PinSeat::Kind::kGroove) {
        RequireKeys(pins, {"groove_radius_mm"});
        // The housing takes the disc's elastic constants unless given.
        const bool need = !pins.Has("housing_young_modulus_mpa") || !pins.Has("housing_poisson_ratio");
        if (need && !deck.material) {
          throw std::invalid_argument("[pins] seat = \"groove\": expected housing_young_modulus_mpa and "
                                      "housing_poisson_ratio, or a [material] section whose disc constants the "
                                      "housing takes");
        }
        if (!pins.Has("housing_young_modulus_mpa")) seat.housing_young_modulus = deck.material->young_modulus;
        if (!pins.Has("housing_poisson_ratio")) seat.housing_poisson_ratio = deck.material->poisson_ratio;
      }
      ReadSettings(pins, {.pin_support = &p, .pin_seat = &seat});
      if (bending) {
        p.Validate(deck.pair.face_width);
        deck.pins = p;
      }
      seat.Validate(deck.pair.pin_radius);
      deck.contact.Validate();  // a seat with the sagitta law
    }
    const Section disc(Find(root, "disc"), "disc");
    if (disc.Present()) {
      ReadSettings(disc, {.disc_body = &deck.disc});
      if (deck.disc.elastic()) {
        RequireKeys(disc, {"bore_radius_mm"});
      } else {
        for (const char* key : {"bore_radius_mm", "plane", "element_size_mm", "grid_points_per_space", "patch_half_width_mm"}) {
          if (disc.Has(key)) throw std::invalid_argument(fmt::format("[disc] {}: a key of body = \"elastic\", not of body = \"rigid\"", key));
        }
      }
    }
    const Section load(Find(root, "load"), "load");
    if (load.Present()) deck.load = ReadLoad(load);
    deck.sweep = ReadSweep(Section(Find(root, "sweep"), "sweep"), deck.pair);
    deck.stiffness = ReadStiffness(Section(Find(root, "stiffness"), "stiffness"));
    if (const toml::value* spectrum = Find(root, "load_spectrum")) deck.load_spectrum = ReadLoadSpectrum(*spectrum);
    const Section allowables(Find(root, "allowables"), "allowables");
    if (allowables.Present()) {
      ReadSettings(allowables, {.allowables = &deck.allowables});
      deck.allowables.Validate();
    }
    const Section inspection(Find(root, "inspection"), "inspection");
    if (inspection.Present()) {
      ReadSettings(inspection, {.inspection = &deck.inspection});
      deck.inspection.Validate();
    }
    if (const toml::value* t = Find(root, "tolerances")) {
      deck.tolerances = ReadTolerances(*t, deck.pair);
    }
    // [operation] and [friction], both optional.
    const Section operation(Find(root, "operation"), "operation");
    if (operation.Present()) deck.operation = ReadOperation(operation);
    const Section friction(Find(root, "friction"), "friction");
    if (friction.Present()) deck.friction = ReadFriction(friction, deck.pair);
    if (const toml::value* opt = Find(root, "optimise")) {
      const Section optimise(opt, "optimise");
      deck.optimise = ReadOptimise(optimise, *opt, deck.tolerances);
    }
    // The geometry must be realisable: this rejects undercut (looped) profiles, also when the
    // profile layer of [errors] is what makes them loop.
    const geometry::RealPair real = deck.MakeRealPair();  // analytic: cheap to check
    // No tip relief but the user's: a default chosen for the solvers' sake changed the
    // part with the torque and the stress limit, and no relief keeps the tips of the |d| >= 2 decks
    // of cases/hard unloaded at their torque (docs/contact.md, "Tip relief"). A loaded sharp corner
    // is an edge contact, a named status; a loaded relief is reported by the solve (a warning).
    if (modification.Has("tip_truncation_mm") || modification.Has("tip_rounding_radius_mm")) {
      deck.tip_relief_source = "deck";
    } else if (std::abs(deck.pair.ToothDifference()) >= 2) {
      deck.tip_relief_note =
          "sharp tips: no tip relief is given ([modification] tip_rounding_radius_mm, tip_truncation_mm) and none is "
          "assumed; a position where a loaded pin bears on a tip corner fails with status edge-contact, which no "
          "line-contact law covers";
    }
    if (const toml::value* second = Find(root, "second_disc")) ReadSecondDisc(root, *second, directory, &deck);
    const Section output(Find(root, "output"), "output");
    const Section bearing(Find(root, "bearing"), "bearing");
    if (output.Present()) {
      deck.reducer = ReadReducer(output, bearing, deck.pair);
      if (const toml::value* second = Find(root, "second_disc"); second != nullptr && second->is_table()) {
        ReadSecondDiscElements(*second, &deck);
      }
      if (deck.reducer->kind == solvers::OutputKind::kCranks && deck.reducer->cranks.beam.given() && !deck.second_disc) {
        throw std::invalid_argument("[output] shaft_diameter_mm: a crankshaft as a beam carries both discs' eccentrics; "
                                    "expected [second_disc] (one disc: shaft_stiffness_n_per_mm)");
      }
    } else if (const toml::value* second = Find(root, "second_disc"); second != nullptr && second->is_table()) {
      ReadSecondDiscElements(*second, &deck);  // refuses its element keys without [output]
    }
    if (!output.Present() && bearing.Present()) {
      throw std::invalid_argument("[bearing] without [output]: the bearing belongs to the reducer stage; expected an "
                                  "[output] section (kind = \"pins\" or \"cranks\")");
    }
    CrankSpeedFromMotor(operation, &deck);  // needs [output]'s first stage
    deck.StageDesign::Validate();
    deck.ValidateSettings();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("deck '{}': {}", name, e.what()));
  } catch (const std::exception& e) {  // TOML errors of an override and the like
    throw std::invalid_argument(fmt::format("deck '{}': {}", name, e.what()));
  }
  return deck;
}

}  // namespace

Deck ParseDeck(std::string_view toml_text, const std::string& name, const std::vector<std::string>& overrides,
               const std::filesystem::path& directory) {
  return ReadParsed(ParseText(toml_text, name), name, overrides, directory, toml_text);
}

struct DeckSource::Impl {
  toml::value root;
  std::string text;
  std::string name;
  std::filesystem::path directory;
  std::shared_ptr<const MemoryFiles> memory;  ///< null: none
};

DeckSource::DeckSource(std::string_view toml_text, std::string name, std::filesystem::path directory) {
  auto impl = std::make_shared<Impl>();
  impl->root = ParseText(toml_text, name);
  impl->text = std::string(toml_text);
  impl->name = std::move(name);
  impl->directory = std::move(directory);
  impl_ = std::move(impl);
}

Deck DeckSource::Read(const std::vector<std::string>& overrides) const {
  return ReadParsed(impl_->root, impl_->name, overrides, impl_->directory, impl_->text, impl_->memory);
}

const std::string& DeckSource::name() const { return impl_->name; }

DeckSource DeckSource::WithFile(const std::string& name, std::string text) const {
  auto files = std::make_shared<MemoryFiles>(impl_->memory ? *impl_->memory : MemoryFiles{});
  (*files)[name] = std::move(text);
  auto impl = std::make_shared<Impl>(*impl_);
  impl->memory = std::move(files);
  DeckSource source = *this;
  source.impl_ = std::move(impl);
  return source;
}

analysis::SweepResult SolveDeckSweep(const Deck& deck, const SolverOptions& options, const analysis::SweepCallbacks& callbacks) {
  const auto start = std::chrono::steady_clock::now();
  options.Validate();
  deck.RequireMaterial();
  const double torque = deck.RequireLoad().torque;
  const analysis::Stage stage = deck.MakeStage();
  const double build = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  analysis::SweepResult sweep = analysis::SolveSweep(stage, options, torque, callbacks);
  sweep.summary.wall_seconds += build;
  if (deck.reducer && sweep.summary.reducer) {  // the stage's bearing lives, once, at the deck's crank speed
    sweep.summary.bearing_life =
        analysis::BearingLives(deck, *sweep.summary.reducer, deck.sweep, sweep.summary.closed_period,
                               deck.operation ? deck.operation->input_speed : std::numeric_limits<double>::quiet_NaN(),
                               deck.operation ? deck.operation->kinematic_viscosity.value_or(std::numeric_limits<double>::quiet_NaN())
                                              : std::numeric_limits<double>::quiet_NaN());
  }
  // The pitting rating of the pins and teeth, at the deck's crank speed and required life.
  sweep.summary.contact_fatigue = analysis::RateContactFatigue(
      sweep.summary.contact_cycles, *deck.material, deck.pair.tooth_count,
      deck.operation ? deck.operation->input_speed : std::numeric_limits<double>::quiet_NaN(), deck.allowables.contact_life_hours);
  return sweep;
}

namespace {
/// The deck as `--set load.torque_nm=T --set operation.input_speed_rpm=n` would make it for a bin.
Deck BinDeck(const Deck& deck, const analysis::LoadBin& bin) {
  Deck d = deck;
  d.load = analysis::LoadCase{.torque = bin.torque};
  if (!d.operation) d.operation = analysis::OperationSettings{};
  d.operation->input_speed = bin.input_speed;
  d.load_spectrum.clear();
  return d;
}
}  // namespace

analysis::SpectrumResult SolveDeckSpectrum(const Deck& deck, const SolverOptions& options) {
  std::vector<analysis::SpectrumBinResult> bins;
  for (const analysis::LoadBin& bin : deck.load_spectrum) {
    bins.push_back({.bin = bin, .summary = SolveDeckSweep(BinDeck(deck, bin), options).summary});
  }
  return analysis::CombineSpectrum(std::move(bins));
}

analysis::EfficiencySpectrum EfficiencyDeckSpectrum(const Deck& deck, const SolverOptions& options) {
  std::vector<analysis::EfficiencySpectrum::Bin> bins;
  for (const analysis::LoadBin& bin : deck.load_spectrum) {
    if (bin.torque == 0.0) {  // an idle bin: no force, no power out and none lost, unless a preload presses the pins
      analysis::EfficiencySummary idle;
      const analysis::Stage stage = BinDeck(deck, bin).MakeStage();
      const auto solver = solvers::MakeSolver(options.name);
      for (const double crank : stage.cranks()) {
        const solvers::LoadProblem problem = stage.Problem(crank, 0.0);
        if (!problem.overlapping()) continue;
        const solvers::LoadResult r = solver->Solve(problem, options);
        if (r.status != solvers::SolverStatus::kSuccess || (r.preload && r.preload->contacts > 0)) {
          idle.Fail(fmt::format("idle bin (0 N*m) at crank {:.6g} deg: the stage is preloaded there; the preload's friction "
                                "at zero torque is not modelled (efficiency needs a torque)",
                                units::RadToDeg(crank)));
          break;
        }
      }
      if (idle.failed == 0) {
        idle.succeeded = 1;
        for (analysis::EfficiencySpread* figure : {&idle.output_power, &idle.power_loss, &idle.power_loss_mesh,
                                                   &idle.power_loss_output, &idle.power_loss_bearings, &idle.power_loss_seats}) {
          figure->Add(0.0);
        }
      }
      bins.push_back({.bin = bin, .summary = idle});
      continue;
    }
    const Deck d = BinDeck(deck, bin);
    analysis::EfficiencyRunner runner(d.MakeStage(), options, bin.torque, d.RequireFriction(), d.RequireOperation());
    for (const double crank : runner.cranks()) (void)runner.Solve(crank);
    bins.push_back({.bin = bin, .summary = runner.Summary()});
  }
  return analysis::CombineEfficiency(std::move(bins));
}

Deck DeckFor(const Deck& deck, const std::string& kinematics) {
  Deck d = deck;
  if (!kinematics.empty()) d.kinematics = contact::ParseKinematics(kinematics);
  return d;
}

SolverOptions SolverFor(const Deck& deck, const std::string& name) {
  SolverOptions solver = deck.solver;
  if (!name.empty()) solver.name = name;
  return solver;
}

Deck LoadDeck(const std::filesystem::path& path, const std::vector<std::string>& overrides) {
  const std::string name = path.string();
  const std::string text = ReadBoundedFile(path, fmt::format("deck '{}'", name), "deck file (TOML)",
                                           DeckLimits::kMaxFileBytes, "a deck");
  // Relative paths in the deck (profile_measured_csv) are read from the deck's own directory.
  Deck deck = ParseDeck(text, name, overrides, path.parent_path());
  deck.source.files.insert(deck.source.files.begin(), path);
  return deck;
}

Deck DefaultDeck(const std::vector<std::string>& overrides) {
  return ParseDeck(DefaultDeckText(), "built-in default (Liu 2021 Table 1)", overrides);
}

}  // namespace ltca::app

// --- the deck writer ----------------------------------------------------------------------------
namespace ltca::app {
namespace {

/// TOML text as lines, with the table each key line is in: enough to edit a deck in place and keep
/// its comments, order and empty tables (TOML 1.0: strings of four kinds, arrays and inline tables
/// that span lines, comments from '#' outside strings).
struct TomlLines {
  struct KeyAt {
    std::string table, key;
    std::size_t first = 0, last = 0;   ///< the lines of key = value
    std::size_t comment = std::string::npos;  ///< where a comment starts on the last line
    bool dotted = false;  ///< written as table.key = value (in the table it is under)
  };
  /// A name as TOML compares it: each dotted part without its quotes and the spaces around it
  /// (["modification"] is [modification]; simple quoted parts only).
  static std::string Unquoted(const std::string& name) {
    std::string out;
    std::size_t start = 0;
    while (start <= name.size()) {
      std::size_t dot = std::string::npos;
      for (std::size_t c = start, quote = 0; c < name.size(); ++c) {  // a dot outside quotes
        if ((name[c] == '"' || name[c] == '\'') && (quote == 0 || name[c] == static_cast<char>(quote))) quote = quote == 0 ? name[c] : 0;
        if (name[c] == '.' && quote == 0) {
          dot = c;
          break;
        }
      }
      std::string part = Trim(std::string_view(name).substr(start, dot == std::string::npos ? std::string::npos : dot - start));
      if (part.size() >= 2 && (part.front() == '"' || part.front() == '\'') && part.back() == part.front()) part = part.substr(1, part.size() - 2);
      out += (out.empty() ? "" : ".") + part;
      if (dot == std::string::npos) break;
      start = dot + 1;
    }
    return out;
  }
  struct TableAt {
    std::string name;       ///< "" for the keys before the first header
    std::size_t header = std::string::npos;  ///< its header line
    std::size_t end = 0;    ///< one past its last line
  };
  std::vector<std::string> lines;
  std::vector<KeyAt> keys;
  std::vector<TableAt> tables;

  explicit TomlLines(std::string_view text) {
    std::size_t start = 0;
    while (start < text.size()) {
      const std::size_t nl = text.find('\n', start);
      const std::size_t stop = nl == std::string_view::npos ? text.size() : nl;
      std::string line(text.substr(start, stop - start));
      if (!line.empty() && line.back() == '\r') line.pop_back();
      lines.push_back(std::move(line));
      start = stop + 1;
    }
    tables.push_back({"", std::string::npos, 0});
    enum class In { kNone, kBasic, kLiteral, kMultiBasic, kMultiLiteral } in = In::kNone;
    int depth = 0;
    KeyAt* open = nullptr;  // a key whose value has not ended yet
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const std::string& l = lines[i];
      const bool top = depth == 0 && in == In::kNone;
      std::size_t comment = std::string::npos;
      if (top) {
        const std::string t = Trim(l);
        if (!t.empty() && t[0] == '[') {
          const bool array = t.size() > 1 && t[1] == '[';
          const std::size_t close = t.find(']');
          tables.back().end = i;
          tables.push_back({Unquoted(Trim(std::string_view(t).substr(array ? 2 : 1, close == std::string::npos ? 0 : close - (array ? 2 : 1)))), i, 0});
        } else if (!t.empty() && t[0] != '#') {
          const std::size_t eq = t.find('=');
          std::string key = Unquoted(Trim(std::string_view(t).substr(0, eq == std::string::npos ? 0 : eq)));
          // A dotted key (modification.pin_radius_mm = ... at the root) is a key of the table it names.
          std::string table = tables.back().name;
          const std::size_t dot = key.rfind('.');
          bool dotted = false;
          if (dot != std::string::npos) {
            table = table.empty() ? key.substr(0, dot) : table + "." + key.substr(0, dot);
            key = key.substr(dot + 1);
            dotted = true;
          }
          keys.push_back({table, key, i, i, std::string::npos, dotted});
          open = &keys.back();
        }
      }
      // The characters: strings, comments and the depth of [ ] and { }.
      for (std::size_t c = 0; c < l.size(); ++c) {
        const auto at = [&](const char* s) { return l.compare(c, std::strlen(s), s) == 0; };
        switch (in) {
          case In::kNone:
            if (l[c] == '#') { comment = c; c = l.size(); break; }
            if (at("\"\"\"")) { in = In::kMultiBasic; c += 2; break; }
            if (at("'''")) { in = In::kMultiLiteral; c += 2; break; }
            if (l[c] == '"') { in = In::kBasic; break; }
            if (l[c] == '\'') { in = In::kLiteral; break; }
            if (l[c] == '[' || l[c] == '{') ++depth;
            if (l[c] == ']' || l[c] == '}') depth = std::max(0, depth - 1);
            break;
          case In::kBasic:
            if (l[c] == '\\') { ++c; break; }
            if (l[c] == '"') in = In::kNone;
            break;
          case In::kLiteral:
            if (l[c] == '\'') in = In::kNone;
            break;
          case In::kMultiBasic:
            if (l[c] == '\\') { ++c; break; }
            if (at("\"\"\"")) { in = In::kNone; c += 2; }
            break;
          case In::kMultiLiteral:
            if (at("'''")) { in = In::kNone; c += 2; }
            break;
        }
      }
      if (in == In::kBasic || in == In::kLiteral) in = In::kNone;  // a one-line string cannot span lines
      if (open != nullptr) {
        open->last = i;
        open->comment = comment;
        if (depth == 0 && in == In::kNone) open = nullptr;
      }
    }
    tables.back().end = lines.size();
  }

  const TableAt* Table(const std::string& name) const {
    for (const TableAt& t : tables) {
      if (t.name == name && (t.header != std::string::npos || name.empty())) return &t;
    }
    return nullptr;
  }
};

/// The deck's text with `edits` written in (a key replaced in place, its comment kept; a new key
/// after its table's last key; a new table at the end) and the tables `drop` left out.
std::string EditToml(std::string_view text, const std::vector<DeckEdit>& edits, const std::vector<std::string>& drop) {
  std::string current(text);
  for (const DeckEdit& e : edits) {
    TomlLines t(current);
    std::vector<std::string> out = t.lines;
    const auto key = std::find_if(t.keys.begin(), t.keys.end(), [&](const TomlLines::KeyAt& k) { return k.table == e.section && k.key == e.key; });
    const std::string line = TomlKey(e.key) + " = " + e.value;
    if (e.remove) {
      if (key != t.keys.end()) {
        out.erase(out.begin() + static_cast<std::ptrdiff_t>(key->first), out.begin() + static_cast<std::ptrdiff_t>(key->last) + 1);
      }
    } else if (key != t.keys.end()) {
      const std::string& last = t.lines[key->last];
      std::string comment;
      if (key->comment != std::string::npos) {
        std::size_t from = key->comment;
        while (from > 0 && (last[from - 1] == ' ' || last[from - 1] == '\t')) --from;
        comment = last.substr(from);
      }
      // The key as the deck writes it (a dotted or quoted key stays so), then the new value.
      const std::string& head = t.lines[key->first];
      const std::string written = key->dotted ? Trim(std::string_view(head).substr(0, head.find('='))) + " = " + e.value : line;
      out.erase(out.begin() + static_cast<std::ptrdiff_t>(key->first), out.begin() + static_cast<std::ptrdiff_t>(key->last) + 1);
      out.insert(out.begin() + static_cast<std::ptrdiff_t>(key->first), written + comment);
    } else if (const auto dotted = std::find_if(t.keys.rbegin(), t.keys.rend(),
                                                [&](const TomlLines::KeyAt& k) { return k.table == e.section && k.dotted; });
               dotted != t.keys.rend() && t.Table(e.section) == nullptr) {
      // The table exists only as dotted keys: one more beside its last.
      out.insert(out.begin() + static_cast<std::ptrdiff_t>(dotted->last) + 1,
                 TomlKey(e.section) + "." + line + (e.comment.empty() ? "" : "  # " + e.comment));
    } else if (const TomlLines::TableAt* table = t.Table(e.section)) {
      std::size_t after = table->header == std::string::npos ? 0 : table->header + 1;
      for (const TomlLines::KeyAt& k : t.keys) {
        if (k.table == e.section) after = std::max(after, k.last + 1);
      }
      out.insert(out.begin() + static_cast<std::ptrdiff_t>(after), line + (e.comment.empty() ? "" : "  # " + e.comment));
    } else {
      if (!out.empty() && !Trim(out.back()).empty()) out.emplace_back();
      out.push_back("[" + TomlKey(e.section) + "]");
      out.push_back(line + (e.comment.empty() ? "" : "  # " + e.comment));
    }
    current.clear();
    for (const std::string& l : out) current += l + "\n";
  }
  if (!drop.empty()) {
    TomlLines t(current);
    std::vector<bool> keep(t.lines.size(), true);
    for (std::size_t k = 0; k < t.tables.size(); ++k) {
      const TomlLines::TableAt& table = t.tables[k];
      if (table.header == std::string::npos) continue;
      const std::string root = table.name.substr(0, table.name.find('.'));
      if (std::find(drop.begin(), drop.end(), root) == drop.end()) continue;
      // The comment lines just above the next header are that table's.
      std::size_t end = table.end;
      if (k + 1 < t.tables.size()) {
        while (end > table.header + 1 && Trim(t.lines[end - 1]).rfind('#', 0) == 0) --end;
      }
      for (std::size_t i = table.header; i < end; ++i) keep[i] = false;
    }
    std::string kept;
    for (std::size_t i = 0; i < t.lines.size(); ++i) {
      if (keep[i]) kept += t.lines[i] + "\n";
    }
    current = kept;
  }
  return current;
}

}  // namespace

std::string WriteDeck(const Deck& deck, const std::vector<DeckEdit>& edits, const std::vector<std::string>& drop,
                      const std::string& header) {
  // The overrides first, as the deck that ran had them, then the edits.
  // In their order: a section removed and then set again (--unset S --set S.k=v) is the new keys.
  std::string body = deck.source.text;
  for (const std::string& text : deck.source.overrides) {
    const Override o = ParseOverride(text);
    if (o.remove && o.key.empty()) {
      body = EditToml(body, {}, {o.section});
    } else {
      body = EditToml(body, {{o.section, o.key, o.remove ? std::string() : GivenText(o.value), "--set", o.remove}}, {});
    }
  }
  std::string text = header;
  if (!text.empty() && text.back() != '\n') text += '\n';
  text += EditToml(body, edits, drop);

  // Read back: the same keys with the same values, the same discs and stage. An edit's value is
  // compared as the reader gives it back (100.0 reads back as 100).
  const auto as_given = [](const std::string& value) {
    try {
      std::istringstream stream("value = " + value + "\n");
      return GivenText(toml::parse(stream, "value").as_table().at("value"));
    } catch (const std::exception&) {
      return value;
    }
  };
  const std::string written_name = deck.name + " (as written)";
  const Deck back = ReadParsed(ParseText(text, written_name), written_name, {}, deck.source.directory, text, deck.source.memory);
  std::vector<std::tuple<std::string, std::string, std::string>> expected, written;
  for (const Deck::GivenKey& g : deck.given) {
    if (std::find(drop.begin(), drop.end(), g.section) != drop.end()) continue;
    std::string value = g.value;
    for (const DeckEdit& e : edits) {
      if (e.section == g.section && e.key == g.key) value = as_given(e.value);
    }
    expected.emplace_back(g.section, g.key, value);
  }
  for (const DeckEdit& e : edits) {
    if (std::none_of(deck.given.begin(), deck.given.end(), [&](const Deck::GivenKey& g) { return g.section == e.section && g.key == e.key; })) {
      expected.emplace_back(e.section, e.key, as_given(e.value));
    }
  }
  for (const Deck::GivenKey& g : back.given) written.emplace_back(g.section, g.key, g.value);
  std::sort(expected.begin(), expected.end());
  std::sort(written.begin(), written.end());
  if (expected != written) {
    std::string what = "a key";
    for (const auto& x : expected) {
      if (!std::binary_search(written.begin(), written.end(), x)) {
        what = fmt::format("[{}] {} = {}", std::get<0>(x), std::get<1>(x), std::get<2>(x));
        break;
      }
    }
    throw std::invalid_argument(fmt::format("deck '{}': the written deck does not read back as the deck: {} is missing or "
                                            "differs", deck.name, what));
  }
  if (back.disc_count() != deck.disc_count() || back.reducer.has_value() != deck.reducer.has_value()) {
    throw std::invalid_argument(fmt::format("deck '{}': the written deck does not read back with the deck's {} disc(s) and stage",
                                            deck.name, deck.disc_count()));
  }
  return text;
}

}  // namespace ltca::app

// Mutated decks: every command of the real `ltca` executable, run as a child process on several
// hundred decks derived from cases/ by one deterministic mutation each (a key deleted, a value of
// the wrong type, negative, zero, huge, tiny, nan/inf, an unknown or hostile key, a truncated file,
// a duplicated or renamed section, non-UTF-8 bytes, deep nesting). The output contract of issue 10:
//   exit 0  every position succeeded, stdout (--json -) is one JSON document;
//   exit 1  the run finished but something did not succeed: stdout is JSON with the statuses;
//   exit 2  bad input: stderr names the section ('[') or the mutated key.
// A signal, exit 3 or any other code, or a sanitizer report is a wrong answer. The work of a run is
// bounded by the deck, not by a clock (issue 55): every base deck is cut to kPositions crank
// positions and kStepsPerBranch torque levels per stiffness branch before it is mutated, so a run
// is a few solves unless the mutation itself asks for more (and the deck's limits bound that). A
// run still going after kHangGuard (over 20x the slowest run under the sanitizers) is killed and
// reported as "too slow", a failure of its own, apart from the wrong answers: it is a hang or a
// mutation that escapes the limits, or a machine far too loaded, never a verdict on the output.
// Every failure is written, deck and command, to mutated_decks/ in the build tree, and summarised
// here by class, with the first reproducer of each class; the summary also names the runs that took
// the most CPU time. Environment: LTCA_MUTANT_JOBS (children at once, default 2), LTCA_MUTANTS
// (decks, default 330).
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

extern char** environ;

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// The hang guard: with the work bounded, the slowest run takes 0.5 s of CPU in release (`ltca
// stiffness` of a stage deck with pin bending; 1.5 s of wall time on a loaded machine) and the
// sanitizers of the debug preset make it about 10x slower: 120 s is over 20x that. A run past it is
// "too slow", never a wrong answer.
constexpr auto kHangGuard = std::chrono::seconds(120);
constexpr int kMutants = 330;        // at least 300 decks; LTCA_MUTANTS overrides (e.g. a quick local run)
constexpr int kCompareEvery = 3;     // compare (4 solvers, Ipopt) on every third deck
constexpr int kPositions = 3;        // sweeps are cut to this many positions (except when mutated)
constexpr int kStepsPerBranch = 5;   // torque levels per stiffness branch (default 41; odd)

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void WriteFile(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// ---------------------------------------------------------------------------------------------
// Decks as lines: every deck in cases/ has one-line values, `[section]` headers and comments.

struct Line {
  std::string text;
  std::string section;  ///< the section it belongs to ("" before the first header)
  std::string key;      ///< "" for headers, comments and blank lines
  std::string value;    ///< the value text without a trailing comment
};

std::string Trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

std::vector<Line> SplitDeck(const std::string& text) {
  std::vector<Line> lines;
  std::istringstream in(text);
  std::string raw, section;
  while (std::getline(in, raw)) {
    Line line{raw, section, "", ""};
    const std::string t = Trim(raw);
    if (!t.empty() && t.front() == '[') {
      section = t.substr(1, t.find(']') - 1);
      line.section = section;
    } else if (!t.empty() && t.front() != '#' && t.find('=') != std::string::npos) {
      line.key = Trim(t.substr(0, t.find('=')));
      std::string value = t.substr(t.find('=') + 1);
      // A '#' outside a string ends the value.
      bool in_string = false;
      for (std::size_t i = 0; i < value.size(); ++i) {
        if (value[i] == '"') in_string = !in_string;
        if (value[i] == '#' && !in_string) {
          value = value.substr(0, i);
          break;
        }
      }
      line.value = Trim(value);
    }
    lines.push_back(line);
  }
  return lines;
}

std::string JoinDeck(const std::vector<Line>& lines) {
  std::string text;
  for (const auto& line : lines) text += line.text + "\n";
  return text;
}

/// The deck with `[section] key = value`: the key's line replaced, or added after the header, or a
/// new section at the end.
std::string SetKey(const std::string& text, const std::string& section, const std::string& key, const std::string& value) {
  auto lines = SplitDeck(text);
  bool has_section = false;
  for (auto& line : lines) {
    if (line.section == section) has_section = true;
    if (line.section == section && line.key == key) {
      line.text = key + " = " + value;
      line.value = value;
      return JoinDeck(lines);
    }
  }
  std::string out = JoinDeck(lines);
  if (has_section) {
    const auto at = out.find("[" + section + "]");
    out.insert(out.find('\n', at) + 1, key + " = " + value + "\n");
    return out;
  }
  return out + "\n[" + section + "]\n" + key + " = " + value + "\n";
}

/// The deck with its work bounded: the sweep cut to kPositions positions and the stiffness loop to
/// kStepsPerBranch torque levels per branch (the commands run here read no other count).
std::string BoundedWork(const std::string& text) {
  return SetKey(SetKey(text, "sweep", "positions", std::to_string(kPositions)), "stiffness", "steps_per_branch",
                std::to_string(kStepsPerBranch));
}

// ---------------------------------------------------------------------------------------------
// Mutations.

struct Mutant {
  std::string text;
  std::string origin;       ///< deck file in cases/
  std::string description;  ///< e.g. "pair.pin_count = -40 (negative)"
  std::string key;          ///< the key (or section) the error should name; "" if none
};

bool IsInteger(const std::string& v) {
  return !v.empty() && v.find_first_not_of("+-0123456789") == std::string::npos;
}
bool IsNumber(const std::string& v) {
  return !v.empty() && v.find_first_not_of("+-0123456789.eE") == std::string::npos;
}

// Keys the decks in cases/ may not carry, with hostile but well-formed values.
struct Insert {
  const char* section;
  const char* key;
  const char* value;
};
constexpr Insert kInserts[] = {
    {"geometry", "geometry_mode", "\"elements\""},
    {"geometry", "geometry_mode", "\"bogus\""},
    {"geometry", "width_slices", "2000000000"},
    {"geometry", "width_slices", "0"},
    {"geometry", "profile_elements", "2000000000"},
    {"geometry", "profile_elements", "-5"},
    {"geometry", "profile_elements", "3"},
    {"solver", "kinematics", "\"exact\""},
    {"solver", "kinematics", "\"sideways\""},
    {"solver", "name", "\"energy-qp\""},
    {"solver", "name", "\"compatibility\""},
    {"solver", "name", "\"nope\""},
    {"solver", "max_iterations", "0"},
    {"solver", "max_iterations", "2147483647"},
    {"solver", "torque_tolerance", "0.0"},
    {"solver", "torque_tolerance", "nan"},
    {"solver", "preset", "\"liu2021\""},
    {"solver", "preset", "\"other\""},
    {"solver", "nlopt_algorithm", "\"GN_NOT_AN_ALGORITHM\""},
    {"contact", "law", "\"linear\""},
    {"contact", "stiffness_n_per_mm2", "1e-300"},
    {"contact", "stiffness_n_per_mm2", "-1.0"},
    {"contact", "log_radius_cap_mm", "inf"},
    {"contact", "rho_convention", "\"weird\""},
    {"errors", "cumulative_pitch_deviation_mm", "[1e300]"},
    {"errors", "cumulative_pitch_deviation_mm", "[\"a\", 1]"},
    {"errors", "pin_circle_reading", "\"diameter\""},
    {"errors", "cycloid_profile_layer_mm", "1.0"},
    {"modification", "rotation_deg", "1e300"},
    {"modification", "rotation_deg", "-inf"},
    {"modification", "pin_radius_mm", "-1.0"},
    {"material", "pin_young_modulus_mpa", "0.0"},
    {"material", "pin_poisson_ratio", "0.5"},
    {"sweep", "crank_end_deg", "1e300"},
    {"sweep", "crank_start_deg", "nan"},
    {"sweep", "positions", "10000000"},
    {"sweep", "positions", "0"},
    {"sweep", "positions", "-1"},
    {"load", "torque_nm", "1e300"},
};

enum class Kind {
  kDelete, kWrongType, kNegative, kZero, kHuge, kTiny, kNan, kInf, kNegInf, kIntMax, kInt64Max,
  kEmptyValue, kUnknownKey, kUnknownSection, kInsert, kTruncate, kDuplicateSection,
  kSwapSections, kRenameSection, kNonUtf8, kDeepNesting, kDeepInlineTables, kDuplicateKey,
  kGarbageLine, kEmptyDeck, kPositions, kCount
};

Mutant Mutate(const std::string& origin, const std::string& base, Kind kind, std::mt19937_64& rng) {
  auto lines = SplitDeck(base);
  std::vector<std::size_t> keyed, headers;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (!lines[i].key.empty()) keyed.push_back(i);
    if (lines[i].key.empty() && Trim(lines[i].text).starts_with("[")) headers.push_back(i);
  }
  auto pick = [&](const std::vector<std::size_t>& from) {
    return from[std::uniform_int_distribution<std::size_t>(0, from.size() - 1)(rng)];
  };
  Mutant m{"", origin, "", ""};
  auto set_value = [&](std::size_t i, const std::string& value, const std::string& what) {
    m.key = lines[i].key;
    m.description = lines[i].section + "." + lines[i].key + " = " + value + " (" + what + ")";
    lines[i].text = lines[i].key + " = " + value;
    m.text = JoinDeck(lines);
  };
  switch (kind) {
    case Kind::kDelete: {
      const auto i = pick(keyed);
      m.key = lines[i].key;
      m.description = "deleted " + lines[i].section + "." + lines[i].key;
      lines.erase(lines.begin() + static_cast<std::ptrdiff_t>(i));
      m.text = JoinDeck(lines);
      break;
    }
    case Kind::kWrongType: {
      const auto i = pick(keyed);
      const std::string& v = lines[i].value;
      std::string w = "\"12\"";
      if (v.starts_with("\"")) w = (rng() % 2) ? "1.5" : "true";
      else if (v.starts_with("[")) w = "0.0";
      else if (IsInteger(v)) w = (rng() % 2) ? v + ".5" : "[1, 2]";
      else if (rng() % 2) w = "true";
      set_value(i, w, "wrong type");
      break;
    }
    case Kind::kNegative: {
      const auto i = pick(keyed);
      const std::string& v = lines[i].value;
      set_value(i, IsNumber(v) ? (v.starts_with("-") ? v.substr(1) + "e3" : "-" + v) : "-1", "negative");
      break;
    }
    case Kind::kZero: {
      const auto i = pick(keyed);
      set_value(i, IsInteger(lines[i].value) ? "0" : "0.0", "zero");
      break;
    }
    case Kind::kHuge: set_value(pick(keyed), "1e300", "huge"); break;
    case Kind::kTiny: set_value(pick(keyed), "1e-300", "tiny"); break;
    case Kind::kNan: set_value(pick(keyed), (rng() % 2) ? "nan" : "-nan", "nan"); break;
    case Kind::kInf: set_value(pick(keyed), "inf", "inf"); break;
    case Kind::kNegInf: set_value(pick(keyed), "-inf", "-inf"); break;
    case Kind::kIntMax: set_value(pick(keyed), "2147483647", "INT_MAX"); break;
    case Kind::kInt64Max: set_value(pick(keyed), "9223372036854775807", "INT64_MAX"); break;
    case Kind::kEmptyValue: set_value(pick(keyed), "\"\"", "empty string"); break;
    case Kind::kUnknownKey: {
      const auto h = pick(headers);
      m.key = "bogus_key";
      m.description = "unknown key [" + lines[h].section + "] bogus_key";
      lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(h) + 1, Line{"bogus_key = 1", "", "", ""});
      m.text = JoinDeck(lines);
      break;
    }
    case Kind::kUnknownSection:
      m.key = "bogus_section";
      m.description = "unknown section [bogus_section]";
      m.text = base + "\n[bogus_section]\nx = 1\n";
      break;
    case Kind::kInsert: {
      const auto& ins = kInserts[rng() % std::size(kInserts)];
      m.key = ins.key;
      m.description = std::string("set ") + ins.section + "." + ins.key + " = " + ins.value;
      // Into the existing section, or a new one at the end.
      std::string header = std::string("[") + ins.section + "]";
      std::size_t at = lines.size();
      for (std::size_t i = 0; i < lines.size(); ++i) {
        if (Trim(lines[i].text) == header) at = i;
      }
      if (at == lines.size()) {
        lines.push_back(Line{header, ins.section, "", ""});
        lines.push_back(Line{std::string(ins.key) + " = " + ins.value, ins.section, ins.key, ins.value});
      } else {
        // Replace the key if present, else add it after the header.
        bool replaced = false;
        for (auto& line : lines) {
          if (line.section == ins.section && line.key == ins.key) {
            line.text = std::string(ins.key) + " = " + ins.value;
            replaced = true;
          }
        }
        if (!replaced)
          lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(at) + 1,
                       Line{std::string(ins.key) + " = " + ins.value, ins.section, ins.key, ins.value});
      }
      m.text = JoinDeck(lines);
      break;
    }
    case Kind::kTruncate: {
      const auto cut = std::uniform_int_distribution<std::size_t>(1, base.size() - 1)(rng);
      m.description = "truncated after " + std::to_string(cut) + " of " + std::to_string(base.size()) + " bytes";
      m.text = base.substr(0, cut);
      break;
    }
    case Kind::kDuplicateSection: {
      const auto h = pick(headers);
      std::size_t end = h + 1;
      while (end < lines.size() && !Trim(lines[end].text).starts_with("[")) ++end;
      m.key = lines[h].section;
      m.description = "duplicated section [" + lines[h].section + "]";
      std::vector<Line> copy(lines.begin() + static_cast<std::ptrdiff_t>(h), lines.begin() + static_cast<std::ptrdiff_t>(end));
      lines.insert(lines.end(), copy.begin(), copy.end());
      m.text = JoinDeck(lines);
      break;
    }
    case Kind::kSwapSections: {
      const auto a = pick(headers);
      auto b = pick(headers);
      if (a == b) b = headers[(std::find(headers.begin(), headers.end(), a) - headers.begin() + 1) % headers.size()];
      m.description = "swapped section names [" + lines[a].section + "] and [" + lines[b].section + "]";
      std::swap(lines[a].text, lines[b].text);
      m.text = JoinDeck(lines);
      break;
    }
    case Kind::kRenameSection: {
      const auto h = pick(headers);
      static const char* kNames[] = {"pair", "load", "material", "sweep", "solver", "contact", "errors", "case"};
      const std::string name = kNames[rng() % std::size(kNames)];
      m.description = "section [" + lines[h].section + "] renamed [" + name + "]";
      lines[h].text = "[" + name + "]";
      m.text = JoinDeck(lines);
      break;
    }
    case Kind::kNonUtf8: {
      const auto i = pick(keyed);
      const std::string bad = (rng() % 2) ? "\xff\xfe" : "\xc3\x28\x80";
      switch (rng() % 4) {
        case 0: lines[i].text = lines[i].key + " = \"" + bad + "\""; break;  // in a string value
        case 3: lines[i].text = lines[i].key + " = '\xcb'"; break;          // in a literal string
        case 1: lines[i].text += " # " + bad; break;                          // in a comment
        default: lines[i].text = lines[i].key + bad + " = 1"; break;         // in a key
      }
      m.key = lines[i].key;
      m.description = "non-UTF-8 bytes at " + lines[i].section + "." + lines[i].key;
      m.text = JoinDeck(lines);
      break;
    }
    case Kind::kDeepNesting: {
      const std::size_t depth = (rng() % 2) ? 10000 : 200;
      const auto i = pick(keyed);
      set_value(i, std::string(depth, '[') + std::string(depth, ']'), "");
      m.description = lines[i].section + "." + lines[i].key + " = an array nested " + std::to_string(depth) + " deep";
      break;
    }
    case Kind::kDeepInlineTables: {
      const std::size_t depth = (rng() % 2) ? 10000 : 200;
      std::string v;
      for (std::size_t d = 0; d < depth; ++d) v += "{a=";
      v += "1";
      for (std::size_t d = 0; d < depth; ++d) v += "}";
      m.key = "deep";
      m.description = "inline table nested " + std::to_string(depth) + " deep";
      m.text = "deep = " + v + "\n" + base;
      break;
    }
    case Kind::kDuplicateKey: {
      const auto i = pick(keyed);
      m.key = lines[i].key;
      m.description = "duplicated key " + lines[i].section + "." + lines[i].key;
      lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(i), lines[i]);
      m.text = JoinDeck(lines);
      break;
    }
    case Kind::kGarbageLine: {
      static const char* kGarbage[] = {"= 3", "key = ", "[", "[[pair]]", "a.b.c = 1", "x = 1979-05-27T07:32:00Z", "\"\\u0000\" = 1"};
      const std::string g = kGarbage[rng() % std::size(kGarbage)];
      const auto i = pick(keyed);
      m.description = "garbage line '" + g + "' after " + lines[i].section + "." + lines[i].key;
      lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(i) + 1, Line{g, "", "", ""});
      m.text = JoinDeck(lines);
      break;
    }
    case Kind::kEmptyDeck:
      m.key = "case";
      m.description = (rng() % 2) ? "empty deck" : "comments only";
      m.text = m.description == "empty deck" ? "" : "# nothing\n";
      break;
    case Kind::kPositions: {
      static const char* kValues[] = {"0", "-3", "1", "2", "2147483647", "1e300", "nan", "\"5\"", "100000000"};
      const std::string v = kValues[rng() % std::size(kValues)];
      for (std::size_t i = 0; i < lines.size(); ++i) {
        if (lines[i].section == "sweep" && lines[i].key == "positions") set_value(i, v, "sweep positions");
      }
      break;
    }
    case Kind::kCount: break;
  }
  return m;
}

// ---------------------------------------------------------------------------------------------
// Running the executable with a timeout.

struct Job {
  std::size_t mutant;
  std::vector<std::string> args;
  fs::path out, err;
  Clock::duration hang_guard = kHangGuard;
  pid_t pid = -1;
  Clock::time_point start;
  bool too_slow = false;  ///< killed by the hang guard
  int status = 0;
  double seconds = 0.0;      ///< wall time, reported only
  double cpu_seconds = 0.0;  ///< user + system time of the child, reported only
};

void Spawn(Job& job) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, job.out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, job.err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<char*> argv;
  for (auto& a : job.args) argv.push_back(a.data());
  argv.push_back(nullptr);
  // A sanitizer report exits with its own code (not 1, which the contract gives a meaning).
  std::vector<std::string> env_text;
  for (char** e = environ; *e != nullptr; ++e) {
    const std::string v = *e;
    if (!v.starts_with("ASAN_OPTIONS=") && !v.starts_with("UBSAN_OPTIONS=")) env_text.push_back(v);
  }
  env_text.emplace_back("ASAN_OPTIONS=exitcode=86:detect_leaks=1");
  env_text.emplace_back("UBSAN_OPTIONS=exitcode=87:print_stacktrace=1:halt_on_error=1");
  std::vector<char*> envp;
  for (auto& e : env_text) envp.push_back(e.data());
  envp.push_back(nullptr);
  job.start = Clock::now();
  const int rc = posix_spawn(&job.pid, argv[0], &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  REQUIRE_MESSAGE(rc == 0, "posix_spawn " << argv[0] << " failed: " << rc);
}

/// Runs every job, `parallel` at a time; polls with WNOHANG and kills a job past its hang guard.
void RunAll(std::vector<Job>& jobs, int parallel) {
  std::size_t next = 0;
  std::vector<Job*> running;
  while (next < jobs.size() || !running.empty()) {
    while (next < jobs.size() && static_cast<int>(running.size()) < parallel) {
      Spawn(jobs[next]);
      running.push_back(&jobs[next++]);
    }
    for (auto it = running.begin(); it != running.end();) {
      Job& job = **it;
      int status = 0;
      rusage usage{};
      const pid_t done = wait4(job.pid, &status, WNOHANG, &usage);
      if (done == job.pid) {
        job.status = status;
        job.seconds = std::chrono::duration<double>(Clock::now() - job.start).count();
        job.cpu_seconds = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                          1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
        it = running.erase(it);
        continue;
      }
      if (!job.too_slow && Clock::now() - job.start > job.hang_guard) {
        job.too_slow = true;
        kill(job.pid, SIGKILL);  // reaped on the next poll
      }
      ++it;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

std::string HangGuardText(const Job& job) {
  std::ostringstream s;
  s << std::chrono::duration<double>(job.hang_guard).count() << " s";
  return s.str();
}

// ---------------------------------------------------------------------------------------------
// Judging an outcome.

void CollectStatuses(const nlohmann::json& j, std::vector<std::string>& statuses) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (it.key() == "status" && it.value().is_string()) statuses.push_back(it.value().get<std::string>());
      CollectStatuses(it.value(), statuses);
    }
  } else if (j.is_array()) {
    for (const auto& e : j) CollectStatuses(e, statuses);
  }
}

/// The JSON document on stdout: the whole of it, or (a contract failure of its own, noted in
/// `verdicts`) a document that starts on a line of its own after some text.
bool ParseStdout(const std::string& out, int code, nlohmann::json& j, std::vector<std::string>& verdicts) {
  const std::string prefix = "exit " + std::to_string(code) + ": ";
  try {
    j = nlohmann::json::parse(out);
    return true;
  } catch (const nlohmann::json::exception&) {
  }
  for (std::size_t at = out.find("\n{"); at != std::string::npos; at = out.find("\n{", at + 1)) {
    try {
      j = nlohmann::json::parse(out.substr(at + 1));
      verdicts.push_back(prefix + "--json - prints text before the JSON document");
      return true;
    } catch (const nlohmann::json::exception&) {
    }
  }
  verdicts.push_back(prefix + "stdout of --json - holds no JSON document");
  return false;
}

/// Empty when the outcome keeps the contract, else every failure class it shows.
std::vector<std::string> Judge(const Job& job, const Mutant& m, const std::string& out, const std::string& err) {
  std::vector<std::string> verdicts;
  if (err.find("AddressSanitizer") != std::string::npos || err.find("LeakSanitizer") != std::string::npos)
    verdicts.push_back("sanitizer: AddressSanitizer report");
  if (err.find("runtime error:") != std::string::npos) verdicts.push_back("sanitizer: UndefinedBehaviorSanitizer report");
  if (!verdicts.empty()) return verdicts;  // its exit code (86, 87: see Spawn) says no more
  if (job.too_slow) {
    verdicts.push_back("too slow: killed by the hang guard");
    return verdicts;
  }
  if (WIFSIGNALED(job.status)) {
    verdicts.push_back("crash: signal " + std::to_string(WTERMSIG(job.status)));
    return verdicts;
  }
  const int code = WEXITSTATUS(job.status);
  const std::string& command = job.args[1];
  nlohmann::json j;
  std::vector<std::string> statuses;
  switch (code) {
    case 0:
      if (ParseStdout(out, code, j, verdicts)) {
        CollectStatuses(j, statuses);
        for (const auto& s : statuses) {
          if (!s.starts_with("success")) {
            verdicts.push_back("exit 0: " + command + " reports status '" + s + "'");
            break;
          }
        }
      }
      break;
    case 1:
      if (ParseStdout(out, code, j, verdicts)) {
        CollectStatuses(j, statuses);
        if (statuses.empty()) verdicts.push_back("exit 1: the JSON carries no status");
        else if (std::all_of(statuses.begin(), statuses.end(), [](const auto& s) { return s.starts_with("success"); }))
          verdicts.push_back("exit 1: every status is success");
      }
      break;
    case 2:
      if (err.empty()) verdicts.push_back("exit 2: nothing on stderr");
      else if (err.find('[') == std::string::npos && (m.key.empty() || err.find(m.key) == std::string::npos))
        verdicts.push_back("exit 2: the message names no section or key");
      break;
    default: verdicts.push_back("exit " + std::to_string(code)); break;
  }
  return verdicts;
}

}  // namespace

TEST_CASE("cli: the mutated-deck judge flags a crash, a hang (too slow, apart from the wrong answers), exit 3, text before JSON, a failed status under exit 0 and an exit 2 naming nothing") {
  const fs::path dir = std::string(LTCA_MUTANT_DIR) + "_judge";  // ctest may run the other test at once
  fs::create_directories(dir);
  const Mutant m{"", "", "", "pin_count"};
  struct Probe {
    std::string script;
    std::string verdict;  // "" = keeps the contract
  };
  const std::vector<Probe> probes = {
      {"kill -SEGV $$", "crash: signal 11"},
      {"sleep 600", "too slow: killed by the hang guard"},
      {"exit 3", "exit 3"},
      {"echo table; echo '{\"status\": \"success\"}'", "exit 0: --json - prints text before the JSON document"},
      {"echo '{\"p\": [{\"status\": \"max-iterations\"}]}'", "exit 0: probe reports status 'max-iterations'"},
      {"echo '{\"status\": \"success\"}'; exit 1", "exit 1: every status is success"},
      {"echo 'bad value' >&2; exit 2", "exit 2: the message names no section or key"},
      {"echo '{\"status\": \"law-cannot-carry\"}'; exit 1", ""},
      {"echo '[pair] pin_count = -1: expected' >&2; exit 2", ""},
      {"echo '{\"status\": \"success\"}'", ""},
  };
  std::vector<Job> jobs;
  for (std::size_t i = 0; i < probes.size(); ++i) {
    Job job;
    job.args = {"/bin/sh", "-c", probes[i].script, "probe"};
    job.out = dir / ("p" + std::to_string(i) + ".out");
    job.err = dir / ("p" + std::to_string(i) + ".err");
    jobs.push_back(job);
  }
  jobs[1].hang_guard = std::chrono::milliseconds(200);  // the hang: its guard short, the others' the default
  RunAll(jobs, 2);
  for (std::size_t i = 0; i < probes.size(); ++i) {
    Job job = jobs[i];
    job.args = {"/bin/sh", "probe"};  // the judge names the command by args[1]
    const auto verdicts = Judge(job, m, ReadFile(job.out), ReadFile(job.err));
    CAPTURE(probes[i].script);
    if (probes[i].verdict.empty()) CHECK(verdicts.empty());
    else CHECK((!verdicts.empty() && verdicts.front() == probes[i].verdict));
  }
  fs::remove_all(dir);
}

TEST_CASE("cli: every command on 330 mutated decks from cases/ succeeds, exits 1 with statuses, or exits 2 naming the key") {
  const fs::path exe = LTCA_EXE;
  const fs::path dir = LTCA_MUTANT_DIR;
  fs::remove_all(dir);
  fs::create_directories(dir / "work");
  // Decks name data files relative to their directory ([errors] profile_measured_csv =
  // "data/..."): the mutants are written to work/, so the data goes beside them.
  if (fs::exists(fs::path(LTCA_CASES_DIR) / "data")) {
    fs::copy(fs::path(LTCA_CASES_DIR) / "data", dir / "work" / "data", fs::copy_options::recursive);
  }

  // The bases: every deck in cases/, its work bounded (BoundedWork), in a fixed order.
  std::vector<std::pair<std::string, std::string>> bases;
  for (const auto& entry : fs::recursive_directory_iterator(LTCA_CASES_DIR)) {
    if (entry.path().extension() == ".toml")
      bases.emplace_back(fs::relative(entry.path(), LTCA_CASES_DIR).string(), BoundedWork(ReadFile(entry.path())));
  }
  std::sort(bases.begin(), bases.end());
  REQUIRE(bases.size() >= 20);

  std::mt19937_64 rng(20240610);
  std::vector<Mutant> mutants;
  const char* count_env = std::getenv("LTCA_MUTANTS");
  const int count = count_env != nullptr ? std::max(1, std::atoi(count_env)) : kMutants;
  for (int i = 0; i < count; ++i) {
    const auto& [origin, base] = bases[rng() % bases.size()];
    const auto kind = static_cast<Kind>(i % static_cast<int>(Kind::kCount));  // every kind, in turn
    Mutant m = Mutate(origin, base, kind, rng);
    if (m.text.empty() && kind != Kind::kEmptyDeck) m = Mutate(origin, base, Kind::kDelete, rng);
    mutants.push_back(std::move(m));
  }
  const std::size_t kinds_covered = static_cast<std::size_t>(Kind::kCount);
  if (count_env == nullptr) CHECK(mutants.size() >= 300);

  std::vector<Job> jobs;
  for (std::size_t i = 0; i < mutants.size(); ++i) {
    const fs::path deck = dir / "work" / ("m" + std::to_string(i) + ".toml");
    WriteFile(deck, mutants[i].text);
    std::vector<std::vector<std::string>> commands = {
        {"geometry"}, {"backlash"}, {"mesh"}, {"solve"}};
    if (i % kCompareEvery == 0) commands.push_back({"compare"});
    if (i % kCompareEvery == 1) commands.push_back({"stiffness"});  // issue 13: the torque loop
    for (auto& c : commands) {
      Job job;
      job.mutant = i;
      job.args = {exe.string(), c[0], deck.string(), "--json", "-"};
      std::string stem = "m";  // built by appending: GCC 12 flags "m" + std::string(...) with a false -Wrestrict
      stem += std::to_string(i) + "_" + c[0];
      job.out = dir / "work" / (stem + ".out");
      job.err = dir / "work" / (stem + ".err");
      jobs.push_back(std::move(job));
    }
  }
  const char* parallel_env = std::getenv("LTCA_MUTANT_JOBS");
  const int parallel = parallel_env != nullptr ? std::max(1, std::atoi(parallel_env)) : 2;
  const auto t0 = Clock::now();
  RunAll(jobs, parallel);
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();

  // Judge, and keep every failure for inspection: wrong answers and runs too slow apart.
  std::map<std::string, std::vector<const Job*>> classes;
  std::size_t wrong = 0, too_slow = 0;
  double slowest = 0.0;
  std::map<std::string, double> by_command, cpu_by_command;
  std::vector<const Job*> by_cpu;
  for (const auto& job : jobs) {
    if (!job.too_slow) slowest = std::max(slowest, job.seconds);
    by_cpu.push_back(&job);
    const Mutant& m = mutants[job.mutant];
    const std::string out = ReadFile(job.out), err = ReadFile(job.err);
    by_command[job.args[1]] += job.seconds;
    cpu_by_command[job.args[1]] += job.cpu_seconds;
    const auto verdicts = Judge(job, m, out, err);
    if (verdicts.empty()) continue;
    ++(job.too_slow ? too_slow : wrong);
    std::string verdict;
    for (const auto& v : verdicts) {
      classes[v].push_back(&job);
      verdict += (verdict.empty() ? "" : "; ") + v;
    }
    const std::string stem = "fail_m" + std::to_string(job.mutant) + "_" + job.args[1];
    WriteFile(dir / (stem + ".toml"), m.text);
    std::ostringstream report;
    report << "failure: " << verdict << "\nmutation: " << m.description << " (from cases/" << m.origin
           << ")\ncommand: ltca " << job.args[1] << " " << (dir / (stem + ".toml")).string()
           << " --json -\nstatus: " << (job.too_slow ? "killed by the hang guard after " + HangGuardText(job) : WIFSIGNALED(job.status) ? "signal " + std::to_string(WTERMSIG(job.status)) : "exit " + std::to_string(WEXITSTATUS(job.status)))
           << "\n--- stderr (first 2000 bytes)\n" << err.substr(0, 2000) << "\n--- stdout (first 2000 bytes)\n" << out.substr(0, 2000) << "\n";
    WriteFile(dir / (stem + ".txt"), report.str());
  }
  std::sort(by_cpu.begin(), by_cpu.end(), [](const Job* a, const Job* b) { return a->cpu_seconds > b->cpu_seconds; });
  fs::remove_all(dir / "work");

  std::ostringstream summary;
  summary << mutants.size() << " mutated decks (" << kinds_covered << " kinds of mutation), " << jobs.size()
          << " runs in " << wall << " s (slowest finished run " << slowest << " s; child seconds by command:";
  for (const auto& [command, seconds] : by_command) summary << " " << command << " " << seconds;
  summary << "; child CPU seconds by command:";
  for (const auto& [command, seconds] : cpu_by_command) summary << " " << command << " " << seconds;
  summary << "), " << wrong << " runs with a wrong answer and " << too_slow << " runs too slow (killed by the hang guard, "
          << HangGuardText(jobs.front()) << "), in " << classes.size() << " classes; each failing deck and its output is in "
          << dir.string() << "\n";
  for (const auto& [verdict, list] : classes) {
    const Job& first = *list.front();
    summary << "  " << list.size() << " x " << verdict << "\n      e.g. ltca " << first.args[1] << " "
            << (dir / ("fail_m" + std::to_string(first.mutant) + "_" + first.args[1] + ".toml")).string()
            << " --json -   [" << mutants[first.mutant].description << ", from cases/" << mutants[first.mutant].origin << "]\n";
  }
  summary << "  the runs of most CPU time:\n";
  for (std::size_t k = 0; k < std::min<std::size_t>(3, by_cpu.size()); ++k) {
    const Job& job = *by_cpu[k];
    summary << "    " << job.cpu_seconds << " s CPU (" << job.seconds << " s wall): ltca " << job.args[1] << " ["
            << mutants[job.mutant].description << ", from cases/" << mutants[job.mutant].origin << "]\n";
  }
  MESSAGE(summary.str());
  WriteFile(dir / "summary.txt", summary.str());
  CHECK_MESSAGE(wrong == 0, "wrong answers: " << summary.str());
  // Apart: a run the hang guard killed says nothing about its answer (rerun its deck alone).
  CHECK_MESSAGE(too_slow == 0, "too slow, not a wrong answer: " << summary.str());
}

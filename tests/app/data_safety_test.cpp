// Nothing the user has is ever lost: the real `ltca` executable, run as a user runs it, must never
// replace a file it reads (the deck, its measured trace, through a symbolic or a hard link), must
// leave every existing file as it was when any part of the run fails (a second output that cannot
// be written, Ctrl-C), must not replace a folder of the user's with a report, and the deck it writes
// must read back as the deck (comments and an empty [second_disc] kept). Each scenario failed on
// the code before this suite (the deck was replaced with exit 0, keep.json was replaced with exit 3,
// the report wrote over index.html, Ctrl-C left .x.ltca-* files, --write-deck dropped
// [second_disc]). The MPI scenarios (a rank that fails ends every rank) are ctest commands in
// tests/CMakeLists.txt, registered where MPI is built.
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/app/deck.hpp"
#include "output.hpp"

namespace {

namespace fs = std::filesystem;

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void WriteFile(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

/// A fresh folder of this test's own under the system's temporary folder, removed at the end.
struct Scratch {
  fs::path dir;
  Scratch() {
    std::string pattern = (fs::temp_directory_path() / "ltca-data-safety-XXXXXX").string();
    REQUIRE(mkdtemp(pattern.data()) != nullptr);
    dir = pattern;
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
  fs::path operator/(const std::string& name) const { return dir / name; }
  /// The names of the folder's files that start with '.' (temporaries left behind).
  std::vector<std::string> Hidden(const fs::path& folder = {}) const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(folder.empty() ? dir : folder)) {
      const std::string name = e.path().filename().string();
      if (name[0] == '.' && name != ".ltca-report") names.push_back(name);
    }
    return names;
  }
};

/// Runs `ltca ARGS` in `dir` with the output streams discarded; its exit code (-signal when killed).
int Ltca(const fs::path& dir, const std::string& args) {
  const std::string command = "cd '" + dir.string() + "' && '" LTCA_EXE "' " + args + " > /dev/null 2> ltca-stderr.txt";
  const int status = std::system(command.c_str());
  if (WIFSIGNALED(status)) return -WTERMSIG(status);
  return WEXITSTATUS(status);
}

std::string Stderr(const Scratch& s) { return ReadFile(s / "ltca-stderr.txt"); }

/// Starts `ltca ARGS` in `dir` as a child process with its output streams discarded; `prepare` runs
/// in the child just before the exec.
pid_t StartLtca(const fs::path& dir, const std::vector<std::string>& args, const std::function<void()>& prepare = {}) {
  const std::string folder = dir.string();
  std::vector<char*> argv = {const_cast<char*>(LTCA_EXE)};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid != 0) return pid;
  if (chdir(folder.c_str()) != 0) _exit(127);
  if (prepare) prepare();
  const int null = ::open("/dev/null", O_WRONLY);
  dup2(null, 1);
  dup2(null, 2);
  execv(LTCA_EXE, argv.data());
  _exit(127);
}

/// Starts `ltca solve <Liu Table 1> --set sweep.positions=POSITIONS OPTION FILE` (StartLtca).
pid_t StartSolve(const fs::path& dir, const char* positions, const char* option, const char* file,
                 const std::function<void()>& prepare = {}) {
  return StartLtca(dir, {"solve", LTCA_CASES_DIR "/liu2021_table1.toml", "--set", std::string("sweep.positions=") + positions, option, file},
                   prepare);
}

const std::string kTable1 = ReadFile(LTCA_CASES_DIR "/liu2021_table1.toml");
constexpr const char* kFew = " --set sweep.positions=3";

}  // namespace

TEST_CASE("app: an output that is the deck is refused with exit 2 and the deck is kept (--json, --csv, --svg, the default job)") {
  Scratch s;
  WriteFile(s / "my.toml", kTable1);
  for (const std::string option : {"--json", "--csv", "--svg"}) {
    CAPTURE(option);
    CHECK(Ltca(s.dir, "solve my.toml" + std::string(kFew) + " " + option + " my.toml") == 2);
    CHECK(Stderr(s).find(option + " my.toml") != std::string::npos);
    CHECK(Stderr(s).find("the deck") != std::string::npos);
    CHECK(ReadFile(s / "my.toml") == kTable1);
  }
  CHECK(Ltca(s.dir, std::string("my.toml") + kFew + " --json ./my.toml") == 2);
  CHECK(ReadFile(s / "my.toml") == kTable1);
  CHECK(Ltca(s.dir, std::string("geometry my.toml --csv ") + (s / "my.toml").string()) == 2);
  CHECK(ReadFile(s / "my.toml") == kTable1);
  CHECK(s.Hidden().empty());
}

TEST_CASE("app: an output through a symbolic link or a hard link to the deck is refused and the deck is kept") {
  Scratch s;
  WriteFile(s / "my.toml", kTable1);
  fs::create_symlink("my.toml", s / "link.json");
  fs::create_hard_link(s / "my.toml", s / "hard.json");
  CHECK(Ltca(s.dir, std::string("solve my.toml") + kFew + " --json link.json") == 2);
  CHECK(Ltca(s.dir, std::string("solve my.toml") + kFew + " --json hard.json") == 2);
  CHECK(Ltca(s.dir, std::string("solve link.json") + kFew + " --csv my.toml") == 2);  // the deck read through the link
  CHECK(ReadFile(s / "my.toml") == kTable1);
  CHECK(fs::is_symlink(s / "link.json"));
  CHECK(fs::hard_link_count(s / "my.toml") == 2);
}

TEST_CASE("app: an output that is the measured trace the deck reads is refused and the trace is kept") {
  Scratch s;
  fs::create_directory(s / "data");
  const std::string trace = ReadFile(LTCA_CASES_DIR "/data/measured_profile.csv");
  WriteFile(s / "data" / "measured_profile.csv", trace);
  WriteFile(s / "measured.toml", ReadFile(LTCA_CASES_DIR "/measured_profile.toml"));
  CHECK(Ltca(s.dir, std::string("solve measured.toml") + kFew + " --csv data/measured_profile.csv") == 2);
  CHECK(Stderr(s).find("a file the deck reads") != std::string::npos);
  CHECK(ReadFile(s / "data" / "measured_profile.csv") == trace);
  // Not an input: written.
  CHECK(Ltca(s.dir, std::string("solve measured.toml") + kFew + " --csv data/solve.csv") == 0);
  CHECK(fs::file_size(s / "data" / "solve.csv") > 0);
}

TEST_CASE("app: ltca optimise --write-deck onto its own deck is refused before the search") {
  Scratch s;
  const std::string deck = ReadFile(LTCA_CASES_DIR "/liu2021_optimise.toml");
  WriteFile(s / "opt.toml", deck);
  CHECK(Ltca(s.dir, "optimise opt.toml --write-deck opt.toml") == 2);
  CHECK(Stderr(s).find("--write-deck opt.toml") != std::string::npos);
  CHECK(ReadFile(s / "opt.toml") == deck);
}

TEST_CASE("app: a run whose second output fails leaves the first output's existing file as it was (exit 3)") {
  Scratch s;
  WriteFile(s / "keep.json", "KEEP");
  WriteFile(s / "keep.csv", "KEEP");
  CHECK(Ltca(s.dir, std::string("solve ") + LTCA_CASES_DIR "/liu2021_table1.toml" + kFew +
                        " --json keep.json --csv keep.csv --svg /dev/full") == 3);
  CHECK(ReadFile(s / "keep.json") == "KEEP");
  CHECK(ReadFile(s / "keep.csv") == "KEEP");
  CHECK(s.Hidden().empty());
  // The same run with a writable figure replaces all three.
  CHECK(Ltca(s.dir, std::string("solve ") + LTCA_CASES_DIR "/liu2021_table1.toml" + kFew +
                        " --json keep.json --csv keep.csv --svg keep.svg") == 0);
  CHECK(ReadFile(s / "keep.json").rfind("{", 0) == 0);
  CHECK(ReadFile(s / "keep.csv") != "KEEP");
  CHECK(fs::file_size(s / "keep.svg") > 0);
  CHECK(s.Hidden().empty());
}

TEST_CASE("app: an output through a dangling symbolic link is written where the link points, the link kept") {
  Scratch s;
  fs::create_directory(s / "out");
  fs::create_symlink("out/target.json", s / "dangling.json");
  CHECK(Ltca(s.dir, std::string("solve ") + LTCA_CASES_DIR "/liu2021_table1.toml" + kFew + " --json dangling.json") == 0);
  CHECK(fs::is_symlink(s / "dangling.json"));
  CHECK(ReadFile(s / "out" / "target.json").rfind("{", 0) == 0);
}

TEST_CASE("app: ltca report refuses a folder of the user's files, replaces its own, and --force replaces any") {
  Scratch s;
  const std::string report = std::string("report ") + LTCA_CASES_DIR "/liu2021_table1.toml" + kFew;
  fs::create_directory(s / "mine");
  WriteFile(s / "mine" / "index.html", "my page");
  WriteFile(s / "mine" / "solve.json", "my data");
  CHECK(Ltca(s.dir, report + " -o mine") == 2);
  CHECK(Stderr(s).find("--force") != std::string::npos);
  CHECK(ReadFile(s / "mine" / "index.html") == "my page");
  CHECK(ReadFile(s / "mine" / "solve.json") == "my data");
  // A new folder, then the same folder again: the report's own.
  CHECK(Ltca(s.dir, report + " -o new") == 0);
  CHECK(fs::exists(s / "new" / ".ltca-report"));
  CHECK(ReadFile(s / "new" / "index.html").find("<html") != std::string::npos);
  WriteFile(s / "new" / "stale.txt", "from before");
  CHECK(Ltca(s.dir, report + " -o new") == 0);
  CHECK_FALSE(fs::exists(s / "new" / "stale.txt"));  // replaced whole, not mixed
  CHECK(Ltca(s.dir, report + " -o mine --force") == 0);
  CHECK(ReadFile(s / "mine" / "index.html").find("<html") != std::string::npos);
  CHECK(s.Hidden().empty());
  // A deck inside the folder the report would replace is refused.
  WriteFile(s / "new" / "deck.toml", kTable1);
  CHECK(Ltca(s.dir, std::string("report new/deck.toml") + kFew + " -o new") == 2);
  CHECK(ReadFile(s / "new" / "deck.toml") == kTable1);
}

TEST_CASE("app: a report that fails part way leaves the folder it would replace as it was") {
  Scratch s;
  REQUIRE(Ltca(s.dir, std::string("report ") + LTCA_CASES_DIR "/liu2021_table1.toml" + kFew + " -o out") == 0);
  const std::string page = ReadFile(s / "out" / "index.html"), solve = ReadFile(s / "out" / "solve.json");
  // The tolerance part refuses --threads 5000 after the geometry, the solve and the loop have
  // written their files into the report's folder.
  CHECK(Ltca(s.dir, std::string("report ") + LTCA_CASES_DIR "/liu2021_tolerances.toml" + kFew + " --threads 5000 -o out") == 2);
  CHECK(Stderr(s).find("--threads 5000") != std::string::npos);
  CHECK(ReadFile(s / "out" / "index.html") == page);
  CHECK(ReadFile(s / "out" / "solve.json") == solve);  // the earlier report's, not a mix
  CHECK_FALSE(fs::exists(s / "out" / "tolerance.json"));
  CHECK(s.Hidden().empty());
}

TEST_CASE("app: Ctrl-C (SIGINT) and SIGTERM remove the run's temporary files and leave the existing output as it was") {
  for (const int signal : {SIGINT, SIGTERM}) {
    CAPTURE(signal);
    Scratch s;
    WriteFile(s / "out.json", "KEEP");
    const pid_t pid = StartSolve(s.dir, "1000000", "--json", "out.json");
    REQUIRE(pid >= 0);
    // Wait for the temporary file (the run has started writing), at most 60 s.
    bool started = false;
    for (int i = 0; i < 6000 && !started; ++i) {
      started = !s.Hidden().empty();
      if (!started) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    CHECK(started);
    kill(pid, signal);
    int status = 0;
    waitpid(pid, &status, 0);
    CHECK(WIFSIGNALED(status));  // ended by the signal, as a shell expects
    CHECK(WTERMSIG(status) == signal);
    CHECK(s.Hidden().empty());
    CHECK(ReadFile(s / "out.json") == "KEEP");
  }
}

TEST_CASE("app: Ctrl-C during ltca optimise removes the spooled history with the staged outputs, a finished run leaves no spool (issue 46)") {
  // The history of --json is spooled beside it while the search runs (the summary comes first in
  // the document), the CSV's rows go into its staged temporary.
  const std::vector<std::string> run = {"optimise", LTCA_CASES_DIR "/liu2021_optimise.toml", "--threads", "1",
                                        "--set", "optimise.global=\"crs2\"", "--set", "optimise.local=\"none\"",
                                        "--json", "out.json", "--csv", "out.csv"};
  Scratch s;
  WriteFile(s / "out.json", "KEEP");
  WriteFile(s / "out.csv", "KEEP");
  std::vector<std::string> long_run = run;
  long_run.insert(long_run.end(), {"--evaluations", "1000000"});
  const pid_t pid = StartLtca(s.dir, long_run);
  REQUIRE(pid >= 0);
  // Wait for the spool and the two staged files (the search has started), at most 60 s.
  const auto spooling = [&] {
    const auto hidden = s.Hidden();
    const bool spool = std::any_of(hidden.begin(), hidden.end(), [](const std::string& n) { return n.rfind(".ltca-spool-", 0) == 0; });
    return spool && hidden.size() == 3;
  };
  bool started = false;
  for (int i = 0; i < 6000 && !started; ++i) {
    started = spooling();
    if (!started) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  CHECK(started);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // some evaluations spooled
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  CHECK(WIFSIGNALED(status));
  CHECK(WTERMSIG(status) == SIGINT);
  CHECK(s.Hidden().empty());
  CHECK(ReadFile(s / "out.json") == "KEEP");
  CHECK(ReadFile(s / "out.csv") == "KEEP");
  // A run that ends: its documents in place, nothing else left.
  std::string args;
  for (const std::string& a : run) args += " '" + a + "'";
  CHECK(Ltca(s.dir, args + " --evaluations 30") == 0);
  CHECK(s.Hidden().empty());
  CHECK(ReadFile(s / "out.json").find("\"history\": [") != std::string::npos);
}

TEST_CASE("app: Ctrl-C while a figure is drawn removes the plotting library's temporary file too") {
  // The figure is drawn for a fraction of a second after the solves: a run whose drawing the poll
  // did not catch (a loaded machine) is tried again, up to five times.
  Scratch s;
  const auto drawing = [&] {
    for (const auto& e : fs::directory_iterator(s.dir)) {
      if (e.path().filename().string().rfind("ltca_plot_", 0) == 0) return true;
    }
    return false;
  };
  bool caught = false;
  for (int attempt = 0; attempt < 5 && !caught; ++attempt) {
    fs::remove(s / "out.svg");  // a run whose drawing was missed wrote it
    const std::string tmp = s.dir.string();
    const pid_t pid = StartSolve(s.dir, "3000", "--svg", "out.svg", [&tmp] { setenv("TMPDIR", tmp.c_str(), 1); });  // the figure's temporary here
    REQUIRE(pid >= 0);
    int status = 0;
    bool exited = false;
    while (!caught && !exited) {
      caught = drawing();
      if (!caught) exited = waitpid(pid, &status, WNOHANG) == pid;
    }
    if (!caught) continue;
    kill(pid, SIGINT);
    waitpid(pid, &status, 0);
    CHECK(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == SIGINT);
    CHECK_FALSE(drawing());
    CHECK(s.Hidden().empty());
    CHECK_FALSE(fs::exists(s / "out.svg"));
  }
  CHECK(caught);
}

TEST_CASE("app: the written deck reads back as the deck: comments, order and an empty [second_disc] kept, edits in place") {
  const std::string text = ReadFile(LTCA_CASES_DIR "/stage/rv_two_discs_cranks.toml");
  REQUIRE(text.find("[second_disc]") != std::string::npos);
  const ltca::app::Deck deck = ltca::app::ParseDeck(text, "rv", {"load.torque_nm=500"});
  REQUIRE(deck.second_disc.has_value());
  const std::string written = ltca::app::WriteDeck(deck, {{"modification", "pin_radius_mm", "-0.005", "the optimum"}}, {}, "# header\n");
  CHECK(written.rfind("# header\n", 0) == 0);
  CHECK(written.find("[second_disc]                 # identical to the first") != std::string::npos);
  const ltca::app::Deck back = ltca::app::ParseDeck(written, "back");
  CHECK(back.second_disc.has_value());
  CHECK(back.RequireLoad().torque == doctest::Approx(500e3));
  CHECK(back.modification.pin_radius == doctest::Approx(-0.005));
  // Every comment line of the deck is still there.
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind('#', 0) == 0) CHECK(written.find(line) != std::string::npos);
  }
  // A dropped section goes with its keys; the rest reads back the same.
  const std::string opt = ReadFile(LTCA_CASES_DIR "/liu2021_optimise.toml");
  const ltca::app::Deck with = ltca::app::ParseDeck(opt, "opt");
  REQUIRE(with.optimise.has_value());
  const ltca::app::Deck without = ltca::app::ParseDeck(ltca::app::WriteDeck(with, {}, {"optimise"}), "without");
  CHECK_FALSE(without.optimise.has_value());
  CHECK(without.given.size() < with.given.size());
  // --unset of a section and of a key (issue 54) is written as their absence.
  const ltca::app::Deck unset = ltca::app::ParseDeck(text, "rv", {"-second_disc", "-load.torque_nm", "load.torque_nm=400"});
  const std::string written_unset = ltca::app::WriteDeck(unset, {});
  CHECK(written_unset.find("[second_disc]") == std::string::npos);
  const ltca::app::Deck back_unset = ltca::app::ParseDeck(written_unset, "back");
  CHECK_FALSE(back_unset.second_disc.has_value());
  CHECK(back_unset.RequireLoad().torque == doctest::Approx(400e3));
  // A section removed and set again is written as the new section (review: the removal was
  // applied after the --set and took its keys with it).
  const ltca::app::Deck replaced = ltca::app::ParseDeck(text, "rv", {"-contact", "contact.law=\"hertz-line\""});
  const ltca::app::Deck back_replaced = ltca::app::ParseDeck(ltca::app::WriteDeck(replaced, {}), "back");
  CHECK(back_replaced.contact.law == ltca::contact::LawKind::kHertzLine);
  CHECK(back_replaced.contact.rho_convention == ltca::contact::RhoConvention::kSigned);  // the deck gave absolute
}

TEST_CASE("app: a commit that fails part way puts back a file it replaced, whatever its name's length") {
  // A review found the file of a long name (no room for its backup's name beside it) removed by the
  // rollback of a later output that could not be renamed.
  Scratch s;
  const std::string long_name = std::string(240, 'p') + ".json";
  WriteFile(s / long_name, "PRECIOUS");
  std::ostringstream out;
  {
    ltca::cli::OutputTransaction run;
    ltca::cli::Output first("--json", (s / long_name).string(), out);
    ltca::cli::Output second("--csv", (s / "c.csv").string(), out);
    first.stream() << "{}";
    second.stream() << "x";
    first.Commit();
    second.Commit();
    fs::create_directories(s / "c.csv" / "in-the-way");  // the second target became a non-empty folder
    CHECK_THROWS_AS(run.CommitAll(), ltca::cli::OutputError);
  }
  CHECK(ReadFile(s / long_name) == "PRECIOUS");
  CHECK(s.Hidden().empty());
}

TEST_CASE("app: ltca optimise keeps its documents when --write-deck has no design to write (exit 1)") {
  Scratch s;
  CHECK(Ltca(s.dir, std::string("optimise ") + LTCA_CASES_DIR "/liu2021_optimise.toml --evaluations 20 --threads 1 " +
                        "--set 'optimise.constraints={mean_backlash_arcsec={min=1e9}}' --json o.json --write-deck best.toml") == 1);
  CHECK(ReadFile(s / "o.json").rfind("{", 0) == 0);
  CHECK_FALSE(fs::exists(s / "best.toml"));
  CHECK(Stderr(s).find("--write-deck best.toml") != std::string::npos);
}

TEST_CASE("app: the deck writer edits a table given with a quoted header or as dotted keys in place") {
  std::string text = ReadFile(LTCA_CASES_DIR "/liu2021_sec52_base.toml");
  REQUIRE(text.find("[modification]") != std::string::npos);
  // [modification] written as ["modification"], and a deck whose [load] is a dotted key at the top.
  const auto at = text.find("[modification]");
  if (at != std::string::npos) text.replace(at, 14, "[\"modification\"]");
  const auto load = text.find("[load]");
  REQUIRE(load != std::string::npos);
  const auto end = text.find('[', load + 6);
  const std::string torque = "load.torque_nm = 206.0\n";
  text = torque + text.substr(0, load) + (end == std::string::npos ? std::string() : text.substr(end));
  const ltca::app::Deck deck = ltca::app::ParseDeck(text, "quoted and dotted");
  const std::string written = ltca::app::WriteDeck(
      deck, {{"modification", "pin_radius_mm", "-0.002", ""}, {"load", "torque_nm", "100.0", ""}});
  const ltca::app::Deck back = ltca::app::ParseDeck(written, "back");
  CHECK(back.modification.pin_radius == doctest::Approx(-0.002));
  CHECK(back.RequireLoad().torque == doctest::Approx(100e3));
  CHECK(written.find("[modification]") == std::string::npos);  // no second table appended
}

TEST_CASE("app: ltca report -o takes the folder however it is spelled: a trailing slash, and through a link") {
  Scratch s;
  const std::string report = std::string("report ") + LTCA_CASES_DIR "/liu2021_table1.toml" + kFew;
  CHECK(Ltca(s.dir, report + " -o out/") == 0);
  CHECK(fs::exists(s / "out" / "index.html"));
  CHECK(Ltca(s.dir, report + " -o out/.") == 0);
  fs::create_directory(s / "real");
  fs::create_directory_symlink("real", s / "lnk");
  CHECK(Ltca(s.dir, report + " -o lnk") == 0);
  CHECK(fs::is_symlink(s / "lnk"));
  CHECK(fs::exists(s / "real" / "index.html"));
  CHECK(s.Hidden().empty());
}

TEST_CASE("app: a signal the run inherits as ignored stays ignored (nohup)") {
  Scratch s;
  const pid_t pid = StartSolve(s.dir, "3000", "--json", "out.json", [] { std::signal(SIGHUP, SIG_IGN); });  // as nohup leaves it
  REQUIRE(pid >= 0);
  for (int i = 0; i < 60000 && s.Hidden().empty(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  kill(pid, SIGHUP);
  int status = 0;
  waitpid(pid, &status, 0);
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
  CHECK(ReadFile(s / "out.json").rfind("{", 0) == 0);
}

#include "output.hpp"

#include "ltca/solvers/modules.hpp"

#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <mutex>
#include <thread>
#include <stdexcept>
#include <system_error>
#include <utility>

#include <fstream>
#include <sstream>
#include <fmt/format.h>
#include <fmt/ostream.h>

namespace ltca::cli {
namespace {

namespace fs = std::filesystem;

std::string Reason() { return errno != 0 ? std::string(": ") + std::strerror(errno) : std::string(); }

// The transaction of the run on this thread.
thread_local OutputTransaction* g_current = nullptr;

/// The file a path names: every symbolic link followed, also a dangling one (an output through a
/// dangling link is written where the link points, not over the link).
fs::path FollowLinks(fs::path p) {
  std::error_code ec;
  for (int i = 0; i < 40 && fs::is_symlink(fs::symlink_status(p, ec)); ++i) {
    const fs::path to = fs::read_symlink(p, ec);
    if (ec) break;
    p = to.is_absolute() ? to : p.parent_path() / to;
  }
  return p;
}

/// A name beside `target` for a file or folder of this run: ".ltca-<what>-XXXXXX" (short, so that
/// it fits beside a target whose own name is as long as a name may be), made
/// unique by mkstemp and removed again (the caller creates it at once).
std::string SiblingName(const fs::path& target, const char* what) {
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::string pattern = (folder / fmt::format(".ltca-{}-XXXXXX", what)).string();  // short: any name fits
  const int fd = mkstemp(pattern.data());
  if (fd < 0) return {};
  close(fd);
  unlink(pattern.c_str());
  return pattern;
}

}  // namespace

void InstallInterruptCleanup() {
  sigset_t set;
  sigemptyset(&set);
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
    // A signal the process inherits as ignored (nohup's SIGHUP, SIGINT of a shell's background job)
    // stays ignored: a blocked ignored signal would still reach sigwait.
    struct sigaction now {};
    if (sigaction(signal, nullptr, &now) == 0 && now.sa_handler == SIG_IGN) continue;
    sigaddset(&set, signal);
  }
  // Blocked in this thread before any other starts, so every thread inherits it and only the
  // waiting thread below takes these signals: it may then remove files and take the lock, which
  // a signal handler may not.
  if (pthread_sigmask(SIG_BLOCK, &set, nullptr) != 0) return;
  std::thread([set] {
    int signal = 0;
    while (sigwait(&set, &signal) != 0) {
    }
    auto lock = app::LockTemporaries();  // a CommitAll() under way finishes first; never unlocked
    app::RemoveTemporariesLocked();
    // Ended by the signal, as a shell expects of an interrupted program: its default action,
    // unblocked in this thread.
    std::signal(signal, SIG_DFL);
    sigset_t one;
    sigemptyset(&one);
    sigaddset(&one, signal);
    pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
    raise(signal);
    _exit(128 + signal);  // should the default action not end it
  }).detach();
}

fs::path OutputTarget(const std::string& path) { return FollowLinks(path); }

int ReportError(std::exception_ptr error, std::ostream& err) {
  try {
    std::rethrow_exception(error);
  } catch (const std::invalid_argument& e) {
    fmt::print(err, "ltca: error: {}\n", e.what());
    return kExitBadInput;
  } catch (const OutputError& e) {
    fmt::print(err, "ltca: output error: {}\n", e.what());
    return kExitOutputError;
  } catch (const solvers::ModuleError& e) {  // a part of the installation, not a bug (as --step's)
    fmt::print(err, "ltca: error: {}\n", e.what());
    return kExitNotSucceeded;
  } catch (const std::exception& e) {
    fmt::print(err, "ltca: internal error: {}\n", e.what());
    return kExitInternalError;
  } catch (...) {
    fmt::print(err, "ltca: internal error: an unknown exception\n");
    return kExitInternalError;
  }
}

OutputTransaction::OutputTransaction() {
  if (g_current != nullptr) throw std::logic_error("OutputTransaction: one run has one");
  g_current = this;
}

OutputTransaction::~OutputTransaction() {
  try {
    Abandon();
  } catch (...) {  // a destructor never throws
  }
  if (g_current == this) g_current = nullptr;
}

OutputTransaction* OutputTransaction::Current() { return g_current; }

OutputTransaction::Direct::Direct() : saved_(g_current) { g_current = nullptr; }
OutputTransaction::Direct::~Direct() { g_current = saved_; }

void OutputTransaction::ProtectInput(const std::string& what, const fs::path& path) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) return;  // not there: nothing to protect
  inputs_.push_back({what, path.string(), st.st_dev, st.st_ino});
  for (const auto& [option, target] : outputs_) CheckOutput(option, target);
}

void OutputTransaction::CheckOutput(const std::string& option, const fs::path& target) const {
  struct stat st {};
  if (stat(target.c_str(), &st) != 0) return;  // a new file is no input
  for (const Input& in : inputs_) {
    if (in.device == st.st_dev && in.inode == st.st_ino) {
      throw std::invalid_argument(fmt::format(
          "{} {}: is {} '{}' that this run reads (the same file, by device and inode); an output never replaces an input: "
          "give another file",
          option, target.string(), in.what, in.path));
    }
  }
  if (S_ISDIR(st.st_mode)) {
    std::error_code ec;
    const fs::path folder = fs::canonical(target, ec);
    if (ec) return;
    for (const Input& in : inputs_) {
      const fs::path file = fs::canonical(in.path, ec);
      if (ec) continue;
      const auto [end, unused] = std::mismatch(folder.begin(), folder.end(), file.begin(), file.end());
      if (end == folder.end()) {
        throw std::invalid_argument(fmt::format(
            "{} {}: the folder holds {} '{}' that this run reads, and the output replaces the folder; give another folder",
            option, target.string(), in.what, in.path));
      }
    }
  }
}

void OutputTransaction::OpenOutput(const std::string& option, const fs::path& target) {
  CheckOutput(option, target);
  outputs_.emplace_back(option, target.string());
}

void OutputTransaction::Stage(const std::string& option, const std::string& temp, const std::string& target) {
  staged_.push_back({option, temp, target, false});
}

void OutputTransaction::StageFolder(const std::string& option, const std::string& temp, const std::string& target) {
  staged_.push_back({option, temp, target, true});
}

void OutputTransaction::Abandon() {
  const auto lock = app::LockTemporaries();
  for (const Staged& s : staged_) {
    std::error_code ec;
    fs::remove_all(s.temp, ec);
    app::ForgetTemporaryLocked(s.temp);
  }
  staged_.clear();
}

void OutputTransaction::CommitAll() {
  const auto lock = app::LockTemporaries();  // SIGINT waits for the renames
  for (const Staged& s : staged_) CheckOutput(s.option, s.target);
  // First pass, before anything is replaced: every existing target is kept (a file: a hard link,
  // else a copy; a folder: moved aside at its turn), or nothing is replaced at all.
  std::vector<std::string> kept(staged_.size());
  std::vector<bool> existed(staged_.size(), false);
  std::string failure;
  const auto give_up = [&](std::size_t upto) {
    for (std::size_t i = 0; i < upto; ++i) {
      std::error_code ec;
      if (!staged_[i].folder && !kept[i].empty()) fs::remove(kept[i], ec);
    }
  };
  for (std::size_t i = 0; i < staged_.size(); ++i) {
    const Staged& s = staged_[i];
    struct stat st {};
    if (lstat(s.target.c_str(), &st) != 0) continue;  // a new file
    existed[i] = true;
    kept[i] = SiblingName(s.target, "old");
    if (s.folder) continue;  // moved aside when its turn comes
    errno = 0;
    bool ok = !kept[i].empty() && link(s.target.c_str(), kept[i].c_str()) == 0;
    if (!ok && !kept[i].empty()) {  // no hard links here: a copy
      std::error_code ec;
      ok = fs::copy_file(s.target, kept[i], ec) && !ec;
    }
    if (!ok) {
      failure = fmt::format("{} {}: cannot keep the file it would replace until every output is in place{}; nothing "
                            "was replaced", s.option, s.target, Reason());
      give_up(i + 1);
      break;
    }
  }
  std::size_t done = 0;
  if (failure.empty()) {
    for (; done < staged_.size(); ++done) {
      const Staged& s = staged_[done];
      errno = 0;
      if (s.folder && existed[done] && (kept[done].empty() || std::rename(s.target.c_str(), kept[done].c_str()) != 0)) {
        failure = fmt::format("{} {}: cannot move the old folder aside{}", s.option, s.target, Reason());
        kept[done].clear();
        break;
      }
      errno = 0;
      if (std::rename(s.temp.c_str(), s.target.c_str()) != 0) {
        failure = fmt::format("{} {}: cannot replace the {}{}", s.option, s.target, s.folder ? "folder" : "file", Reason());
        if (s.folder && existed[done]) std::rename(kept[done].c_str(), s.target.c_str());
        if (s.folder) kept[done].clear();
        break;
      }
    }
  }
  if (!failure.empty()) {
    // Every output put in place so far goes back to what it replaced (or away, when it was new),
    // the last first (two outputs to one target restore the oldest).
    for (std::size_t i = done; i-- > 0;) {
      const Staged& s = staged_[i];
      std::error_code ec;
      if (existed[i]) {
        if (s.folder) fs::remove_all(s.target, ec);
        std::rename(kept[i].c_str(), s.target.c_str());
        kept[i].clear();
      } else {
        fs::remove_all(s.target, ec);
      }
    }
    for (std::size_t i = 0; i < staged_.size(); ++i) {
      std::error_code ec;
      if (i >= done) fs::remove_all(staged_[i].temp, ec);
      if (!staged_[i].folder && !kept[i].empty()) fs::remove(kept[i], ec);  // the unused copies
      app::ForgetTemporaryLocked(staged_[i].temp);
    }
    staged_.clear();
    throw OutputError(failure);
  }
  for (std::size_t i = 0; i < staged_.size(); ++i) {
    std::error_code ec;
    if (!kept[i].empty()) fs::remove_all(kept[i], ec);
    app::ForgetTemporaryLocked(staged_[i].temp);
  }
  staged_.clear();
}

void WriteFigure(const app::plots::Figure& figure, Output& output) {
  if (!output.enabled()) return;
  try {
    app::plots::Write(figure, output.stream(), app::plots::FormatForPath(output.path()));
  } catch (const std::runtime_error& e) {
    throw OutputError(fmt::format("{}: {}", output.path(), e.what()));
  }
  output.Commit();
}


Output::Output(std::string option, std::string path, std::ostream& out)
    : option_(std::move(option)), path_(std::move(path)) {
  if (path_.empty()) return;
  if (option_ == "--svg") {  // a figure: its format (by the extension) must be one the plotting library draws
    try {
      app::plots::RequireFormat(app::plots::FormatForPath(path_));
    } catch (const std::runtime_error& e) {
      throw OutputError(fmt::format("{} {}: {}", option_, path_, e.what()));
    }
  }
  if (path_ == "-") {
    out_ = &out;
    return;
  }
  std::error_code ec;
  const fs::path target = FollowLinks(path_);
  if (OutputTransaction* run = OutputTransaction::Current()) run->OpenOutput(option_, target);
  const fs::file_status status = fs::status(target, ec);
  if (fs::is_directory(status)) throw OutputError(fmt::format("{} {}: is a folder, expected a file", option_, path_));
  errno = 0;
  if (fs::exists(status) && !fs::is_regular_file(status)) {
    // A device or a FIFO (/dev/stdout, /dev/full): written in place, checked on Commit().
    in_place_ = true;
    file_.open(target);
    if (!file_) throw OutputError(fmt::format("{} {}: cannot open for writing{}", option_, path_, Reason()));
    return;
  }
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(folder, ec)) {
    throw OutputError(fmt::format("{} {}: the folder '{}' does not exist", option_, path_, folder.string()));
  }
  std::string pattern = (folder / ".ltca-tmp-XXXXXX").string();  // short: beside any name
  if (!app::CreateTemporary(pattern, false)) {
    throw OutputError(fmt::format("{} {}: cannot write in the folder '{}'{}", option_, path_, folder.string(), Reason()));
  }
  temp_ = pattern;
  // The permissions a plain new file would get (mkstemp makes 0600), or the replaced file's.
  mode_t mode = 0666;
  struct stat existing {};
  if (stat(target.c_str(), &existing) == 0) {
    mode = existing.st_mode & 07777;
  } else {
    const mode_t mask = umask(0);
    umask(mask);
    mode &= ~mask;
  }
  chmod(temp_.c_str(), mode);
  path_ = target.string();
  file_.open(temp_, std::ios::out | std::ios::trunc);
  if (!file_) {
    std::remove(temp_.c_str());
    ForgetTemporary(temp_);
    temp_.clear();
    throw OutputError(fmt::format("{} {}: cannot open for writing{}", option_, path_, Reason()));
  }
}

Output::~Output() {
  if (committed_ || temp_.empty()) return;
  file_.close();
  std::remove(temp_.c_str());
  ForgetTemporary(temp_);
}

std::ostream& Output::stream() { return out_ != nullptr ? *out_ : file_; }

void Output::Check() {
  if (path_.empty() || stream()) return;
  throw OutputError(fmt::format("{} {}: writing failed", option_, path_));
}

void Output::Commit() {
  if (path_.empty() || committed_) return;
  errno = 0;
  if (out_ != nullptr) {
    if (!out_->flush()) throw OutputError(fmt::format("{} -: writing standard output failed{}", option_, Reason()));
    committed_ = true;
    return;
  }
  if (!file_.flush()) throw OutputError(fmt::format("{} {}: writing failed{}", option_, path_, Reason()));
  file_.close();
  if (file_.fail()) throw OutputError(fmt::format("{} {}: closing failed{}", option_, path_, Reason()));
  if (!in_place_) {
    if (OutputTransaction* run = OutputTransaction::Current()) {
      run->Stage(option_, temp_, path_);  // put in place with the run's other outputs
      committed_ = true;
      return;
    }
    if (std::rename(temp_.c_str(), path_.c_str()) != 0) {
      throw OutputError(fmt::format("{} {}: cannot replace the file{}", option_, path_, Reason()));
    }
    ForgetTemporary(temp_);
  }
  committed_ = true;
}

Spool::Spool(const std::string& option, const std::string& output_path) : option_(option) {
  fs::path folder = fs::temp_directory_path();
  if (!output_path.empty() && output_path != "-") {
    std::error_code ec;
    const fs::path target = FollowLinks(output_path);
    const fs::file_status status = fs::status(target, ec);
    if (!fs::exists(status) || fs::is_regular_file(status)) folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  }
  std::string pattern = (folder / ".ltca-spool-XXXXXX").string();
  if (!app::CreateTemporary(pattern, false)) {
    throw OutputError(fmt::format("{} {}: cannot make a temporary file in the folder '{}'{}", option_, output_path, folder.string(), Reason()));
  }
  path_ = pattern;
  file_.open(path_, std::ios::in | std::ios::out | std::ios::trunc | std::ios::binary);
  if (!file_) {
    std::remove(path_.c_str());
    ForgetTemporary(path_);
    throw OutputError(fmt::format("{} {}: cannot open the temporary file '{}'{}", option_, output_path, path_, Reason()));
  }
}

Spool::~Spool() {
  file_.close();
  std::remove(path_.c_str());
  ForgetTemporary(path_);
}

void Spool::Check() {
  if (!file_) throw OutputError(fmt::format("{}: writing the temporary file '{}' failed", option_, path_));
}

void Spool::CopyTo(std::ostream& os) {
  errno = 0;
  if (!file_.flush()) throw OutputError(fmt::format("{}: writing the temporary file '{}' failed{}", option_, path_, Reason()));
  const std::streamoff size = file_.tellp();
  if (size < 0) throw OutputError(fmt::format("{}: the temporary file '{}' cannot be read back{}", option_, path_, Reason()));
  file_.seekg(0);
  char buffer[1 << 16];
  std::streamoff copied = 0;
  while (copied < size && file_) {
    file_.read(buffer, static_cast<std::streamsize>(std::min<std::streamoff>(sizeof buffer, size - copied)));
    const std::streamsize n = file_.gcount();
    if (n <= 0) break;
    os.write(buffer, n);
    copied += n;
  }
  if (copied != size) throw OutputError(fmt::format("{}: reading the temporary file '{}' failed{}", option_, path_, Reason()));
}

void WriteTo(const std::string& option, const std::string& path, std::ostream& out,
             const std::function<void(std::ostream&)>& write) {
  Output output(option, path, out);
  if (!output.enabled()) return;
  write(output.stream());
  output.Commit();
}

void RequireDistinctOutputs(const std::vector<std::pair<std::string, std::string>>& option_paths) {
  // Two outputs to one file would leave only the last one written: refused like two to stdout.
  // A path is compared absolute and normalised, its existing part with links resolved, so that
  // "o.json", "./o.json" and "$PWD/o.json" are one file whether or not it exists yet.
  struct File {
    std::string option, path;
    std::filesystem::path resolved;
  };
  std::vector<File> files;
  for (const auto& [option, path] : option_paths) {
    if (path.empty() || path == "-") continue;
    std::error_code ec;
    std::filesystem::path resolved = std::filesystem::absolute(path, ec);
    if (!ec) resolved = std::filesystem::weakly_canonical(resolved, ec);
    if (ec) resolved = std::filesystem::path(path).lexically_normal();
    resolved = resolved.lexically_normal();
    for (const File& other : files) {
      if (other.resolved == resolved) {
        throw std::invalid_argument(fmt::format("{} {} and {} {}: two outputs to one file; give each its own file",
                                                other.option, other.path, option, path));
      }
    }
    files.push_back({option, path, resolved});
  }
  std::string first;
  for (const auto& [option, path] : option_paths) {
    if (path != "-") continue;
    if (!first.empty()) {
      throw std::invalid_argument(
          fmt::format("{} - and {} -: standard output carries one document; give one of them a file", first, option));
    }
    first = option;
  }
}

Progress::Progress(std::ostream& os, bool enabled, std::string what, std::int64_t total, double min_seconds)
    : os_(os), enabled_(enabled), what_(std::move(what)), total_(total), min_seconds_(min_seconds),
      start_(std::chrono::steady_clock::now()), last_(start_) {}

Progress::~Progress() {
  try {
    Finish();
  } catch (...) {  // a destructor never throws
  }
}

void Progress::Finish() {
  enabled_ = false;
  Clear();
}

void Progress::Clear() {
  if (!shown_) return;
  shown_ = false;
  os_ << '\r' << std::string(72, ' ') << '\r' << std::flush;
}

void Progress::Update(std::int64_t done) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (elapsed < min_seconds_) return;
  if (shown_ && now - last_ < std::chrono::milliseconds(250) && done < total_) return;
  last_ = now;
  shown_ = true;
  const double fraction = total_ > 0 ? static_cast<double>(done) / static_cast<double>(total_) : 1.0;
  const double remaining = fraction > 0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
  fmt::print(os_, "\rltca: {} {} of {} ({:.0f} %), about {:.0f} s left   ", what_, done, total_, 100.0 * fraction,
             remaining);
  os_.flush();
}

void ReplaceGeneratedBlock(const std::string& option, const std::string& path, const std::string& begin,
                           const std::string& end, const std::string& content, std::ostream& out) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(fmt::format("{} {}: cannot read the document", option, path));
  std::stringstream text;
  text << in.rdbuf();
  std::string doc = text.str();
  const auto b = doc.find(begin), e = doc.find(end);
  if (b == std::string::npos || e == std::string::npos || e < b) {
    throw std::invalid_argument(fmt::format("{} {}: the markers of the generated block are missing", option, path));
  }
  doc = doc.substr(0, b) + begin + "\n" + content + "\n" + doc.substr(e);
  WriteTo(option, path, out, [&](std::ostream& os) { os << doc; });
}

}  // namespace ltca::cli

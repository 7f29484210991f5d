#pragma once
// Writing outputs. "-" means standard output. A file output is checked when it is opened
// (before any computation), written to a temporary file in the same folder, flushed and
// checked, and renamed over the target only on success: a failure leaves no partial file.
// Devices and FIFOs (/dev/stdout, /dev/full) are written in place, and checked the same way.
#include <sys/types.h>

#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <cstdint>
#include <fstream>
#include <functional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "documents/common.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/app/exit_codes.hpp"
#include "ltca/app/plots.hpp"
#include "ltca/app/temporaries.hpp"

namespace ltca::cli {

/// An output that could not be opened or written (exit code 3).
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

using app::kExitBadInput;
using app::kExitInternalError;
using app::kExitNotSucceeded;
using app::kExitOutputError;
using app::kExitSuccess;

/// The files of one run of `ltca` (cli::Run makes one; a command run in-process without it writes
/// each output as it completes): the inputs it reads, which no output may be, and the outputs it
/// writes, all renamed into place together when the run has succeeded, or none.
/// - An output whose file (links followed, also a hard link: the same device and inode) is an
///   input is refused with std::invalid_argument naming the option, whichever is named first.
/// - Output::Commit() completes a file (flushed, closed, checked) and hands its temporary here;
///   CommitAll() renames every one over its target, keeping each replaced file as a hard link until
///   all are in place, and puts the replaced files back if a rename fails. A run that ends any
///   other way (an exception, SIGINT or SIGTERM with InstallInterruptCleanup) removes every
///   temporary and leaves every existing file as it was.
class OutputTransaction {
 public:
  OutputTransaction();  ///< becomes Current() (one at a time: std::logic_error for a second)
  ~OutputTransaction();  ///< removes what was not committed
  OutputTransaction(const OutputTransaction&) = delete;
  OutputTransaction& operator=(const OutputTransaction&) = delete;
  static OutputTransaction* Current();

  /// A file the run reads (`what`: "the deck", "[errors] profile_measured_csv", ...). Refuses an
  /// output already opened that is this file.
  void ProtectInput(const std::string& what, const std::filesystem::path& path);
  /// Throws std::invalid_argument when `target` is an input or holds one (a folder).
  void CheckOutput(const std::string& option, const std::filesystem::path& target) const;
  /// CheckOutput, and remembered: an input named later is checked against it.
  void OpenOutput(const std::string& option, const std::filesystem::path& target);
  /// A completed temporary file to rename over `target` at CommitAll().
  void Stage(const std::string& option, const std::string& temp, const std::string& target);
  /// A completed folder to put in place of `target` (which is replaced whole) at CommitAll().
  void StageFolder(const std::string& option, const std::string& temp, const std::string& target);
  /// Puts every staged output in place (OutputError when that fails; then none is).
  void CommitAll();
  /// Removes every staged temporary now (a run that ends without unwinding: MPI_Abort).
  void Abandon();

  /// While it lives, outputs are written directly (the report's files in its private folder).
  class Direct {
   public:
    Direct();
    ~Direct();
    Direct(const Direct&) = delete;
    Direct& operator=(const Direct&) = delete;

   private:
    OutputTransaction* saved_;
  };

 private:
  struct Input {
    std::string what, path;
    dev_t device;
    ino_t inode;
  };
  struct Staged {
    std::string option, temp, target;
    bool folder = false;
  };
  std::vector<Input> inputs_;
  std::vector<std::pair<std::string, std::string>> outputs_;  ///< option and target of every output opened
  std::vector<Staged> staged_;
};

using app::ForgetTemporary;   // the temporaries an interrupt removes (ltca/app/temporaries.hpp)
using app::RegisterTemporary;
/// For the `ltca` executable, first thing in main(): SIGINT, SIGTERM and SIGHUP are taken by a
/// thread of their own, which removes every registered temporary (waiting for a CommitAll() under
/// way to finish) and ends the process with 128 + the signal's number.
void InstallInterruptCleanup();

/// The file or folder an output path names: every symbolic link followed, also a dangling one.
std::filesystem::path OutputTarget(const std::string& path);

/// The exit code of the exception being handled, after printing it to `err` as `ltca` does
/// ("ltca: error: ..." 2, "ltca: output error: ..." 3, "ltca: internal error: ..." 4).
int ReportError(std::exception_ptr error, std::ostream& err);

/// One output of a command: "" none, "-" the out stream, else a file written atomically.
class Output {
 public:
  /// Opens the output at once (creating the temporary file), so that an unwritable path is
  /// found before computing. Throws OutputError naming the option and the path.
  Output(std::string option, std::string path, std::ostream& out);
  ~Output();  ///< removes the temporary file unless Commit() succeeded
  Output(const Output&) = delete;
  Output& operator=(const Output&) = delete;

  bool enabled() const { return !path_.empty(); }
  const std::string& path() const { return path_; }
  std::ostream& stream();
  /// Throws OutputError, as Commit would, when writing has already failed (a long run that writes
  /// as it goes stops at once on a full disk instead of at its end).
  void Check();
  /// Flushes and checks the stream, closes and renames the file into place. Throws OutputError.
  void Commit();

 private:
  std::string option_, path_, temp_;
  std::ostream* out_ = nullptr;  ///< "-"
  std::ofstream file_;
  bool in_place_ = false;        ///< a device or FIFO: no temporary file
  bool committed_ = false;
};

/// Writes a whole document to an output given as option/path (a convenience over Output).
void WriteTo(const std::string& option, const std::string& path, std::ostream& out,
             const std::function<void(std::ostream&)>& write);

/// Draws a figure into an output, SVG or, by the path's extension, PNG or PDF, and
/// commits it.
void WriteFigure(const app::plots::Figure& figure, Output& output);

/// A temporary file for a part of a document written before its place in the document comes (the
/// history of `ltca optimise --json`, which follows the summary known only at the end): beside the
/// output's file (the same folder, so the same file system as the document), or in the system's
/// temporary folder when the output is "-" or a device. Registered, so that an interrupt removes
/// it; removed when it goes out of scope.
class Spool {
 public:
  /// OutputError naming the option when it cannot be made.
  Spool(const std::string& option, const std::string& output_path);
  ~Spool();
  Spool(const Spool&) = delete;
  Spool& operator=(const Spool&) = delete;
  std::ostream& stream() { return file_; }
  /// Throws OutputError when writing has already failed (Output::Check).
  void Check();
  /// Copies what was written into `os`; OutputError when writing or reading the spool failed.
  void CopyTo(std::ostream& os);

 private:
  std::string option_, path_;
  std::fstream file_;
};

/// Throws std::invalid_argument when more than one of these outputs is "-" (standard output
/// carries one document) or two of them name the same file (one would replace the other).
void RequireDistinctOutputs(const std::vector<std::pair<std::string, std::string>>& option_paths);

// The documents' shared pieces (documents/common.hpp), as the commands name them.
using app::documents::DecimatedSeries;
using app::documents::CaseJson;
using app::documents::Dump;
using app::documents::FigureCaption;
using app::documents::FiniteOrNull;
using app::documents::FormatOrNa;
using app::documents::MarkMeanAndPeakToPeak;
using app::documents::ModelJson;
using app::documents::ModelLine;


using app::documents::Nested;
using app::documents::OpenObject;



/// The streams of a command: documents go to out ("-"); the human text to text, which is the
/// error stream when any output of the command is "-" (so stdout carries only the document).
struct Streams {
  std::ostream& out;
  std::ostream& text;
  std::ostream& err;
  bool progress = false;  ///< a progress line on err (a terminal) for runs over about 2 s
  double progress_delay_seconds = 2.0;  ///< the line shows after this long (tests: 0)
};

/// "ltca: solving position i of n" on a terminal, after min_seconds, at most every 0.25 s.
class Progress {
 public:
  Progress(std::ostream& os, bool enabled, std::string what, std::int64_t total, double min_seconds = 2.0);
  ~Progress();  ///< calls Finish()
  void Update(std::int64_t done);
  /// Clears the line (before the summary is printed); later updates are not shown.
  void Finish();
  /// Clears the line before other text is written to the terminal; the next update shows it again.
  void Clear();

 private:
  std::ostream& os_;
  bool enabled_, shown_ = false;
  std::string what_;
  std::int64_t total_;
  double min_seconds_;
  std::chrono::steady_clock::time_point start_, last_;
};

/// Replaces the block between the lines `begin` and `end` of the document at `path` by `content`
/// (--write-doc of `ltca validate` and `ltca keys`); std::invalid_argument naming `option` when the
/// document cannot be read or lacks the markers.
void ReplaceGeneratedBlock(const std::string& option, const std::string& path, const std::string& begin,
                           const std::string& end, const std::string& content, std::ostream& out);

}  // namespace ltca::cli

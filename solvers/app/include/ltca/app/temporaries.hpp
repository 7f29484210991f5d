#pragma once
// The temporary files and folders of this process (an output being written, a figure being drawn,
// a report's folder being built), so that an interrupted run can remove them: the `ltca`
// executable's signal thread (cli::InstallInterruptCleanup) takes the lock, removes every one and
// ends the process. Thread-safe.
#include <mutex>
#include <string>
#include <utility>

namespace ltca::app {

/// Registers a temporary file or folder (removed whole) that an interrupt removes.
void RegisterTemporary(const std::string& path);
/// Creates a temporary from `pattern` (its name ending in XXXXXX, replaced in place): a file
/// (mkstemp, closed) or a folder (mkdtemp), created and registered with the lock held, so that an
/// interrupt comes either before it exists or after it is registered (and removes it). Returns
/// false, with errno set, when it cannot be created.
bool CreateTemporary(std::string& pattern, bool folder);
/// Forgets it (it was renamed into place or removed).
void ForgetTemporary(const std::string& path);

/// The registry's lock: held, no temporary is added, forgotten or removed by an interrupt (a
/// commit of outputs holds it while it renames them, so an interrupt waits for the commit).
std::unique_lock<std::mutex> LockTemporaries();
/// With the lock held: forgets one, or removes every one (the interrupt).
void ForgetTemporaryLocked(const std::string& path);
void RemoveTemporariesLocked();

/// A scratch file of this run (made by CreateTemporary; `path` empty until then), removed and
/// forgotten when it goes out of scope: a figure's drawing, the DXF or STEP written before it is
/// read back.
struct ScratchFile {
  std::string path;
  ScratchFile() = default;
  explicit ScratchFile(std::string p) : path(std::move(p)) {}
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;
  ~ScratchFile();
};

}  // namespace ltca::app

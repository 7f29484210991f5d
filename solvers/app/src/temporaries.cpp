#include "ltca/app/temporaries.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <vector>

#include <unistd.h>

namespace ltca::app {
namespace {

// Never destroyed: the signal thread may use them while the process's statics are destroyed.
std::mutex& Mutex() {
  static auto* m = new std::mutex;
  return *m;
}

std::vector<std::string>& Paths() {  // guarded by Mutex()
  static auto* paths = new std::vector<std::string>;
  return *paths;
}

}  // namespace

void RegisterTemporary(const std::string& path) {
  const std::lock_guard<std::mutex> lock(Mutex());
  Paths().push_back(path);
}

bool CreateTemporary(std::string& pattern, bool folder) {
  int error = 0;
  {
    const std::lock_guard<std::mutex> lock(Mutex());
    errno = 0;
    bool made = false;
    if (folder) {
      made = mkdtemp(pattern.data()) != nullptr;
    } else if (const int fd = mkstemp(pattern.data()); fd >= 0) {
      close(fd);
      made = true;
    }
    if (made) Paths().push_back(pattern);
    error = made ? 0 : errno;
  }
  errno = error;
  return error == 0;
}

void ForgetTemporary(const std::string& path) {
  const std::lock_guard<std::mutex> lock(Mutex());
  ForgetTemporaryLocked(path);
}

ScratchFile::~ScratchFile() {
  if (!path.empty()) {
    std::remove(path.c_str());
    ForgetTemporary(path);
  }
}

std::unique_lock<std::mutex> LockTemporaries() { return std::unique_lock<std::mutex>(Mutex()); }

void ForgetTemporaryLocked(const std::string& path) {
  auto& paths = Paths();
  const auto it = std::find(paths.begin(), paths.end(), path);
  if (it != paths.end()) paths.erase(it);
}

void RemoveTemporariesLocked() {
  for (const std::string& path : Paths()) {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  Paths().clear();
}

}  // namespace ltca::app

// ltca-test-meter RECORD_DIR COMMAND [ARGS...]: runs COMMAND, exits as it did (its code, or its
// signal re-raised), and writes the CPU time (user + system) of COMMAND and of every process it
// waited for to RECORD_DIR/<hash of the command line>.tsv:
//   <CPU seconds> TAB <wall seconds> TAB <argument 1> NUL <argument 2> NUL ...
// Every test of tests/CMakeLists.txt runs through it (issue 55), so that tests/suite_times.py can
// judge each test by the CPU work it did, which another process on the machine does not change the
// way it changes the wall time. The wall time is recorded for the listing only.
#include <signal.h>
#include <sys/stat.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

namespace {

pid_t child = -1;

void Forward(int sig) {
  if (child > 0) kill(child, sig);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: ltca-test-meter RECORD_DIR COMMAND [ARGS...]\n");
    return 2;
  }
  const auto start = std::chrono::steady_clock::now();
  child = fork();
  if (child < 0) {
    std::perror("ltca-test-meter: fork");
    return 2;
  }
  if (child == 0) {
    execvp(argv[2], argv + 2);
    std::fprintf(stderr, "ltca-test-meter: cannot run %s: %s\n", argv[2], std::strerror(errno));
    _exit(127);
  }
  // ctest ends a test past its TIMEOUT with a signal to this process: pass it on.
  for (const int sig : {SIGTERM, SIGINT, SIGHUP}) signal(sig, Forward);
  int status = 0;
  rusage usage{};
  while (wait4(child, &status, 0, &usage) < 0) {
    if (errno != EINTR) {
      std::perror("ltca-test-meter: wait4");
      return 2;
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // wait4's usage covers the child and every descendant it waited for (a doctest suite's `ltca`
  // children, a Python script's subprocesses).
  const double cpu = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                     1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
  std::string line = std::to_string(cpu) + "\t" + std::to_string(wall) + "\t";
  std::uint64_t hash = 1469598103934665603ull;  // FNV-1a of the command line
  for (int i = 2; i < argc; ++i) {
    if (i > 2) line += '\0';
    line += argv[i];
  }
  for (const char c : line.substr(line.find('\t', line.find('\t') + 1) + 1)) {
    hash = (hash ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  }
  char name[32];
  std::snprintf(name, sizeof name, "/%016llx.tsv", static_cast<unsigned long long>(hash));
  mkdir(argv[1], 0755);  // exists already, but for the first test of a run without the start test
  const std::string path = std::string(argv[1]) + name;
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(line.data(), 1, line.size(), f);
    std::fclose(f);
  } else {
    std::fprintf(stderr, "ltca-test-meter: cannot write %s (the test's verdict stands)\n", path.c_str());
  }
  if (WIFSIGNALED(status)) {
    signal(WTERMSIG(status), SIG_DFL);
    raise(WTERMSIG(status));
    return 128 + WTERMSIG(status);
  }
  return WEXITSTATUS(status);
}

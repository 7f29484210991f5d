// ltca-peak-rss PROGRAM [ARG...]: runs PROGRAM (its standard output discarded) and prints its peak
// resident memory in KiB, as the kernel accounts it, then exits with PROGRAM's exit code (127 when
// it could not run, 128 + N for a signal).
//
// Why a program of its own (issue 26): a child's ru_maxrss includes the resident size of the
// process it was exec'd from (Linux records the old address space's high-water mark at exec), and
// getrusage(RUSAGE_CHILDREN) reports the largest of every child ever waited for. The benchmark is a
// large process; this small one, started fresh, forks the measured program from a small address
// space and reads its own child's rusage from wait4.
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: ltca-peak-rss PROGRAM [ARG...]\n");
    return 2;
  }
  const pid_t pid = fork();
  if (pid < 0) return 127;
  if (pid == 0) {
    const int null = open("/dev/null", O_WRONLY);
    if (null >= 0) dup2(null, STDOUT_FILENO);
    execv(argv[1], argv + 1);
    _exit(127);
  }
  int status = 0;
  rusage usage{};
  if (wait4(pid, &status, 0, &usage) != pid) return 127;
  std::printf("%ld\n", usage.ru_maxrss);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 127;
}

#pragma once
// A process id that no running process has: what a stopped writer's leftover files are named after.

#include <sys/wait.h>
#include <unistd.h>

namespace artemis::test {

// The pid of a child that has ended and been reaped (the kernel reuses pids only much later).
inline pid_t endedPid() {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(0);
  ::waitpid(pid, nullptr, 0);
  return pid;
}

}  // namespace artemis::test

#pragma once
// Runs the built artemis program with arguments, capturing exit code, stdout and stderr.

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "support/test_support.hpp"

namespace artemis::test {

struct RunResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

inline RunResult runCli(const std::string& args) {
  TempDir tmp;
  const std::string cmd = std::string(ARTEMIS_CLI_PATH) + " " + args + " 2>" + (tmp / "stderr").string();
  RunResult r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return r;
  std::array<char, 4096> buf{};
  std::size_t n = 0;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.out.append(buf.data(), n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream err(tmp / "stderr");
  std::stringstream ss;
  ss << err.rdbuf();
  r.err = ss.str();
  return r;
}

}  // namespace artemis::test

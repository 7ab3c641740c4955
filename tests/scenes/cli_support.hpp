// What the end-to-end tests of the `grainflow` executable share: running it as a user
// would (stdout and stderr together, the exit status) and a fresh folder per test.
#pragma once
#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

#include <sys/wait.h>

namespace {

struct Result {
  int status = -1;
  std::string output;  // stdout + stderr
};

inline Result run(const std::string& args) {
  Result r;
  const std::string cmd = std::string(GRAINFLOW_EXE) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), int(buf.size()), p)) r.output += buf.data();
  const int raw = pclose(p);
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return r;
}

inline std::filesystem::path fresh_dir(const std::string& name) {
  const std::filesystem::path d = std::filesystem::path(GRAINFLOW_TEST_OUT) / "cli" / name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d.parent_path());
  return d;
}

inline bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace

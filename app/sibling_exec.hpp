/// @file sibling_exec.hpp
/// Replacing this process by a program installed next to it (the launcher's and
/// startracker-solve's hand-over). Header-only: the launcher links nothing of the project.
#pragma once
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

namespace st::app {

/// `name` in the folder of the running executable (/proc/self/exe, symlinks resolved).
inline std::string siblingPath(const char* argv0, const char* name) {
  char self[4096];
  const ssize_t n = ::readlink("/proc/self/exe", self, sizeof self - 1);
  std::string dir = n > 0 ? std::string(self, std::size_t(n)) : std::string(argv0);
  const auto slash = dir.rfind('/');
  dir = slash == std::string::npos ? "." : dir.substr(0, slash);
  return dir + "/" + name;
}

/// execv()s the sibling `name` with the same argv; returns 1 (with one message) only when
/// that fails.
inline int execSibling(const char* name, char** argv) {
  const std::string path = siblingPath(argv[0], name);
  ::execv(path.c_str(), argv);
  std::fprintf(stderr, "error: cannot run %s: %s\n", path.c_str(), std::strerror(errno));
  return 1;
}

}  // namespace st::app

#pragma once
/// \file atomic_file.hpp
/// Write a file completely or not at all: the content goes to a temporary file beside the target,
/// is flushed and synced, and is then renamed over the target (rename is atomic on POSIX file
/// systems). A reader never sees a half-written file; a failed write leaves no file behind.

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>

#if defined(__unix__) || defined(__APPLE__)
#include <unistd.h>
#endif

namespace drape {

/// Thrown when an output file cannot be written; the message names the file and the OS reason.
class FileWriteError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Calls `write(FILE*)` on a temporary file and renames it to `path` if everything succeeded.
/// `write` returns false (or throws) to signal failure.
/// \throws FileWriteError naming `path` and the reason; no file named `path` is created or changed.
inline void write_file_atomically(const std::string& path, const std::function<bool(std::FILE*)>& write) {
  const std::string tmp = path + ".tmp";
  std::FILE* file = std::fopen(tmp.c_str(), "wb");
  if (!file) throw FileWriteError("cannot create '" + tmp + "': " + std::strerror(errno));
  bool ok = false;
  int saved_errno = 0;
  try {
    ok = write(file);
    saved_errno = errno;
    ok = ok && std::fflush(file) == 0;
    if (!ok && saved_errno == 0) saved_errno = errno;
#if defined(__unix__) || defined(__APPLE__)
    ok = ok && ::fsync(fileno(file)) == 0;
#endif
  } catch (...) {
    std::fclose(file);
    std::remove(tmp.c_str());
    throw;
  }
  if (std::fclose(file) != 0 && ok) {
    ok = false;
    saved_errno = errno;
  }
  if (!ok) {
    std::remove(tmp.c_str());
    throw FileWriteError("cannot write '" + path + "': " + (saved_errno ? std::strerror(saved_errno) : "write failed"));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int e = errno;
    std::remove(tmp.c_str());
    throw FileWriteError("cannot rename '" + tmp + "' to '" + path + "': " + std::strerror(e));
  }
}

}  // namespace drape

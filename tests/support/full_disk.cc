// A disk that is full for chosen files, for the CLI tests: loaded into pgba with LD_PRELOAD,
// it gives every open(2) for writing of a path that contains the environment variable
// PGBA_FULL_DISK's text the device /dev/full instead, on which every write fails with ENOSPC
// exactly as on a full disk. Other opens go to the C library unchanged.
#include <dlfcn.h>
#include <fcntl.h>
#include <sys/types.h>

#include <cstdarg>
#include <cstdlib>
#include <cstring>

namespace {

using OpenFunction = int (*)(const char*, int, ...);

bool OnTheFullDisk(const char* path, int flags) {
  const char* match = std::getenv("PGBA_FULL_DISK");
  return match != nullptr && *match != '\0' && path != nullptr && (flags & O_ACCMODE) != O_RDONLY &&
         std::strstr(path, match) != nullptr;
}

int Open(const char* symbol, const char* path, int flags, mode_t mode) {
  const auto real = reinterpret_cast<OpenFunction>(dlsym(RTLD_NEXT, symbol));
  if (OnTheFullDisk(path, flags)) return real("/dev/full", O_WRONLY | (flags & O_CLOEXEC));
  return real(path, flags, mode);
}

mode_t ModeOf(int flags, va_list args) {
  return (flags & (O_CREAT | O_TMPFILE)) != 0 ? static_cast<mode_t>(va_arg(args, int)) : 0;
}

}  // namespace

extern "C" int open(const char* path, int flags, ...) {
  va_list args;
  va_start(args, flags);
  const mode_t mode = ModeOf(flags, args);
  va_end(args);
  return Open("open", path, flags, mode);
}

extern "C" int open64(const char* path, int flags, ...) {
  va_list args;
  va_start(args, flags);
  const mode_t mode = ModeOf(flags, args);
  va_end(args);
  return Open("open64", path, flags, mode);
}

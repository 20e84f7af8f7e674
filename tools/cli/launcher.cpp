// build/clothsim: a static launcher that closes the dynamic loader's window for signals.
//
// The program (libexec/clothsim) links 146 shared libraries; ld.so maps and relocates them
// (LLVM alone, through Mesa, holds 63 % of the relocations) for about 30 ms before any code of
// ours runs, and a signal then met the default action: the process died without its line.
// This launcher is static, so no loader runs before its first instruction. It blocks SIGINT,
// SIGTERM and SIGHUP at once and execs the program: the mask and any pending signal survive
// execve, and the program's .preinit_array installs its handlers and unblocks (main.cpp), so a
// signal from the first instant is answered with the usual line. Why not load Mesa and FFmpeg
// lazily instead: every library (yaml-cpp, libpng, x264's) costs the window a little, and
// dlopen would move GL and the encoder behind function tables.
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <csignal>
#include <cstring>
#include <initializer_list>

namespace {

void say(std::initializer_list<const char*> parts) {  // one line on stderr, no stdio needed
  for (const char* s : parts) {
    const ssize_t ignored = ::write(STDERR_FILENO, s, std::strlen(s));
    (void)ignored;
  }
}

}  // namespace

int main(int, char** argv) {
  sigset_t answered;
  sigemptyset(&answered);
  sigaddset(&answered, SIGINT);
  sigaddset(&answered, SIGTERM);
  sigaddset(&answered, SIGHUP);
  sigprocmask(SIG_BLOCK, &answered, nullptr);  // first: held until the program can answer

  // The program lies in libexec/ beside this launcher (the build tree: build/clothsim,
  // build/libexec/clothsim) or in ../libexec/clothsim/ (an installed prefix, wherever it was
  // unpacked: PREFIX/bin/clothsim, PREFIX/libexec/clothsim/clothsim).
  char path[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", path, sizeof path - 64);
  if (n <= 0) {
    say({"clothsim: cannot find the program: /proc/self/exe: ", std::strerror(errno), "\n"});
    return 1;
  }
  path[n] = '\0';
  char* slash = std::strrchr(path, '/');
  char* tail = slash ? slash + 1 : path;
  std::strcpy(tail, "libexec/clothsim");
  struct stat st;
  if (::stat(path, &st) != 0 || !S_ISREG(st.st_mode)) std::strcpy(tail, "../libexec/clothsim/clothsim");
  ::execv(path, argv);
  say({"clothsim: cannot run ", path, ": ", std::strerror(errno), "\n"});
  return 1;
}

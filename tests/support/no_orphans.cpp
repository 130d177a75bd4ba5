// no_orphans COMMAND [ARGS...]: runs a test command and fails it when a
// process it started outlives it (docs/RELIABILITY.md, "Tests clean up after
// themselves").
//
// It makes itself a child subreaper (prctl(2) PR_SET_CHILD_SUBREAPER): every
// process the test starts, daemons that double-fork such as nginx's master
// and workers included, is reparented here instead of to init when its own
// parent ends. Once the command has exited, whatever is still a child of this
// process was left behind: after a short grace for processes already on
// their way out, each is named on stderr, killed, and the test fails.
#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

// The whole of a /proc file, or "" when it cannot be read. With read(2)
// rather than a stream: a process that exits between readdir and the read
// makes read fail with ESRCH, which std::filebuf turns into an exception that
// istreambuf_iterator lets through (it aborted a passing test in CI).
std::string ReadProcFile(const std::string& path) {
  std::string text;
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return text;
  char buffer[4096];
  for (;;) {
    const ssize_t got = read(fd, buffer, sizeof buffer);
    if (got > 0) {
      text.append(buffer, static_cast<size_t>(got));
    } else if (got < 0 && errno == EINTR) {
      continue;
    } else {
      if (got < 0) text.clear();
      break;
    }
  }
  close(fd);
  return text;
}

// The processes whose parent is this one (from /proc/PID/stat: "pid (comm) state ppid").
std::vector<pid_t> Children() {
  std::vector<pid_t> out;
  const pid_t self = getpid();
  DIR* proc = opendir("/proc");
  if (proc == nullptr) return out;
  while (dirent* e = readdir(proc)) {
    const pid_t pid = static_cast<pid_t>(std::atoi(e->d_name));
    if (pid <= 0) continue;
    const std::string text = ReadProcFile("/proc/" + std::string(e->d_name) + "/stat");
    const size_t close = text.rfind(')');
    if (close == std::string::npos) continue;
    std::istringstream rest(text.substr(close + 1));
    char state = 0;
    pid_t ppid = 0;
    rest >> state >> ppid;
    if (ppid == self && state != 'Z') out.push_back(pid);
  }
  closedir(proc);
  return out;
}

std::string CommandLine(pid_t pid) {
  std::string text = ReadProcFile("/proc/" + std::to_string(pid) + "/cmdline");
  for (char& c : text) {
    if (c == '\0') c = ' ';
  }
  return text;
}

void ReapZombies() {
  while (waitpid(-1, nullptr, WNOHANG) > 0) {
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: no_orphans COMMAND [ARGS...]\n");
    return 2;
  }
  if (prctl(PR_SET_CHILD_SUBREAPER, 1) != 0) {
    std::perror("no_orphans: prctl(PR_SET_CHILD_SUBREAPER)");
    return 2;
  }
  const pid_t child = fork();
  if (child < 0) {
    std::perror("no_orphans: fork");
    return 2;
  }
  if (child == 0) {
    execvp(argv[1], argv + 1);
    std::perror("no_orphans: exec");
    _exit(127);
  }
  // Reaps whatever ends meanwhile (a daemon reparented here, once it exits,
  // must not linger as a zombie that looks alive to the test).
  int status = 0;
  for (;;) {
    int st = 0;
    const pid_t ended = waitpid(-1, &st, 0);
    if (ended == child) {
      status = st;
      break;
    }
    if (ended < 0 && errno != EINTR) break;
  }
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);

  std::vector<pid_t> left;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  do {
    ReapZombies();
    left = Children();
    if (left.empty()) return code;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  } while (std::chrono::steady_clock::now() < deadline);

  for (pid_t pid : left) {
    std::fprintf(stderr, "no_orphans: %s left process %d running: %s\n", argv[1],
                 static_cast<int>(pid), CommandLine(pid).c_str());
    kill(pid, SIGKILL);
  }
  for (int k = 0; k < 40 && !Children().empty(); ++k) {
    ReapZombies();
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ReapZombies();
  return code != 0 ? code : 1;
}

// A child process of a test: spawned with its stdout in a temporary file and its stdin a pipe
// (Command() drives a node line by line), killed (SIGKILL) and reaped on destruction, so that no
// test leaves a process behind. Used by tests/dds and tests/ros_dds.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace semgraph::dds_test {

class Child {
 public:
  explicit Child(const std::vector<std::string>& args) {
    char path[] = "/tmp/semgraph_dds_child_XXXXXX";
    const int fd = mkstemp(path);
    out_path_ = path;
    close(fd);
    int pipe_fds[2];
    if (pipe(pipe_fds) != 0) return;
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, pipe_fds[0], 0);
    posix_spawn_file_actions_addclose(&actions, pipe_fds[1]);
    posix_spawn_file_actions_addopen(&actions, 1, out_path_.c_str(), O_WRONLY | O_TRUNC, 0600);
    std::vector<char*> argv;
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    if (posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
    close(pipe_fds[0]);
    in_ = pipe_fds[1];
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  ~Child() {
    Kill();
    if (in_ >= 0) close(in_);
    std::remove(out_path_.c_str());
  }
  [[nodiscard]] bool started() const { return pid_ > 0; }
  /// SIGKILL and reap (idempotent).
  void Kill() {
    if (pid_ > 0 && !exited_) {
      kill(pid_, SIGKILL);
      int status = 0;
      waitpid(pid_, &status, 0);
      exited_ = true;
    }
  }
  /// Waits for the exit up to `timeout`; the exit code, or -1 (then it is killed).
  int Wait(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (pid_ > 0 && !exited_) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        exited_ = true;
        code_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        break;
      }
      if (std::chrono::steady_clock::now() >= deadline) {
        Kill();
        return -1;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return code_;
  }
  [[nodiscard]] std::string Output() const {
    std::ifstream in(out_path_);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  /// Waits until the output holds a line equal to `line` (true), or the timeout.
  bool WaitForLine(const std::string& line, std::chrono::milliseconds timeout) const {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      const std::string out = Output();
      if (out.find(line + "\n") != std::string::npos) return true;
      if (std::chrono::steady_clock::now() >= deadline) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }
  /// Sends one command line and waits for the node's "ok <n>" (true; n counts the commands),
  /// or its "error <n> ..." or the timeout (false).
  bool Command(const std::string& line,
               std::chrono::milliseconds timeout = std::chrono::milliseconds(20000)) {
    const std::string text = line + "\n";
    if (write(in_, text.data(), text.size()) != static_cast<ssize_t>(text.size())) return false;
    const std::string n = std::to_string(++sent_);
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      const std::string out = Output();
      if (out.find("ok " + n + "\n") != std::string::npos) return true;
      if (out.find("error " + n + " ") != std::string::npos) return false;
      if (std::chrono::steady_clock::now() >= deadline) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  }

 private:
  pid_t pid_ = -1;
  bool exited_ = false;
  int code_ = -1;
  int in_ = -1;  // the child's stdin
  int sent_ = 0;
  std::string out_path_;
};

/// The lines of `text` that start with `prefix` + " ", without the prefix.
inline std::vector<std::string> LinesWith(const std::string& text, const std::string& prefix) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(prefix + " ", 0) == 0) out.push_back(line.substr(prefix.size() + 1));
  }
  return out;
}

/// Parses "name n0 n1 ..." into numbers (empty when the line is an error line).
inline std::vector<double> Numbers(const std::string& line, std::string* name) {
  std::istringstream in(line);
  in >> *name;
  std::vector<double> v;
  for (double x; in >> x;) v.push_back(x);
  return v;
}

}  // namespace semgraph::dds_test

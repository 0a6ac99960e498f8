// A child process of a live test (ros_dds_test_node), driven line by line through its stdin;
// its stdout goes to a temporary file. Killed (SIGKILL) and reaped on destruction, so no test
// leaves a process behind.
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

namespace semgraph::ros_dds_test {

class Child {
 public:
  explicit Child(const std::vector<std::string>& args) {
    char path[] = "/tmp/semgraph_ros_dds_child_XXXXXX";
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
  void Kill() {
    if (pid_ > 0 && !exited_) {
      kill(pid_, SIGKILL);
      int status = 0;
      waitpid(pid_, &status, 0);
      exited_ = true;
    }
  }
  [[nodiscard]] std::string Output() const {
    std::ifstream in(out_path_);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  /// Sends one command line and waits for the node's "ok <command>" (true) or its "error ..."
  /// or the timeout (false).
  bool Command(const std::string& line,
               std::chrono::milliseconds timeout = std::chrono::milliseconds(20000)) {
    const std::string text = line + "\n";
    if (write(in_, text.data(), text.size()) != static_cast<ssize_t>(text.size())) return false;
    const std::string done = "ok " + std::to_string(++sent_) + "\n";
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      const std::string out = Output();
      if (out.find(done) != std::string::npos) return true;
      if (out.find("error " + std::to_string(sent_) + " ") != std::string::npos) return false;
      if (std::chrono::steady_clock::now() >= deadline) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  }

 private:
  pid_t pid_ = -1;
  bool exited_ = false;
  int in_ = -1;
  int sent_ = 0;
  std::string out_path_;
};

}  // namespace semgraph::ros_dds_test

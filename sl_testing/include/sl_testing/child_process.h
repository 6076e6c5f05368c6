// A node or tool run by a test while the test watches it: its output read as it comes, a signal as
// roslaunch sends one, its exit status.
#pragma once

#include <algorithm>
#include <csignal>
#include <stdexcept>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <ros/time.h>

namespace sl_testing
{
/// @brief A command run in its own process group with stdout and stderr on one pipe, read while it runs.
class Child
{
public:
  explicit Child(const std::vector<std::string>& args)
  {
    // Built before fork(): the child of a threaded process may only make async-signal-safe calls.
    std::vector<char*> argv;
    for (const std::string& a : args)
      argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0)
      throw std::runtime_error("pipe2 failed");
    pid_ = fork();
    if (pid_ == 0)
    {
      // The child stops on SIGINT as a node does, also when the test itself was started with
      // SIGINT ignored (a background job of a non-interactive shell, nohup): restore the default.
      struct sigaction dfl = {};
      dfl.sa_handler = SIG_DFL;
      sigaction(SIGINT, &dfl, nullptr);
      sigaction(SIGTERM, &dfl, nullptr);
      sigset_t none;
      sigemptyset(&none);
      sigprocmask(SIG_SETMASK, &none, nullptr);
      setpgid(0, 0);
      dup2(fds[1], STDOUT_FILENO);
      dup2(fds[1], STDERR_FILENO);
      execvp(argv[0], argv.data());
      _exit(127);
    }
    setpgid(pid_, pid_);  // as in the child: whichever runs first
    close(fds[1]);
    fd_ = fds[0];
    fcntl(fd_, F_SETFL, O_NONBLOCK);
  }
  ~Child()
  {
    if (pid_ > 0 && !exited_)
    {
      kill(-pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    if (fd_ >= 0)
      close(fd_);
  }

  /// Reads the output until it contains every one of @p texts, the child ends, or @p give_up_s pass.
  bool readUntil(const std::vector<std::string>& texts, double give_up_s)
  {
    const ros::WallTime give_up = ros::WallTime::now() + ros::WallDuration(give_up_s);
    while (ros::WallTime::now() < give_up)
    {
      drain();
      if (std::all_of(texts.begin(), texts.end(),
                      [&](const std::string& t) { return output_.find(t) != std::string::npos; }))
        return true;
      if (!running())
        break;
      ros::WallDuration(0.05).sleep();
    }
    drain();
    return false;
  }
  bool running()
  {
    if (exited_)
      return false;
    exited_ = waitpid(pid_, &status_, WNOHANG) == pid_;
    return !exited_;
  }
  /// SIGINT (as roslaunch stops a node), then its exit status; -1 if it did not exit normally.
  int interrupt()
  {
    if (running())
    {
      kill(-pid_, SIGINT);
      waitpid(pid_, &status_, 0);
      exited_ = true;
    }
    drain();
    return WIFEXITED(status_) ? WEXITSTATUS(status_) : -1;
  }
  const std::string& output()
  {
    drain();
    return output_;
  }

private:
  void drain()
  {
    char buf[512];
    ssize_t n;
    while ((n = read(fd_, buf, sizeof buf)) > 0)
      output_.append(buf, static_cast<size_t>(n));
  }

  pid_t pid_ = -1;
  int fd_ = -1;
  int status_ = 0;
  bool exited_ = false;
  std::string output_;
};
}  // namespace sl_testing

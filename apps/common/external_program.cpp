#include "apps/common/external_program.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <thread>

#include "splat/core/error.hpp"

extern char** environ;

namespace splat::cli {

bool program_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return false;
  std::stringstream folders(path);
  std::string folder;
  while (std::getline(folders, folder, ':')) {
    if (folder.empty()) continue;
    const std::filesystem::path candidate = std::filesystem::path(folder) / name;
    if (::access(candidate.c_str(), X_OK) == 0 && std::filesystem::is_regular_file(candidate)) return true;
  }
  return false;
}

int run_program(const std::vector<std::string>& arguments, const std::filesystem::path& log,
                const std::function<void()>& while_running) {
  std::vector<char*> argv;
  for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  pid_t pid = 0;
  const int started = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (started != 0) throw ArgumentError("cannot run " + arguments[0] + ": " + std::strerror(started));
  int status = 0;
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, while_running ? WNOHANG : 0);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) throw ArgumentError("lost track of " + arguments[0] + ": " + std::strerror(errno));
    if (done == 0) {
      while_running();
      std::this_thread::sleep_for(std::chrono::milliseconds(250));
    }
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

std::string last_line_of_file(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line, last;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  const std::size_t first = last.find_first_not_of(" \t"), end = last.find_last_not_of(" \t\r");
  return first == std::string::npos ? std::string() : last.substr(first, end - first + 1);
}

}  // namespace splat::cli

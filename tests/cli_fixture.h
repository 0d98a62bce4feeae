#pragma once
// The command-line tool as a test sees it: each test gets its own empty folder, runs `eitbench`
// with arguments, and reads back the exit code, the output and the files left behind.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace eitbench {
namespace fs = std::filesystem;

// The bad-input corpus (tests/bad_inputs): files every command must refuse.
inline const std::string kCorpus = EITBENCH_BAD_INPUTS;

// A file's bytes; empty when it cannot be read.
inline std::string file_text(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

struct Result {
  int exit_code;
  std::string output;  // stdout and stderr together
};

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("eitbench_cli_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  Result run(const std::string& args) const { return run_after("", args); }
  // The tool run by `prefix` (an environment, taskset, timeout: "env A=1 ").
  Result run_after(const std::string& prefix, const std::string& args) const {
    return shell(prefix + std::string(EITBENCH_CLI) + " " + args);
  }
  // `command` as a shell runs it: exit code and output (`log_name` names the log in the test's
  // folder, for a command run beside another).
  Result shell(const std::string& command, const std::string& log_name = "log.txt") const {
    const std::string log = path(log_name);
    const int status = std::system((command + " > " + log + " 2>&1").c_str());
    return {WEXITSTATUS(status), file_text(log)};
  }

  // Polls ready() every 2 ms until it holds (true) or 300 s have passed (false): a sanitizer
  // build is 5-10x slower.
  static bool wait_for(const std::function<bool()>& ready) {
    const auto start = std::chrono::steady_clock::now();
    while (!ready()) {
      if (std::chrono::steady_clock::now() - start > std::chrono::seconds(300)) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return true;
  }

  // Starts `eitbench args` in the background, waits until ready() (wait_for), then kills it with
  // SIGKILL. False when ready() never held.
  bool kill_when(const std::string& args, const std::function<bool()>& ready) const {
    const std::string pid_file = path("pid");
    fs::remove(pid_file);
    if (std::system(
            (std::string(EITBENCH_CLI) + " " + args + " > /dev/null 2>&1 & echo $! > " + pid_file)
                .c_str()) != 0)
      return false;
    pid_t pid = 0;
    for (int k = 0; k < 500 && pid == 0; ++k) {
      std::ifstream in(pid_file);
      in >> pid;
      if (pid == 0) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (pid <= 0) return false;
    const bool ok = wait_for(ready);
    ::kill(pid, SIGKILL);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // let the kernel reap it
    return ok;
  }

  std::vector<std::string> files() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir_))
      if (entry.path().filename() != "log.txt") names.push_back(entry.path().filename().string());
    return names;
  }

  fs::path dir_;
};

}  // namespace eitbench

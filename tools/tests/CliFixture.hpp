#pragma once
// The command line as its tests meet it: the binary, the shipped models, a fresh folder per test,
// bash command lines run there with `flexmb` standing for the binary, and the small helpers the CLI
// tests share (a file's text, a search). One fixture for test_cli, test_user_path, test_study_cli and
// test_transfer_cli.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace flexmb::cli_test {

namespace fs = std::filesystem;

inline const std::string kFlexmb = std::string(FLEXMB_BINARY_DIR) + "/flexmb";
inline const std::string kSource = FLEXMB_SOURCE_DIR;
inline const std::string kData = kSource + "/datfiles/";

struct Result {
  int code = -1;  // exit code; 128 + signal when killed
  std::string out, err;
};

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline bool has(const std::string& text, const std::string& needle) { return text.find(needle) != std::string::npos; }

// Runs a bash script in `dir`: `flexmb` starting a command (a line, after ; & | ( or `timeout 120 `)
// is the binary under test. Its stdout and stderr are returned (their files removed when `tidy`).
inline Result runScript(const fs::path& dir, const std::string& script, bool tidy = true) {
  const std::string cmd =
      std::regex_replace(script, std::regex("(^|[;&|(] *|\n *|timeout 120 )flexmb\\b"), "$1" + kFlexmb);
  std::ofstream(dir / "run.sh") << "cd '" << dir.string() << "' || exit 99\n{\n" << cmd << "\n} >out.txt 2>err.txt\n";
  const int status = std::system(("/bin/bash '" + (dir / "run.sh").string() + "'").c_str());
  Result r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.out = slurp(dir / "out.txt");
  r.err = slurp(dir / "err.txt");
  if (tidy)
    for (const char* f : {"out.txt", "err.txt", "run.sh"}) fs::remove(dir / f);
  return r;
}

// A fresh folder per test, named for it (kept when the test fails).
class CliTest : public ::testing::Test {
 protected:
  explicit CliTest(std::string prefix = "flexmb_cli_") : prefix_(std::move(prefix)) {}
  void SetUp() override {
    dir_ = fs::temp_directory_path() / (prefix_ + ::testing::UnitTest::GetInstance()->current_test_info()->name() +
                                        "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }
  Result sh(const std::string& line) { return runScript(dir_, line); }
  Result flexmb(const std::string& args) { return sh("timeout 120 flexmb " + args); }
  // A model in the test folder: `base` from datfiles/ with every match of `from` replaced by `to`.
  std::string variant(const std::string& base, const std::string& from, const std::string& to,
                      const std::string& name = "model.dat") {
    const std::string text = std::regex_replace(slurp(kData + base), std::regex(from), to);
    std::ofstream(dir_ / name) << text;
    return name;
  }
  // The test folder's files, sorted, relative to it.
  std::vector<std::string> files() const {
    std::vector<std::string> v;
    for (const auto& e : fs::recursive_directory_iterator(dir_)) v.push_back(fs::relative(e.path(), dir_).string());
    std::sort(v.begin(), v.end());
    return v;
  }
  std::string listing() const {
    std::string s;
    for (const auto& f : files()) s += f + " ";
    return s;
  }
  fs::path dir_;
  std::string prefix_;
};

}  // namespace flexmb::cli_test

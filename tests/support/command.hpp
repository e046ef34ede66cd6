// Running the project's programs from tests: exit code, stdout and stderr,
// scratch files, the scene files.
#pragma once
#include <cstdlib>
#include <filesystem>
#include <vector>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

namespace xfdem::testing {

struct CommandResult {
  int exit_code;
  std::string out, err;
};

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// A per-process scratch folder named after `tag`.
inline std::filesystem::path scratch(const std::string& tag) {
  auto dir = std::filesystem::temp_directory_path() / ("xfdem_" + tag + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

/// Runs `program args` through the shell, capturing both streams.
inline CommandResult run_command(const std::string& program, const std::string& args) {
  const auto dir = scratch("command");
  const std::string cmd = program + " " + args + " >" + (dir / "out.txt").string() + " 2>" + (dir / "err.txt").string();
  const int status = std::system(cmd.c_str());
  return {WEXITSTATUS(status), slurp(dir / "out.txt"), slurp(dir / "err.txt")};
}

/// Path of a scene file of scenes/.
inline std::string scene_file(const char* name) { return std::string(XFDEM_SOURCE_DIR) + "/scenes/" + name; }

/// The numbers of a CSV file's last row (the run's final sample).
inline std::vector<double> last_csv_row(const std::filesystem::path& csv) {
  std::ifstream in(csv);
  std::string line, last;
  while (std::getline(in, line)) last = line;
  std::vector<double> values;
  std::stringstream row(last);
  for (std::string cell; std::getline(row, cell, ',');) values.push_back(std::stod(cell));
  return values;
}

}  // namespace xfdem::testing

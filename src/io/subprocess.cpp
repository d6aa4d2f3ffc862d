#include "io/subprocess.hpp"

#include <cstdlib>
#include <stdexcept>

#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>

#include "ejecta/build_info.hpp"

extern char** environ;

namespace ejecta::io {

int runProcess(const std::vector<std::string>& argv) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid{};
  if (posix_spawnp(&pid, args[0], nullptr, nullptr, args.data(), environ) != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string pythonInterpreter() {
  if (const char* p = std::getenv("EJECTA_PYTHON"); p && *p) return p;
  if (std::filesystem::exists("/usr/bin/python3")) return "/usr/bin/python3";
  return "python3";
}

std::filesystem::path scriptsDir() {
  if (const char* p = std::getenv("EJECTA_SCRIPTS_DIR"); p && *p) return p;
  return build_info::scripts_dir;
}

void runPlotScript(const std::string& script, const std::filesystem::path& data_json,
                   const std::filesystem::path& out_png) {
  const auto path = scriptsDir() / script;
  if (!std::filesystem::exists(path))
    throw std::runtime_error(fmt::format("plot script {} not found (set EJECTA_SCRIPTS_DIR)", path.string()));
  const int rc = runProcess({pythonInterpreter(), path.string(), data_json.string(), out_png.string()});
  if (rc != 0)
    throw std::runtime_error(fmt::format("plotting failed ({} exited with {}); is python3-matplotlib installed?",
                                         script, rc));
}

void stagePlot(OutputTransaction& outputs, const std::string& script, const std::string& data_json,
               const std::filesystem::path& png) {
  const std::filesystem::path data = temporarySibling(std::filesystem::path(png).replace_extension(".json"));
  writeFileAtomically(data, data_json);
  const auto staged = outputs.reserve(png);
  try {
    runPlotScript(script, data, staged);
  } catch (...) {
    std::filesystem::remove(data);
    throw;
  }
  std::filesystem::remove(data);
}

}  // namespace ejecta::io

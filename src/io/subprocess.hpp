#pragma once
#include <filesystem>

#include "core/atomic_file.hpp"
#include <string>
#include <vector>

namespace ejecta::io {

// Runs a program with arguments (no shell) and waits; returns its exit status, or -1 if it
// could not be started.
int runProcess(const std::vector<std::string>& argv);

// The Python interpreter that has the plotting library (Debian's python3-matplotlib lives under
// /usr/bin/python3): $EJECTA_PYTHON, else /usr/bin/python3, else python3 on PATH.
std::string pythonInterpreter();
// Where the shipped helper scripts are: $EJECTA_SCRIPTS_DIR, else the source tree's scripts/.
std::filesystem::path scriptsDir();

// Runs scripts/<script> DATA.json OUT.png; throws std::runtime_error if it fails.
void runPlotScript(const std::string& script, const std::filesystem::path& data_json,
                   const std::filesystem::path& out_png);

// Makes `png` with scripts/<script> from `data_json` (JSON text, in a temporary file beside it,
// removed afterwards) as one more output of the transaction.
void stagePlot(OutputTransaction& outputs, const std::string& script, const std::string& data_json,
               const std::filesystem::path& png);

}  // namespace ejecta::io

#pragma once
#include <string>

#include <CLI/CLI.hpp>

#include "scenario/run.hpp"

namespace ejecta::cli {

// Each sub-command registers its options and returns the action to run after parsing.
// Actions return the process exit code; they throw InputError for bad input.
using Action = std::function<int()>;
Action addSoilCommand(CLI::App& app);
Action addVerifyCommand(CLI::App& app);
Action addRunCommand(CLI::App& app);
Action addSweepCommand(CLI::App& app);
Action addValidateCommand(CLI::App& app);

// Parses a number given on the command line; `percent_ok` accepts "7%" as 0.07.
// Sets the OpenMP thread count (0: all cores); throws InputError for a negative count.
void applyThreads(int threads);
// `--cell-size MM` as a deck override of mesh.cell_size_m.
std::string cellSizeOverride(const std::string& millimetres);

// A deck file, or the name of a built-in deck (decks/NAME.toml); empty: the default EMI 7% deck.
std::string resolveDeck(const std::string& name);

double parseNumber(const std::string& field, const std::string& text, bool percent_ok = false);

// A study's case (validate, sweep): with `reuse`, a case that an interrupted study left a checkpoint
// of (in its run's staging folder) continues from it, and one that cannot be continued (another
// build, damaged) runs from the start, said on stderr under `label`.
scenario::RunResult runOrContinue(const scenario::Deck& deck, scenario::RunOptions ro, bool reuse, const std::string& label);
// A study's --checkpoint-every MIN (0: none), passed to each case's run.
void addCaseCheckpointOption(CLI::App* sub, double& minutes);

// The number of MPI ranks this process runs among (1 without a launcher or without MPI).
int mpiRanks();
int mpiRank();
bool speaks();             // this process prints for the run (rank 0, or the only process)
std::string rankPrefix();  // "rank N: " on MPI ranks, else nothing

}  // namespace ejecta::cli

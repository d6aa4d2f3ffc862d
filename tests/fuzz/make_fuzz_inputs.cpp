// Writes what the fuzz targets start from into the folder given, generated at build time rather
// than committed so that it follows the code:
//   seeds/checkpoint/   valid checkpoints of the tiny set-ups (envelope and payload) and their bare
//                       payloads (the solver's payload layout)
//   deck.dict           libFuzzer's dictionary for fuzz_deck: TOML syntax, and every key, section,
//                       --set path and word value of the deck's key table
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include <fmt/format.h>

#include "checkpoint_setup.hpp"
#include "core/atomic_file.hpp"
#include "scenario/deck.hpp"

namespace {

void writeCheckpointSeeds(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  for (const bool moving_mesh : {false, true}) {
    auto solver = ejecta::fuzz::tinySolver(moving_mesh);
    std::ostringstream payload;
    solver.writeCheckpoint(payload);
    const std::string name = moving_mesh ? "tiny-moving-mesh" : "tiny";
    ejecta::io::writeCheckpointFile((dir / (name + "-checkpoint.bin")).string(), ejecta::fuzz::expectedHeader(), payload.str());
    ejecta::io::writeFileAtomically(dir / (name + "-payload.bin"), payload.str());
  }
}

// A dictionary entry: printable ASCII as is, quotes and backslashes escaped, the rest as \xNN.
std::string entry(const std::string& word) {
  std::string out = "\"";
  for (const char c : word) {
    if (c == '"' || c == '\\') out += std::string("\\") + c;
    else if (c >= 0x20 && c < 0x7f) out += c;
    else out += fmt::format("\\x{:02x}", static_cast<unsigned char>(c));
  }
  return out + "\"";
}

void writeDeckDictionary(const std::filesystem::path& file) {
  std::set<std::string> words{"=", " = ", "[", "]", "[[", "]]", "{", "}", ",", ".", "\"", "'", "\"\"\"", "'''", "#", "\n", "\\", "\\u", "\\U",
                              "true", "false", "inf", "-inf", "nan", "+nan", "0x", "0o", "0b", "1e", "_", "1979-05-27T07:32:00Z",
                              "07:32:00", "1979-05-27", std::string(1, '\0')};   // NUL: the fuzz input's override separator
  for (const auto& key : ejecta::scenario::deckKeys()) {
    std::string path = key.path;
    if (const auto n = path.find(".N."); n != std::string::npos) path.replace(n, 3, ".0.");
    words.insert(path + "=");
    std::size_t start = 0;
    for (std::size_t dot = path.find('.'); dot != std::string::npos; dot = path.find('.', start)) {
      const std::string section = path.substr(start, dot - start);
      if (start == 0 && section != "0") words.insert({section, "[" + section + "]", "[[" + section + "]]"});
      start = dot + 1;
    }
    words.insert(path.substr(start));
    for (const auto& choice : key.choices) words.insert("\"" + choice + "\"");
  }
  std::ofstream out(file);
  out << "# libFuzzer dictionary for fuzz_deck, written by make_fuzz_inputs from the deck's key table\n";
  for (const auto& w : words) out << entry(w) << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s FOLDER\n", argv[0]);
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  writeCheckpointSeeds(dir / "seeds" / "checkpoint");
  writeDeckDictionary(dir / "deck.dict");
  return 0;
}

#pragma once
#include <filesystem>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace ejecta::io {

// Writes `path` atomically: the content goes to a temporary file in the same directory, is
// flushed, and is renamed over `path` only when complete. An interrupted or failed write
// leaves no partial file behind. Throws std::runtime_error on failure.
void writeFileAtomically(const std::filesystem::path& path,
                         const std::function<void(std::ostream&)>& writer);
void writeFileAtomically(const std::filesystem::path& path, const std::string& content);

// A temporary path beside `path` whose rename onto `path` is atomic (same file system).
std::filesystem::path temporarySibling(const std::filesystem::path& path);

// The whole content of a file; std::nullopt if it cannot be opened.
std::optional<std::string> readWholeFile(const std::filesystem::path& path);

// Collects outputs of one command: each is staged to a temporary sibling, and all are
// renamed into place by commit(). If the transaction is destroyed without commit() (an
// error part way through), the staged files are removed, so nothing is left half-written.
class OutputTransaction {
 public:
  OutputTransaction() = default;
  OutputTransaction(const OutputTransaction&) = delete;
  OutputTransaction& operator=(const OutputTransaction&) = delete;
  ~OutputTransaction();

  // Stages a file written by `writer`; returns the staged (temporary) path.
  std::filesystem::path stage(const std::filesystem::path& final_path,
                              const std::function<void(std::ostream&)>& writer);
  // Reserves a temporary path for a file produced by another program (the plot script).
  std::filesystem::path reserve(const std::filesystem::path& final_path);
  void commit();
  // Removes everything staged so far (also done by the destructor when commit() never ran).
  void discard();

 private:
  std::vector<std::pair<std::filesystem::path, std::filesystem::path>> staged_;  // temp, final
  bool committed_ = false;
};

}  // namespace ejecta::io

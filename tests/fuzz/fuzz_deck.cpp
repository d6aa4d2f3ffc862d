// libFuzzer target: the deck reader, parseDeck, with its --set overrides.
// The input is the deck's text, then optionally NUL-separated override lines ("key=value"): a NUL
// is never valid in a deck's TOML, so splitting there costs the fuzzer nothing it could reach.
// Refusing garbage with an InputError is the correct outcome; any other exception, a crash, a
// hang or a sanitizer report is a bug.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <typeinfo>
#include <vector>

#include "core/error.hpp"
#include "scenario/deck.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  std::string text;
  std::vector<std::string> overrides;
  std::size_t start = input.find('\0');
  text = input.substr(0, start);
  while (start != std::string::npos) {
    const std::size_t next = input.find('\0', start + 1);
    overrides.push_back(input.substr(start + 1, next == std::string::npos ? std::string::npos : next - start - 1));
    start = next;
  }
  try {
    ejecta::scenario::parseDeck(text, overrides, "fuzz.toml");
  } catch (const ejecta::InputError&) {
    // the deck was refused, naming the key: what bad input should get
  } catch (const std::exception& e) {
    std::fprintf(stderr, "parseDeck threw %s (not an InputError): %s\n", typeid(e).name(), e.what());
    std::abort();
  }
  return 0;
}

#pragma once
// Bad-input tests of the study readers: edit a good file (replace the first `from` with `to`) and
// require that loading it throws an InputError whose message names the file and the key (`needle`).
#include <catch2/catch.hpp>

#include <string>

#include "dem/input_error.hpp"
#include "tests/temp_dir.hpp"

namespace grainscale::testing {

/// Replaces the first `from` in `file` by `to`; nothing when `from` is empty. `from` must occur.
inline void replace_in_file(const std::string& file, const std::string& from, const std::string& to) {
  if (from.empty()) return;
  std::string text = slurp(file);
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  text.replace(at, from.size(), to);
  write_text(file, text);
}

/// `load(file)` must throw an InputError naming `file_name` and `needle`; `label` says which case failed.
template <class Load>
void require_input_error(const std::string& file, Load load, const std::string& file_name, const std::string& needle,
                         const std::string& label) {
  try {
    load(file);
    FAIL("no error for: " << label);
  } catch (const InputError& e) {
    const std::string what = e.what();
    INFO(what);
    CHECK(what.find(file_name) != std::string::npos);
    CHECK(what.find(needle) != std::string::npos);
  }
}

}  // namespace grainscale::testing

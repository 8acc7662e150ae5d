#pragma once
// Results are written atomically: to `path.tmp`, flushed and closed, then renamed over `path`, so a
// crash or a full disk never leaves a half-written file where a good one was.
#include <string>

namespace grainscale::dem {

/// Throws std::runtime_error naming the path and the reason if any step fails.
void write_file_atomically(const std::string& path, const std::string& content);

}  // namespace grainscale::dem

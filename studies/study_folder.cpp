#include "studies/study_folder.hpp"

#include <chrono>
#include <filesystem>
#include <iostream>
#include <stdexcept>

namespace grainscale::studies {

namespace fs = std::filesystem;

double wall_seconds_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

StudyFolder::StudyFolder(const std::string& directory, const std::vector<std::string>& inputs, bool resume)
    : dir_(fs::absolute(directory).lexically_normal().string()) {
  std::error_code ec;
  fs::create_directories(path("inputs"), ec);
  if (ec || !fs::is_directory(path("inputs"))) {
    throw std::runtime_error("cannot create the study folder " + dir_ + ": " + ec.message());
  }
  log_.open(path("log.txt"), resume ? std::ios::app : std::ios::trunc);
  if (!log_) throw std::runtime_error("cannot write " + path("log.txt"));
  for (const std::string& f : inputs) copy_input(f);
}

std::string StudyFolder::path(const std::string& relative) const {
  return (fs::path(dir_) / relative).lexically_normal().string();
}

void StudyFolder::log(const std::string& line) {
  std::cerr << "[study] " << line << "\n";
  if (log_) log_ << line << std::endl;
}

void StudyFolder::copy_input(const std::string& file) {
  std::error_code ec;
  fs::copy_file(file, path("inputs/" + fs::path(file).filename().string()), fs::copy_options::overwrite_existing, ec);
  if (ec) throw std::runtime_error("cannot copy " + file + " into " + path("inputs") + ": " + ec.message());
}

}  // namespace grainscale::studies

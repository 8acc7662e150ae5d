#pragma once
// `grainscale study FILE.yaml` for every kind of study. A study file's top-level `kind` key (default
// `platform`) picks the runner; each kind is one function plus one line in study_kinds.cpp's table.
//
//   platform   DEM -> coarse-graining -> fit -> prediction -> report (study_run.hpp)
//   (the other kinds are listed in study_kinds.cpp and docs/studies.md)
//
// Every kind writes the same kind of folder (study_folder.hpp: inputs/, log.txt, report.md) and
// reads its file with the checked YAML reader, so a typo is an InputError naming file, line and key.
#include <string>
#include <vector>

#include "studies/study_run.hpp"

namespace grainscale::studies {

/// Runs the study file end to end; returns the path of its report.md. Throws InputError.
using StudyKindRunner = std::string (*)(const std::string& study_file, const StudyOptions& options);

struct StudyKind {
  const char* name;
  const char* what;  // one line for --help and error messages
  StudyKindRunner run;
};

/// Every registered kind, in the order --help lists them.
const std::vector<StudyKind>& study_kinds();

/// The `kind` key of a study file ("platform" if absent). Throws InputError for an unknown kind,
/// naming the file, the line and the kinds there are.
const StudyKind& study_kind_of(const std::string& study_file);

/// The command line: `grainscale study FILE.yaml [--out DIR] [--threads N] [--resume]`.
int study_command(const std::vector<std::string>& positional, const std::string& out, const std::string& threads,
                  bool resume);

}  // namespace grainscale::studies

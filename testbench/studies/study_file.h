// Study files (configs/studies/ID.yaml): a study is the runs behind one generated block of a doc
// (`<!-- generated: ID -->` ... `<!-- end generated: ID -->`) and the table it renders there. Each
// run is a sweep file, a reproduction (`rtsim reproduce`, `--ablation` or `--bvh`), an animation
// or a program of the build, with its options, in a sub-directory of the study's. Paths are
// relative to the study file. Format: configs/studies/ and docs/reports.md.
#pragma once

#include "reports/study_tables.h"

#include <string>
#include <vector>

namespace rtsim {

struct StudyRun {
  std::string dir;        // sub-directory of the study's output ("": the study's directory)
  std::string kind;       // "sweep", "reproduce", "animate" or "program"
  std::string file;       // sweep: the sweep file; animate: the scene file; reproduce: the
                          // sweep file instead of the shipped one (empty: the shipped one)
  std::string reproduce;  // reproduce: paper, ablation or the BVH study (kBvhFamily)
  std::vector<std::string> variants;           // sweep, reproduce: only these variants (empty: all)
  std::vector<std::string> set;                // --set PATH=VALUE overrides of every point
  std::string sample;                          // reproduce, animate: --sample F (empty: full runs)
  bool plots = true;                           // sweep: draw its figures
  std::string hw, times, lvb = "both";         // animate
  int width = 0, height = 0, check_every = 0;  // animate (0: the scene's, none)
  std::vector<std::string> program;            // program: its path in the source tree, arguments
};

struct StudySpec {
  std::string file, id, doc;  // doc: the page that holds the block (absolute)
  double minutes = 0;         // what a sitting takes on 2 cores, for --list
  int jobs = 0;               // runs at once when the study times its runs (0: --jobs)
  std::vector<StudyRun> runs;
  report::StudyTable table;
  std::string figure_from, figure_to;  // a figure of the runs and its copy (empty: none)
};

// The folder of the shipped studies, and the file of study NAME: NAME itself when it is a path
// to a .yaml file, else configs/studies/NAME.yaml.
std::string studies_dir();
std::string study_file_of(const std::string& name);
// Reads and checks a study file; an InputError naming the file and the key otherwise.
StudySpec load_study(const std::string& path);
// The shipped studies' files, sorted by name.
std::vector<std::string> study_files();
// `path` relative to the source tree when it lies in it, else as given.
std::string source_relative(const std::string& path);
// A run as the command it stands for ("rtsim sweep configs/sweeps/x.yaml --no-plots"), paths
// relative to the source tree.
std::string describe_run(const StudyRun& run);

}  // namespace rtsim

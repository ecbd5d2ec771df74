#include "testbench/studies/slurm.h"

#include "common/error.h"
#include "reports/output_files.h"
#include "testbench/studies/sweep_results.h"

#include <fmt/format.h>

#include <filesystem>

namespace fs = std::filesystem;

namespace rtsim {

namespace {

// #SBATCH lines cannot quote: the scripts' paths must be plain.
void check_plain(const std::vector<std::string>& paths) {
  for (const std::string& p : paths)
    if (p.find_first_of(" \t\n'\"$`\\") != std::string::npos)
      throw InputError(fmt::format(
          "--emit slurm: the path '{}' has a space, quote or shell character; use a plain path",
          p));
}

std::string absolute(const std::string& path) {
  return fs::absolute(path).lexically_normal().string();
}

}  // namespace

int emit_slurm(const SweepSpec& s, const std::string& dir) {
  claim_sweep_directory(s, dir);
  const fs::path abs_dir = absolute(dir);
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  check_plain({abs_dir.string(), self, fs::current_path().string()});
  const std::string script = fmt::format(
      "#!/bin/bash\n# rtsim sweep '{name}' as a Slurm job array: one task per point of "
      "{dir}/manifest.json.\n# Submit with: sbatch {dir}/sweep.sbatch    Then gather: rtsim sweep "
      "--merge {dir}\n#SBATCH --job-name=rtsim-{name}\n#SBATCH --array=0-{last}\n#SBATCH "
      "--cpus-per-task=1\n#SBATCH --output={dir}/points/slurm-%A_%a.out\nset -euo "
      "pipefail\nRTSIM=\"${{RTSIM:-{self}}}\"\n# Scene and hardware paths in the manifest are "
      "relative to where the sweep was emitted.\ncd '{cwd}'\nexec \"$RTSIM\" sweep --out '{dir}' "
      "--point \"$SLURM_ARRAY_TASK_ID\"\n",
      fmt::arg("name", s.name), fmt::arg("dir", abs_dir.string()),
      fmt::arg("last", s.points.size() - 1), fmt::arg("self", self),
      fmt::arg("cwd", fs::current_path().string()));
  fs::create_directories(abs_dir / output::kPointsDir);
  write_file_atomic((abs_dir / "sweep.sbatch").string(), script);
  fmt::print(
      "wrote {0}/sweep.sbatch ({1} array tasks) and {0}/manifest.json\nsubmit: sbatch "
      "{0}/sweep.sbatch; then: rtsim sweep --merge {0}\n",
      abs_dir.string(), s.points.size());
  return 0;
}

int emit_study_slurm(const std::string& id, const std::string& study_file, const std::string& dir,
                     const std::vector<std::string>& arrays) {
  const std::string out = absolute(dir), file = absolute(study_file);
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  std::vector<std::string> paths{out, file, self, fs::current_path().string(), id};
  std::string submit;
  for (const std::string& a : arrays) {
    paths.push_back(absolute(a));
    submit += fmt::format(" '{}/sweep.sbatch'", absolute(a));
  }
  check_plain(paths);
  const std::string job = fmt::format(
      "#!/bin/bash\n# rtsim study '{id}': gathers its runs once their job arrays completed "
      "(submitted "
      "by {out}/study.sh).\n# Nothing is left to simulate: the reproductions' reports, the "
      "programs' output and\n# {out}/table.md are written here.\n#SBATCH "
      "--job-name=rtsim-study-{id}\n"
      "#SBATCH --cpus-per-task=1\n#SBATCH --output={out}/study-%j.out\nset -euo pipefail\n"
      "RTSIM=\"${{RTSIM:-{self}}}\"\ncd '{cwd}'\nexec \"$RTSIM\" study '{file}' --out '{out}' "
      "--jobs 1\n",
      fmt::arg("id", id), fmt::arg("out", out), fmt::arg("self", self),
      fmt::arg("cwd", fs::current_path().string()), fmt::arg("file", file));
  const std::string script = fmt::format(
      "#!/bin/bash\n# rtsim study '{id}' on Slurm: submits each run's job array, then "
      "{out}/study.sbatch\n# once they all completed. Run: bash {out}/study.sh    ($RTSIM, if set, "
      "is the binary\n# every job runs.)\nset -euo pipefail\nafter=\nfor array in{submit}; do\n"
      "  job=$(sbatch --parsable \"$array\")\n  after=\"$after:${{job%%;*}}\"\ndone\n"
      "sbatch --parsable ${{after:+--dependency=afterok$after}} '{out}/study.sbatch'\n",
      fmt::arg("id", id), fmt::arg("out", out), fmt::arg("submit", submit));
  write_file_atomic(out + "/study.sbatch", job);
  write_file_atomic(out + "/study.sh", script);
  fmt::print(
      "wrote {0}/study.sh ({1} job arrays, then {0}/study.sbatch, which gathers them into "
      "{0}/table.md)\nsubmit: bash {0}/study.sh; then `rtsim study {2} --out {0} --table-only "
      "--write-doc` puts the table in its doc\n",
      out, arrays.size(), file);
  return 0;
}

}  // namespace rtsim

#include "testbench/studies/slurm.h"

#include "common/error.h"
#include "reports/output_files.h"
#include "testbench/studies/sweep_results.h"

#include <fmt/format.h>

#include <filesystem>

namespace fs = std::filesystem;

namespace rtsim {

int emit_slurm(const SweepSpec& s, const std::string& dir) {
  claim_sweep_directory(s, dir);
  const fs::path abs_dir = fs::absolute(dir).lexically_normal();
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  // #SBATCH lines cannot quote: keep the paths plain.
  for (const std::string& p : {abs_dir.string(), self, fs::current_path().string()})
    if (p.find_first_of(" \t\n'\"$`\\") != std::string::npos)
      throw InputError(fmt::format(
          "--emit slurm: the path '{}' has a space, quote or shell character; use a plain path",
          p));
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

}  // namespace rtsim

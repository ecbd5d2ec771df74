// The paper's published figures (configs/paper/tables.yaml): Tables 3-6 per setup, which the
// reproduction and ablation reports print beside ours.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace rtsim::report {

struct PaperScene {
  std::string name;  // the paper's setup (bunny, kitchen, robots)
  std::string title;
  double triangles = 0, lights = 0, nodes = 0, leaves = 0, rays_per_light = 0;
  int width = 0, height = 0;                       // the frame its counts and milliseconds are of
  std::vector<double> culled_leaves, culled_rays;  // per light (Tables 4 and 5)
  double all_on = 0, all_off = 0, shadow_on = 0, shadow_off = 0;  // ms (Table 6)
};

// By setup name (bunny, kitchen, robots, and each one's `also` names). Throws InputError naming the
// file and key.
std::map<std::string, PaperScene> load_paper_tables(const std::string& path);

}  // namespace rtsim::report

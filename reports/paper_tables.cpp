#include "reports/paper_tables.h"

#include "common/yaml_reader.h"

namespace rtsim::report {

std::map<std::string, PaperScene> load_paper_tables(const std::string& path) {
  YamlMap top = YamlMap::load_file(path);
  std::map<std::string, PaperScene> out;
  for (const std::string& name : top.keys()) {
    YamlMap m = top.map(name);
    PaperScene p;
    p.name = name;
    p.title = m.require<std::string>("title");
    p.triangles = m.require<double>("triangles");
    const auto res = m.require<std::vector<int>>("resolution");
    if (res.size() != 2 || res[0] <= 0 || res[1] <= 0)
      m.fail("resolution", "expected [width, height], both positive");
    p.width = res[0];
    p.height = res[1];
    p.lights = m.require<double>("lights");
    p.nodes = m.require<double>("nodes");
    p.leaves = m.require<double>("leaves");
    p.culled_leaves = m.require<std::vector<double>>("culled_leaves");
    p.culled_rays = m.require<std::vector<double>>("culled_rays");
    p.rays_per_light = m.require<double>("shadow_rays_per_light");
    YamlMap ms = m.map("ms");
    p.all_on = ms.require<double>("all_on");
    p.all_off = ms.require<double>("all_off");
    p.shadow_on = ms.require<double>("shadow_on");
    p.shadow_off = ms.require<double>("shadow_off");
    ms.finish();
    // Our other setups of the same scene (bunny-10k, the paper-sized trees) compare with it too.
    const auto also = m.get<std::vector<std::string>>("also", {});
    m.finish();
    out[name] = p;
    for (const std::string& a : also) out[a] = p;
  }
  return out;
}

}  // namespace rtsim::report

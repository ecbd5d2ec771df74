// The scene description file (YAML): which geometry to load, at what time, seen by which camera,
// lit by which lights. Format: docs/scene-files.md.
// It composes the loaders and the kd-tree parameters, so it lives in config_loader/, above both
// scene_loader/ and kernels/ (rtsim::config in the package, with the hardware file's reader).
#pragma once

#include "common/yaml_reader.h"
#include "kernels/bvh.h"
#include "kernels/kdtree.h"
#include "scene/scene.h"

#include <string>
#include <vector>

namespace rtsim {

struct SceneFileOptions {
  std::string scene_root;  // relative geometry paths resolve here; empty = default_scene_root()
  std::vector<ConfigOverride> overrides;  // "--set scene.KEY=VALUE", applied to the file's keys
};

// $RTSIM_SCENE_ROOT, else ../shared/scenes (from the working directory, then from the source
// tree) when it exists, else the working directory.
std::string default_scene_root();

// What a scene file describes: the scene, and how to build its kd-tree and its BVHs (the
// branching factor comes from the run's acceleration structure, run.accel).
struct SceneSetup {
  Scene scene;
  KdTreeParams kdtree;
  BvhConfig bvh;
};

// Loads the scene a YAML file describes; every error names the file, line and key.
SceneSetup load_scene_file(const std::string& path, const SceneFileOptions& options = {});

}  // namespace rtsim

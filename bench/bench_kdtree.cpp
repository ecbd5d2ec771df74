// kd-tree build time. Usage:
//   bench_kdtree [FILE.ply] [--aff FILE.aff] [--time T] [--runs N]
//                [--ki K_I] [--kt K_T] [--empty-bonus B] [--max-depth D] [--max-prims M]
// Default scene: ../shared/scenes/bunny/bun_zipper.ply. Prints every build's time, the median and
// the tree statistics (single-threaded build).
#include "bench/bench_util.h"
#include "kernels/kdtree.h"
#include "scene/scene.h"

#include "scene_loader/aff_loader.h"
#include "scene_loader/ply_loader.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <string>
#include <vector>

namespace {

[[noreturn]] void usage(const char* msg) {
  std::fprintf(
      stderr,
      "bench_kdtree: %s\nusage: bench_kdtree [FILE.ply] [--aff FILE.aff] [--time T] [--runs N]\n   "
      "    [--ki K_I] [--kt K_T] [--empty-bonus B] [--max-depth D] [--max-prims M]\n",
      msg);
  std::exit(2);
}

// What the command line asks for.
struct Options {
  std::string ply = std::string(RTSIM_SOURCE_DIR) + "/../shared/scenes/bunny/bun_zipper.ply";
  std::string aff;
  double time = 0.0;
  int runs = 5;
  rtsim::KdTreeParams params;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> const char* {
      if (i + 1 >= argc) usage(("missing value after " + a).c_str());
      return argv[++i];
    };
    if (a == "--aff")
      o.aff = value();
    else if (a == "--time")
      o.time = std::atof(value());
    else if (a == "--runs")
      o.runs = std::max(1, std::atoi(value()));
    else if (a == "--ki")
      o.params.intersection_cost = float(std::atof(value()));
    else if (a == "--kt")
      o.params.traversal_cost = float(std::atof(value()));
    else if (a == "--empty-bonus")
      o.params.empty_bonus = float(std::atof(value()));
    else if (a == "--max-depth")
      o.params.max_depth = std::atoi(value());
    else if (a == "--max-prims")
      o.params.max_prims_per_leaf = std::atoi(value());
    else if (!a.empty() && a[0] == '-')
      usage(("unknown option " + a).c_str());
    else
      o.ply = a;
  }
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace rtsim;
  const Options o = parse(argc, argv);
  const std::string &ply = o.ply, &aff = o.aff;
  const double time = o.time;
  const int runs = o.runs;
  const KdTreeParams& params = o.params;

  Scene scene;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    if (!aff.empty()) {
      load_aff(aff, time, scene);
    } else {
      load_ply(ply, 0, scene);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_kdtree: %s\n", e.what());
    return 2;
  }
  const double load_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("scene: %s\ntriangles: %zu (loaded in %.3f s)\n",
              aff.empty() ? ply.c_str() : aff.c_str(), scene.triangles.size(), load_s);
  std::printf("params: K_T %.3g  K_I %.3g  empty bonus %.3g  max depth %d  max prims %d\n",
              params.traversal_cost, params.intersection_cost, params.empty_bonus, params.max_depth,
              params.max_prims_per_leaf);

  // Wall time is what build_kdtree reports; CPU time shows whether other load on the machine
  // inflated it.
  std::vector<double> wall, cpu;
  KdTree tree;
  for (int r = 0; r < runs; ++r) {
    const std::clock_t c0 = std::clock();
    tree = build_kdtree(scene.triangles, params);
    const double c = double(std::clock() - c0) / CLOCKS_PER_SEC;
    wall.push_back(tree.stats.build_seconds);
    cpu.push_back(c);
    std::printf("build %d: %.3f s (cpu %.3f s)\n", r + 1, tree.stats.build_seconds, c);
  }
  std::printf("median: %.3f s (cpu %.3f s) over %d builds\n", bench::median(wall),
              bench::median(cpu), runs);

  const KdTreeStats& s = tree.stats;
  std::printf("nodes %llu (inner %llu, leaves %llu, empty %llu)\n", (unsigned long long)s.nodes,
              (unsigned long long)s.inner_nodes, (unsigned long long)s.leaves,
              (unsigned long long)s.empty_leaves);
  std::printf("prim refs %llu (%.2f per triangle), mean %.2f / max %u per non-empty leaf\n",
              (unsigned long long)s.prim_refs,
              scene.triangles.empty() ? 0.0 : double(s.prim_refs) / double(scene.triangles.size()),
              s.mean_prims_per_leaf, s.max_prims_per_leaf);
  std::printf("depth %d (limit %d), SAH cost %.3f\n", s.max_depth, s.depth_limit, s.sah_cost);
  return 0;
}

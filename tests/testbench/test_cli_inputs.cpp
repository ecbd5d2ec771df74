// Bad input to the rtsim command: exit code 2 and one clear message naming the file, the line or
// key and what was expected, for every kind of file and setting.
#include "tests/test_util.h"
#include "tests/testbench/cli_util.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

namespace rtsim::cli_test {
namespace {

TEST(Cli, BadHardwareConfigsAreNamed) {
  const fs::path dir = test::temp_dir("cli_hw");
  const std::string scene = (test::source_dir() / "configs/scenes/city.yaml").string();
  auto check = [&](const std::string& name, const std::string& yaml,
                   const std::vector<std::string>& fragments) {
    write(dir / name, yaml);
    expect_input_error(
        "run " + scene + " --hw " + (dir / name).string() + " --out " + (dir / "o").string(),
        fragments);
  };
  check("unknown.yaml", "trv:\n  count: 4\n  cache: 3\n",
        {"unknown.yaml:3", "trv.cache", "unknown key"});
  check("type.yaml", "clock_ghz: fast\n", {"type.yaml:1", "clock_ghz", "expected a number"});
  check("negative.yaml", "trv:\n  l1: {size_kb: -8}\n",
        {"negative.yaml:2", "trv.l1.size_kb", "got -8"});
  check("sets.yaml", "trv:\n  l1: {size_kb: 24, ways: 2}\n",
        {"sets.yaml:2", "trv.l1", "power of two"});
  check("ways.yaml", "ist:\n  l1: {size_kb: 1, ways: 32, line_bytes: 64}\n",
        {"ways.yaml:2", "ist.l1"});
  check("preset.yaml", "dram: {preset: ddr9}\n", {"preset.yaml:1", "dram.preset", "gddr3-gt200"});
  check("sharing.yaml", "trv:\n  l2: {sharing: pooled}\n",
        {"sharing.yaml:2", "trv.l2.sharing", "'unit'"});
  check("banks.yaml", "ist:\n  l2: {banks: 3}\n", {"banks.yaml:2", "ist.l2", "banks"});
  check("ports.yaml", "list:\n  l1: {ports: 65}\n", {"ports.yaml:2", "list.l1.ports"});
  check("fill.yaml", "list:\n  l1: {fill_port: dual}\n",
        {"fill.yaml:2", "list.l1.fill_port", "'separate'"});
  check("link.yaml", "memory_link: {bytes_per_cycle: -32}\n",
        {"link.yaml:1", "memory_link.bytes_per_cycle"});
  check("link2.yaml", "shading:\n  link: {latency: 2}\n",
        {"link2.yaml:2", "shading.link", "unknown key"});
  check("records.yaml", "culling: {records_per_cycle: 1}\nshading: {write_records: false}\n",
        {"records.yaml", "culling.records_per_cycle", "write_records"});
  check("rate.yaml", "culling: {records_per_cycle: 65}\n",
        {"rate.yaml:1", "culling.records_per_cycle"});
  check("raygen.yaml", "raygen: {rays_per_cycle: 0}\n", {"raygen.yaml:1", "raygen.rays_per_cycle"});
  expect_input_error("run " + scene + " --hw " + (dir / "missing.yaml").string() + " --out " +
                         (dir / "o").string(),
                     {"missing.yaml", "not found"});
  fs::remove_all(dir);
}

TEST(Cli, MissingSceneFileIsAnInputError) {
  expect_input_error("info /nonexistent/scene.yaml", {"/nonexistent/scene.yaml", "not found"});
}

TEST(Cli, UnknownYamlKeyIsNamed) {
  const fs::path dir = test::temp_dir("cli_yaml");
  write(dir / "s.yaml",
        "name: t\ngeometry:\n  - procedural: {kind: city, blocks: 2}\nresolution: [8, 8]\ncolour: "
        "red\n");
  expect_input_error("info " + (dir / "s.yaml").string(), {"s.yaml:5", "colour", "unknown key"});
  write(dir / "n.yaml", "geometry:\n  - procedural: {kind: city, blocks: 2, seeds: 3}\n");
  expect_input_error("info " + (dir / "n.yaml").string(),
                     {"n.yaml:2", "geometry[0].procedural.seeds"});
  write(dir / "r.yaml", "geometry:\n  - procedural: {kind: city}\nresolution: [8, -8]\n");
  expect_input_error("info " + (dir / "r.yaml").string(), {"r.yaml:3", "resolution", "expected"});
  // simplify: a count of at least 4, on an entry of one material (the city has several).
  const std::string quad =
      "geometry:\n  - triangles: {vertices: [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], indices: "
      "[[0, 1, 2], [0, 2, 3]]}\n    simplify: ";
  write(dir / "s0.yaml", quad + "{triangles: 2}\n");
  expect_input_error("info " + (dir / "s0.yaml").string(), {"s0.yaml", "simplify.triangles"});
  write(dir / "s1.yaml", quad + "{}\n");
  expect_input_error("info " + (dir / "s1.yaml").string(), {"s1.yaml", "simplify.triangles"});
  write(dir / "s2.yaml",
        "geometry:\n  - procedural: {kind: city, blocks: 2}\n    simplify: "
        "{triangles: 100}\n");
  expect_input_error("info " + (dir / "s2.yaml").string(), {"s2.yaml", "simplify", "one material"});
  fs::remove_all(dir);
}

TEST(Cli, ValuesThatWouldMakeNoImageAreRejected) {
  const fs::path dir = test::temp_dir("cli_values");
  const std::string geo = "geometry:\n  - procedural: {kind: city, blocks: 2}\n";
  write(dir / "nan.yaml", geo + "camera: {eye: [0, 0, 5], dir: [0, 0, -1], vfov_deg: .nan}\n");
  expect_input_error("info " + (dir / "nan.yaml").string(),
                     {"nan.yaml:3", "camera.vfov_deg", "finite"});
  write(dir / "twice.yaml", geo + "resolution: [8, 8]\nresolution: [16, 8]\n");
  expect_input_error("info " + (dir / "twice.yaml").string(),
                     {"twice.yaml:4", "resolution", "twice"});
  write(dir / "null.yaml", geo + "resolution: ~\n");
  expect_input_error("info " + (dir / "null.yaml").string(),
                     {"null.yaml:3", "resolution", "no value"});
  write(dir / "range.yaml", "geometry:\n  - procedural: {kind: city, blocks: -3}\n");
  expect_input_error("info " + (dir / "range.yaml").string(),
                     {"range.yaml:2", "procedural.blocks", "[1, 1024]"});
  write(dir / "huge.yaml", "geometry:\n  - procedural: {kind: city, blocks: 400}\n");
  expect_input_error("info " + (dir / "huge.yaml").string(),
                     {"huge.yaml:2", "procedural.blocks", "at most 16777216"});
  write(dir / "verts.yaml", "geometry:\n  - triangles: {vertices: {a: 1}, indices: [[0, 1, 2]]}\n");
  expect_input_error("info " + (dir / "verts.yaml").string(),
                     {"verts.yaml:2", "vertices", "expected a list"});
  // The camera of a geometry file is checked like one given here.
  write(dir / "flat.nff",
        "v\nfrom 0 0 5\nat 0 0 0\nup 0 0 1\nangle 40\nhither 1\nresolution 8 8\nl 0 5 0\np 3\n0 0 "
        "0\n1 0 0\n0 1 0\n");
  write(dir / "nff.yaml", "geometry:\n  - file: flat.nff\n");
  expect_input_error("info " + (dir / "nff.yaml").string() + " --scene-root " + dir.string(),
                     {"nff.yaml", "up", "parallel"});
  expect_input_error("info " + dir.string(), {"not a regular file"});
  fs::remove_all(dir);
}

TEST(Cli, MissingGeometryFileIsNamed) {
  const fs::path dir = test::temp_dir("cli_geom");
  write(dir / "s.yaml", "geometry:\n  - file: nowhere/model.ply\n");
  expect_input_error("info " + (dir / "s.yaml").string() + " --scene-root " + dir.string(),
                     {"s.yaml:2", "nowhere/model.ply", "not found"});
  fs::remove_all(dir);
}

TEST(Cli, MalformedGeometryFilesAreInputErrors) {
  const fs::path dir = test::temp_dir("cli_bad");
  const std::string cam =
      "camera: {eye: [0, 0, 5], at: [0, 0, 0], vfov_deg: 40}\nlights: {add: [{position: [0, 5, "
      "5]}]}\n";
  // PLY whose face count is larger than the data.
  write(dir / "bad.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
        "float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 "
        "0\n0 1 0\n3 0 1 2\n");
  write(dir / "ply.yaml", "geometry:\n  - file: bad.ply\n" + cam);
  expect_input_error("info " + (dir / "ply.yaml").string() + " --scene-root " + dir.string(),
                     {"bad.ply"});
  // OBJ face index out of range.
  write(dir / "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
  write(dir / "obj.yaml", "geometry:\n  - file: bad.obj\n" + cam);
  expect_input_error("info " + (dir / "obj.yaml").string() + " --scene-root " + dir.string(),
                     {"bad.obj", "4"});
  // AFF with an unknown keyword, and one cut short inside a polygon.
  write(dir / "unknown.aff", "l 0 5 0\nzz 1 2 3\n");
  write(dir / "aff.yaml", "geometry:\n  - file: unknown.aff\n" + cam);
  expect_input_error("info " + (dir / "aff.yaml").string() + " --scene-root " + dir.string(),
                     {"unknown.aff:2", "zz"});
  // rotation_keys: bart or all, and only for AFF/NFF.
  write(dir / "ok.aff", "l 0 5 0\np 3\n0 0 0\n1 0 0\n0 1 0\n");
  write(dir / "rot.yaml", "geometry:\n  - file: ok.aff\n    rotation_keys: sideways\n" + cam);
  expect_input_error("info " + (dir / "rot.yaml").string() + " --scene-root " + dir.string(),
                     {"rot.yaml:3", "rotation_keys", "'bart'"});
  write(dir / "rotobj.yaml", "geometry:\n  - file: bad.obj\n    rotation_keys: all\n" + cam);
  expect_input_error("info " + (dir / "rotobj.yaml").string() + " --scene-root " + dir.string(),
                     {"rotobj.yaml:3", "rotation_keys", "only AFF/NFF"});
  write(dir / "short.aff", "l 0 5 0\np 3\n0 0 0\n1 0 0\n");
  write(dir / "short.yaml", "geometry:\n  - file: short.aff\n" + cam);
  expect_input_error("info " + (dir / "short.yaml").string() + " --scene-root " + dir.string(),
                     {"short.aff"});
  fs::remove_all(dir);
}

TEST(Cli, BadOverridesAndRunSettingsAreNamed) {
  const fs::path dir = test::temp_dir("cli_set");
  const std::string hw = (test::source_dir() / "configs/hw/tni-paper.yaml").string();
  const std::string scene = (test::source_dir() / "configs/scenes/city.yaml").string();
  const std::string base =
      "run " + scene + " --hw " + hw + " --out " + (dir / "o").string() + " --set ";
  expect_input_error(base + "hw.trv.l1.sise_kb=8",
                     {"--set hw.trv.l1.sise_kb=8", "trv.l1.sise_kb", "unknown key"});
  expect_input_error(base + "hw.trv.l1.ways=two",
                     {"--set hw.trv.l1.ways=two", "expected an integer"});
  expect_input_error(base + "hw.ist.l2.size_kb=-16", {"ist.l2.size_kb", "got -16"});
  expect_input_error(base + "hw.trv.l2.size_kb=96", {"trv.l2.size_kb", "power of two"});
  expect_input_error(base + "hw.list.l1.ways=128", {"list.l1", "exceeds the number of lines"});
  expect_input_error(base + "scene.kdtree.max_depth=deep",
                     {"city.yaml", "kdtree.max_depth", "expected an integer"});
  expect_input_error(base + "run.lvb=sometimes", {"--set run.lvb=sometimes", "true or false"});
  expect_input_error(base + "run.lvb_bounds=sphere", {"lvb_bounds", "'cell' or 'geometry'"});
  expect_input_error(base + "run.lvb_frustum_test=inside",
                     {"lvb_frustum_test", "'overlap' or 'contained'"});
  expect_input_error(base + "hw.shading.count=65", {"shading.count", "[1, 64]"});
  expect_input_error(base + "hw.dram.tRCD=0", {"dram.tRCD", "[1, 1000]"});
  expect_input_error(base + "hw.schedule=eager",
                     {"--set hw.schedule=eager", "'two-phase' or 'one-phase'"});
  expect_input_error(base + "cache.size=3", {"--set cache.size=3", "'hw.', 'scene.' or 'run.'"});
  expect_input_error(base + "hw.trv", {"--set hw.trv", "no '='"});
  // tests/fuzz/fuzz.py seed 23, case 585: yaml-cpp reads "[8, 8]" and stops, the rest of the text
  // (with a byte that is not UTF-8) reached config.json: "internal error", exit 1
  expect_input_error(base + "'scene.resolution=[8, 8]x\xff]'", {"--set", "not UTF-8 text"});
  expect_input_error(
      "run " + (dir / "nothere.yaml").string() + " --hw " + hw + " --out " + (dir / "o").string(),
      {"nothere.yaml", "not found"});
  expect_input_error("run " + scene + " --hw " + hw + " --out " + (dir / "o").string() +
                         " --trace t.vcd --trace-window 9:3",
                     {"--trace-window 9:3", "START < END"});
  expect_input_error(
      "run --config " + (dir / "none.json").string() + " --out " + (dir / "o").string(),
      {"none.json", "not found"});
  write(dir / "bad_config.json",
        "{\"scene_file\": \"" + scene + "\", \"hw\": {}, \"run\": {\"lvb\": true, \"speed\": 3}}");
  expect_input_error(
      "run --config " + (dir / "bad_config.json").string() + " --out " + (dir / "o").string(),
      {"bad_config.json", "run.speed", "unknown key"});
  EXPECT_FALSE(fs::exists(dir / "o" / "report.json"));
  fs::remove_all(dir);
}

TEST(Cli, BadSweepFilesAreNamed) {
  const fs::path dir = test::temp_dir("cli_sweep_bad");
  const std::string scene = (test::source_dir() / "configs/scenes/city.yaml").string();
  const std::string hw = (test::source_dir() / "configs/hw/tni-paper.yaml").string();
  const std::string head = "scenes: [" + scene + "]\nhw: " + hw + "\n";
  auto check = [&](const std::string& name, const std::string& yaml,
                   const std::vector<std::string>& fragments) {
    write(dir / name, yaml);
    expect_input_error("sweep " + (dir / name).string() + " --out " + (dir / "o").string(),
                       fragments);
  };
  check("unknown.yaml", head + "axis:\n  hw.trv.count: [1, 2]\n",
        {"unknown.yaml:3", "axis", "unknown key"});
  check("prefix.yaml", head + "axes:\n  trv.count: [1, 2]\n",
        {"prefix.yaml", "trv.count", "'hw.', 'scene.' or 'run.'"});
  check("empty.yaml", head + "axes:\n  hw.trv.count: []\n", {"empty.yaml:4", "at least one value"});
  check("value.yaml", head + "axes:\n  hw.trv.l1.size_kb: [8, 12]\n",
        {"value.yaml", "p0001", "power of two"});
  check("scene.yaml", "scenes: [nowhere.yaml]\nhw: " + hw + "\n",
        {"scene.yaml:1", "nowhere.yaml", "not found"});
  check("type.yaml", head + "axes:\n  run.reflections: [0, many]\n",
        {"type.yaml", "p0001", "expected an integer"});
  // Text that is not UTF-8 would reach the JSON writers (issue 22: a mutated axis key).
  check("utf8.yaml", head + "axes:\n  run.lv\xdb: [on, off]\n", {"utf8.yaml:4", "not UTF-8"});
  check("utf8v.yaml", head + "axes:\n  run.lvb: [on, \"o\xc3\"]\n", {"utf8v.yaml:4", "not UTF-8"});
  EXPECT_FALSE(fs::exists(dir / "o" / "manifest.json"))
      << "nothing runs before every point is valid";
  fs::remove_all(dir);
}

// One sweep at a time in a directory: while another process holds DIR/.lock (a running sweep),
// a second sweep there refuses before it writes anything.
TEST(Cli, ASecondSweepInTheSameDirectoryRefuses) {
  const fs::path dir = test::temp_dir("cli_sweep_lock");
  const std::string scene = (test::source_dir() / "configs/scenes/city.yaml").string();
  const std::string hw = (test::source_dir() / "configs/hw/tni-paper.yaml").string();
  write(dir / "sweep.yaml", "scenes: [" + scene + "]\nhw: " + hw +
                                "\naxes:\n  run.width: [16, 32]\n  run.height: [9]\n");
  fs::create_directories(dir / "out");
  const int fd = ::open((dir / "out" / ".lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  expect_input_error("sweep " + (dir / "sweep.yaml").string() + " --out " + (dir / "out").string(),
                     {"another sweep is running in this directory"});
  EXPECT_FALSE(fs::exists(dir / "out" / "manifest.json"));
  ::close(fd);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rtsim::cli_test

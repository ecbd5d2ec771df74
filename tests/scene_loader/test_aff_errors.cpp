// Bad AFF input: one error naming the file and line, for truncated blocks, unknown keywords,
// missing includes and errors inside them.
#include "common/error.h"
#include "scene_loader/aff_loader.h"
#include "scene_loader/kb_spline.h"
#include "tests/scene_loader/aff_test_util.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace rtsim {
namespace {

using namespace aff_test;

TEST(AffErrors, TruncatedMesh) {
  expect_text_error(
      "fm 0 0 0 1 1 1 0 0 0 1 0 1\nm\nvertices 3\n0 0 0\n1 0 0\n0 1 0\ntriangles 2\n0 1 2\n0 1\n",
      9, "end of file");
  expect_text_error("m\nvertices 3\n0 0 0\n1 0\n", 4, "end of file");
}

TEST(AffErrors, TruncatedViewBlock) {
  expect_text_error("v\nfrom 0 0 0\nat 0 0 -1\nup 0 1 0\nangle 45\n", 5, "'hither'");
  expect_text_error("v\nfrom 0 0 0\nat 0 0\nup 0 1 0\n", 4, "'up'");
}

TEST(AffErrors, UnknownKeyword) {
  expect_text_error("b 0 0 0\n\nsphere 1 2 3 4\n", 3, "unknown keyword");
  expect_text_error(
      "k cam {\n transl 4\n 0 0 0 0 0 0 0\n 1 0 0 0 0 0 0\n 2 0 0 0 0 0 0\n 3 0 0 0 0 0 0\n spin "
      "4\n}\n",
      7, "'spin'");
}

TEST(AffErrors, MissingIncludeNamesIncludingFileAndLine) {
  expect_text_error("b 0 0 0\n# comment\ni 0 no_such_file.aff\n", 3, "no_such_file.aff");
}

TEST(AffErrors, ErrorInsideIncludeNamesThatFile) {
  fs::path dir = test::temp_dir("aff_inc_err");
  write_file(dir / "top.aff", "i 0 child.aff\n");
  write_file(dir / "child.aff",
             std::string(kOneTriangle) + "\n\nm vertices 1 0 0 0 triangles 1 0 0 7\n");
  expect_input_error((dir / "top.aff").string(), "child.aff", 4, "vertex index");
}

TEST(AffErrors, OtherMalformedInputs) {
  expect_text_error("m vertices 2 0 0 0 1 1 1\ntriangles 1 0 1 2\n", 2, "vertex index");
  expect_text_error("xs 1 1 1 0 1 0 90 0 0 0 {\n\n", 1, "'}'");
  expect_text_error("\n}\n", 2, "'}'");
  expect_text_error("k a {\n rot 3\n 0 1 0 0 0 0 0 0\n}\n", 2, "at least 4");
  expect_text_error("l 1 2 x\n", 1, "a number");
  expect_text_error("xs 1 1 1 0 1 0 90 0 0 0\nm\n", 2, "'{'");
  Scene s;
  EXPECT_THROW(load_aff("/nonexistent/dir/none.aff", 0.0, s), InputError);
}

// A count no file could hold (issue 22's mutated keyframe block) ends with the file, as an error
// at the line where the items stop, never as an allocation of that size (std::bad_alloc).
TEST(AffErrors, AHugeCountIsAnErrorWhereTheFileEndsNotAnAllocation) {
  const std::string keys = " 0 1 1 1 0 0 0\n";
  expect_text_error("k a {\n transl 4294967295\n" + keys + "}\n", 4, "key time");
  expect_text_error("k a {\n rot 4294967295\n 0 0 1 0 0 0 0 0\n}\n", 4, "key time");
  expect_text_error("m vertices 4294967295\n 0 0 0\n", 2, "mesh vertex");
  expect_text_error("p 4294967295\n 0 0 0\n", 2, "polygon vertex");
  expect_text_error("tpa 4294967295\n 0\n", 2, "tpa");
}

TEST(AffErrors, EveryKeywordMalformedNamesItsLineAndField) {
  // One row per keyword of BART's format: its last field spoiled, on line 2 of the file (or the
  // line of the spoiled field).
  struct Case {
    const char* text;
    long line;
    const char* what;
  };
  const Case cases[] = {
      {"v\nfrom 0 0 0\nat 0 0 -1\nup 0 1 0\nangle 45\nhither x\nresolution 4 4\n", 7, "v hither"},
      {"b 0 0 x\n", 2, "background colour"},
      {"l 1 2 x\n", 2, "a number"},
      {"la car 1 2 x\n", 2, "a number"},
      {"f 1 1 1 0.5 0.5 8 0 x\n", 2, "f index of refraction"},
      {"fm 0 0 0 1 1 1 0 0 0 8 0 x\n", 2, "fm index of refraction"},
      {"am 1 1 x\n", 2, "ambient light colour"},
      {"a 0 10 x\n", 2, "animation frame count"},
      {"c 0 0 0 1 0 1 0 x\n", 2, "cone apex radius"},
      {"s 0 0 0 x\n", 2, "a number"},
      {"p 3 0 0 0 1 0 0 0 1 x\n", 2, "polygon vertex"},
      {"pp 3 0 0 0 0 0 1 1 0 0 0 0 1 0 1 0 0 0 x\n", 2, "polygon patch normal"},
      {"tt t.ppm 0 0 0 0 0 1 0 0 1 0 0 1 0 0 x\n", 2, "texture coordinate v"},
      {"ttp t.ppm 0 0 0 0 0 1 0 0  1 0 0 0 0 1 1 0  0 1 0 0 0 1 0 x\n", 2, "texture coordinate v"},
      {"tpa 1\n0  0 0 0 0 0 1  1 0 0 0 0 1  0 1 0 0 0 x\n", 3, "a number"},
      {"m vertices 3 0 0 0 1 0 0 0 1 0 triangles 1 0 1 x\n", 2, "an integer"},
      {"d x\n", 2, "detail level"},
      {"i x child.aff\n", 2, "include detail level"},
      {"xs 1 1 1 0 1 0 90 0 0 x {\n}\n", 2, "a number"},
      {"x car\n}\n", 3, "'{'"},
      {"k car {\n transl 4\n 0 0 0 0 0 0 0\n 1 0 0 0 0 0 0\n 2 0 0 0 0 0 0\n 3 0 0 0 0 0 x\n}\n", 7,
       "a number"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    expect_text_error(std::string("# one keyword\n") + c.text, c.line, c.what);
  }
}

TEST(AffErrors, MissingTextureFileDoesNotThrow) {
  EXPECT_NO_THROW(
      load_text("m vertices 3 0 0 0 1 0 0 0 1 0\ntexturecoords 3 /no/such/texture.ppm 0 0 1 0 0 "
                "1\ntriangles 1 0 1 2 0 1 2\n"));
}

}  // namespace
}  // namespace rtsim

// A procedural test scene: a small city that is the same, bit for bit, on every machine.
#pragma once

#include "scene/scene.h"

#include <cstdint>

namespace rtsim {

// The city's scale knob is `blocks`: its triangles grow as about 122 blocks^2 with the default
// spheres (blocks 8: 9,602; 28: 101,922; 90: 1,008,362; 181: 4,037,500). The triangle bound keeps
// a city well within 32-bit triangle and reference indices; whether a frame of it fits the
// machine is the run's memory check (testbench/run/resources.h; docs/scale.md measures 4 M).
inline constexpr int kMaxCityBlocks = 1024;
inline constexpr uint64_t kMaxCityTriangles = uint64_t(1) << 24;  // 16,777,216

struct CityParams {
  int blocks = 8;            // the city is blocks x blocks buildings (1..kMaxCityBlocks)
  uint32_t seed = 1;         // same seed -> identical scene
  int sphere_segments = 16;  // segments around each sphere (4..256); it has segments/2 stacks
  int lights = 4;            // point lights above the city (1..15)
};

// Appends the city to `scene` (triangles, materials, lights) and sets its name ("city"),
// camera and resolution (640x360).
//
// Layout (y up, metres): blocks of 10 x 10 with streets 3 wide, the city spans
// W = 10 * blocks + 3 on x and z from the origin.
// - ground: one quad (2 triangles) covering the city;
// - one box building per block, random footprint inset and height 3..25, walls and roof only
//   (10 triangles);
// - a mirror sphere (reflectance 0.5) on the roof of every building whose (column + row) is even,
//   and one sphere per row standing in the street before it;
// - each sphere has S = sphere_segments segments and S/2 stacks: 2 * S * (S/2 - 1) triangles.
// So the triangle count is 2 + 10 b^2 + (ceil(b^2 / 2) + b) * 2 S (S/2 - 1) for b = blocks.
// Lights sit on a ring above the city, each of colour 1/sqrt(lights) (NFF's convention). The
// camera looks at the city centre from above the corner at the origin, 45 degrees vertical fov.
//
// Determinism: a private splitmix64 generator and integer-to-float conversion, and sin/cos from
// Taylor series (libm's may differ in the last bit between machines); needs IEEE arithmetic
// without FMA contraction, which the build sets (-ffp-contract=off).
//
// Throws InputError when a parameter is outside its range or the city would have more than
// kMaxCityTriangles triangles.
void make_city(const CityParams& params, Scene& scene);

// The number of triangles make_city makes with `params` (the formula above), without making them.
uint64_t city_triangles(const CityParams& params);

}  // namespace rtsim

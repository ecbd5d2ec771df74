// Report files are written whole or not at all: to a temporary name, then renamed.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace rtsim {

// The files the commands write, each name defined here once (docs/reports.md says what each
// holds; reports/rtsim_plots/files.py names the ones the figures read, and a test checks that
// the two agree).
namespace output {
// A run (rtsim run), and what render and lvb write of the same kind.
inline constexpr const char* kReportJson = "report.json";  // written last: marks a finished run
inline constexpr const char* kReportMd = "report.md";
inline constexpr const char* kStatsCsv = "stats.csv";
inline constexpr const char* kGlossaryCsv = "glossary.csv";
inline constexpr const char* kSampleCsv = "sample.csv";    // a sampled run's measured units
inline constexpr const char* kBatchesCsv = "batches.csv";  // the primary phase by ray batches
inline constexpr const char* kConfigJson = "config.json";
inline constexpr const char* kRenderPng = "render.png";
inline constexpr const char* kRenderJson = "render.json";
inline constexpr const char* kMaskNpy = "mask.npy";
inline constexpr const char* kCulledNpy = "culled.npy";
inline constexpr const char* kVisibilityNpy = "visibility.npy";
inline constexpr const char* kRadianceNpy = "radiance.npy";  // a path-traced frame's, (H, W, 3)
inline constexpr const char* kLvbJson = "lvb.json";          // rtsim lvb
// A sweep (rtsim sweep, reproduce, animate): points/<id>/ holds each point's run and its row.
inline constexpr const char* kPointsDir = "points";
inline constexpr const char* kRowJson = "row.json";
inline constexpr const char* kLogTxt = "log.txt";
inline constexpr const char* kManifestJson = "manifest.json";
inline constexpr const char* kResultsCsv = "results.csv";
inline constexpr const char* kResultsJson = "results.json";
// What reproduce and animate write beside their points.
inline constexpr const char* kReproductionMd = "reproduction.md";
inline constexpr const char* kReproductionJson = "reproduction.json";
inline constexpr const char* kAblationMd = "ablation.md";
inline constexpr const char* kAblationJson = "ablation.json";
inline constexpr const char* kBvhStudyMd = "bvh.md";
inline constexpr const char* kBvhStudyJson = "bvh.json";
inline constexpr const char* kFramesCsv = "frames.csv";
inline constexpr const char* kHostCsv = "host.csv";
inline constexpr const char* kSummaryMd = "summary.md";  // animate
// A sweep's figures (plots.py sweep) and their index (reports/sweep_index.h).
inline constexpr const char* kPlotsDir = "plots";
inline constexpr const char* kPlotsIndexMd = "index.md";
// What a sweep's `reports:` write beside its results.
inline constexpr const char* kAreaLightsMd = "area_lights.md";  // reports: [area]
}  // namespace output

void write_file_atomic(const std::string& path, const std::string& contents);
void write_json(const std::string& path, const nlohmann::json& j);
// A JSON file; an InputError naming it when it is missing or malformed.
nlohmann::json read_json(const std::string& path);
// NumPy .npy (format 1.0), little-endian uint16, C order, shape (height, width).
void write_npy_u16(const std::string& path, const std::vector<uint16_t>& data, int height,
                   int width);
// Any shape, row-major (C order): the last dimension varies fastest.
void write_npy_u16(const std::string& path, const std::vector<uint16_t>& data,
                   const std::vector<size_t>& shape);
// The uint16 values of a .npy file written by write_npy_u16 (any shape, flattened); empty when
// the file is missing or too short to be one.
std::vector<uint16_t> read_npy_u16(const std::string& path);
// NumPy .npy, little-endian float32, row-major (the last dimension varies fastest).
void write_npy_f32(const std::string& path, const std::vector<float>& data,
                   const std::vector<size_t>& shape);
// NumPy .npy of `count` records of a structured dtype, `descr` its Python literal ("[('x', '<f4'),
// ...]"), `bytes` the records packed little-endian as the dtype lays them out.
void write_npy_records(const std::string& path, const std::string& descr, size_t count,
                       const std::string& bytes);
// 8-bit RGB PNG.
void write_png_rgb(const std::string& path, const std::vector<uint8_t>& rgb, int width, int height);

}  // namespace rtsim

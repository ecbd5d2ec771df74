// Report files are written whole or not at all: to a temporary name, then renamed.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace rtsim {

void write_file_atomic(const std::string& path, const std::string& contents);
void write_json(const std::string& path, const nlohmann::json& j);
// NumPy .npy (format 1.0), little-endian uint16, C order, shape (height, width).
void write_npy_u16(const std::string& path, const std::vector<uint16_t>& data, int height,
                   int width);
// Any shape, row-major (C order): the last dimension varies fastest.
void write_npy_u16(const std::string& path, const std::vector<uint16_t>& data,
                   const std::vector<size_t>& shape);
// 8-bit RGB PNG.
void write_png_rgb(const std::string& path, const std::vector<uint8_t>& rgb, int width, int height);

}  // namespace rtsim

#include "reports/output_files.h"

#include "common/error.h"

#include <stb_image_write.h>

#include <fmt/format.h>

#include <unistd.h>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace rtsim {

void write_file_atomic(const std::string& path, const std::string& contents) {
  const std::filesystem::path target(path);
  if (target.has_parent_path()) std::filesystem::create_directories(target.parent_path());
  const std::string tmp = fmt::format("{}.tmp.{}", path, getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(contents.data(), std::streamsize(contents.size()));
    out.close();
    if (!out) {
      const int err = errno;
      std::remove(tmp.c_str());
      throw InputError(fmt::format("{}: cannot write ({})", path, std::strerror(err)));
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    std::remove(tmp.c_str());
    throw InputError(fmt::format("{}: cannot rename the temporary file into place ({})", path,
                                 std::strerror(err)));
  }
}

void write_json(const std::string& path, const nlohmann::json& j) {
  write_file_atomic(path, j.dump(2) + "\n");
}

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: not valid JSON: {}", path, e.what()));
  }
}

void write_npy_u16(const std::string& path, const std::vector<uint16_t>& data, int height,
                   int width) {
  write_npy_u16(path, data, std::vector<size_t>{size_t(height), size_t(width)});
}

namespace {

// A .npy file's magic, version 1.0, and its header for `descr` (NumPy's dtype as a Python literal:
// "'<u2'", or a structured type's list) and `shape` (a Python tuple: "(h, w)", and "(n,)" for one
// dimension), padded so the data start 64-byte aligned.
std::string npy_header(const std::string& descr, const std::vector<size_t>& shape) {
  std::string header = fmt::format("{{'descr': {}, 'fortran_order': False, 'shape': ({}{}), }}",
                                   descr, fmt::join(shape, ", "), shape.size() == 1 ? "," : "");
  // The magic, version and length take 10 bytes.
  const size_t total = (10 + header.size() + 1 + 63) / 64 * 64;
  header.append(total - 10 - header.size() - 1, ' ');
  header.push_back('\n');
  std::string out("\x93NUMPY\x01\x00", 8);
  const uint16_t hlen = static_cast<uint16_t>(header.size());
  out.push_back(char(hlen & 0xff));
  out.push_back(char(hlen >> 8));
  return out + header;
}

}  // namespace

void write_npy_u16(const std::string& path, const std::vector<uint16_t>& data,
                   const std::vector<size_t>& shape) {
  std::string out = npy_header("'<u2'", shape);
  for (uint16_t v : data) {
    out.push_back(char(v & 0xff));
    out.push_back(char(v >> 8));
  }
  write_file_atomic(path, out);
}

void write_npy_records(const std::string& path, const std::string& descr, size_t count,
                       const std::string& bytes) {
  write_file_atomic(path, npy_header(descr, {count}) + bytes);
}

void write_npy_f32(const std::string& path, const std::vector<float>& data,
                   const std::vector<size_t>& shape) {
  std::string out = npy_header("'<f4'", shape);
  for (float v : data) {
    uint32_t bits;
    std::memcpy(&bits, &v, 4);
    for (int k = 0; k < 4; ++k) out.push_back(char((bits >> (8 * k)) & 0xff));
  }
  write_file_atomic(path, out);
}

std::vector<uint16_t> read_npy_u16(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 10) return {};
  const size_t header = 10 + size_t(uint8_t(bytes[8])) + 256 * size_t(uint8_t(bytes[9]));
  if (header > bytes.size()) return {};
  std::vector<uint16_t> v((bytes.size() - header) / 2);
  for (size_t i = 0; i < v.size(); ++i)
    v[i] = uint16_t(uint8_t(bytes[header + 2 * i]) | (uint8_t(bytes[header + 2 * i + 1]) << 8));
  return v;
}

void write_png_rgb(const std::string& path, const std::vector<uint8_t>& rgb, int width,
                   int height) {
  std::string png;
  auto sink = [](void* ctx, void* data, int size) {
    static_cast<std::string*>(ctx)->append(static_cast<char*>(data), size);
  };
  if (!stbi_write_png_to_func(sink, &png, width, height, 3, rgb.data(), width * 3))
    throw InputError(fmt::format("{}: PNG encoding failed", path));
  write_file_atomic(path, png);
}

}  // namespace rtsim

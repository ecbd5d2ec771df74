// The accelerator's registers as a platform sees them (docs/systemc-integration.md, "The register
// map"): 32-bit little-endian registers at byte offsets from the register socket's base, accessed
// with b_transport (a multiple of 4 bytes, 4-aligned; a burst covers consecutive registers).
// A driver programs where the scene image and the frame buffer lie, the resolution, the camera,
// the culling mode and the scene's layout (a copy of the image's header and each light's sample
// count), writes CONTROL.START, and waits for the interrupt (or polls STATUS).
#pragma once

#include "kernels/memory_image.h"

#include <cstdint>

namespace rtsim::model::regs {

inline constexpr uint32_t kIdValue = 0x41535452;  // "RTSA"
inline constexpr uint32_t kVersionValue = 1;

enum Offset : uint32_t {
  kId = 0x000,           // RO kIdValue
  kVersion = 0x004,      // RO kVersionValue
  kControl = 0x008,      // WO kStart | kReset (reads 0)
  kStatus = 0x00c,       // RO kBusy | kDone, error code in bits 8..15
  kIrqEnable = 0x010,    // RW bit 0: raise the interrupt output at a frame's end
  kIrqStatus = 0x014,    // RW1C bit 0: a frame ended (the output is kIrqEnable & kIrqStatus)
  kCyclesLo = 0x018,     // RO cycles of the last frame (accelerator clock), low word
  kCyclesHi = 0x01c,     // RO ... high word
  kFrames = 0x020,       // RO frames ended since the last reset
  kImageBaseLo = 0x028,  // RW where the scene image starts in memory (64-byte aligned)
  kImageBaseHi = 0x02c,
  kFbBaseLo = 0x030,  // RW where the frame buffer of hit records starts (64-byte aligned)
  kFbBaseHi = 0x034,
  kWidth = 0x038,         // RW pixels
  kHeight = 0x03c,        // RW pixels
  kCulling = 0x040,       // RW bit 0: LVB shadow-ray culling on
  kRecordStride = 0x044,  // RO bytes per hit record in the frame buffer
  kLevels = 0x048,        // RO hit records per pixel: 1 + reflections, or spp x (1 + max_depth)
  kOrder = 0x04c,         // RO record order within a level: 0 scanline, 1 square tiles
  kTile = 0x050,          // RO tile side in pixels (kOrder 1)
  kFbBytesLo = 0x054,     // RO bytes the frame buffer takes at the programmed resolution
  kFbBytesHi = 0x058,
  kCamera = 0x060,        // RW 10 floats: eye xyz, view direction xyz, up xyz, vertical fov (deg)
  kSceneHeader = 0x100,   // RW 128 bytes: the image's header, copied by the driver
  kLightSamples = 0x180,  // RW per light l < kMaxLights at +4l: its shadow rays per hit (0 = 1)
  kMapBytes = 0x200,      // the register window's size
};

// FB_BYTES: a record per pixel and level (the primary hit and each reflection), RECORD_STRIDE
// bytes each; memory_layout() (model/accelerator.h) gives the same before elaboration.
inline uint64_t frame_buffer_bytes(uint32_t width, uint32_t height, uint32_t levels,
                                   uint32_t record_stride) {
  return uint64_t(width) * height * levels * record_stride;
}

inline constexpr uint32_t kCameraWords = 10;
inline constexpr uint32_t kHeaderBytes = 128;
inline constexpr uint32_t kMaxLights = image::kMaxLights;  // one LVB word per leaf

// CONTROL bits.
inline constexpr uint32_t kStart = 1u << 0;
inline constexpr uint32_t kReset = 1u << 1;
// STATUS bits.
inline constexpr uint32_t kBusy = 1u << 0;
inline constexpr uint32_t kDone = 1u << 1;  // the last START's frame ended
inline constexpr uint32_t kErrorShift = 8;

// STATUS error codes (set by a START or RESET the device refused, or at the end of a frame that
// met memory it cannot read as an image; cleared by the next accepted START or a RESET).
enum Error : uint32_t {
  kNoError = 0,
  kBadHeader = 1,      // the header's magic or version is not the image format's
  kBadResolution = 2,  // width or height 0 or above 16384
  kBadCamera = 3,      // a zero or non-finite direction, up parallel to it, fov not in (0, 180)
  kTooManyLights = 4,  // more than kMaxLights
  kBadPlacement = 5,   // image or frame buffer unaligned, overlapping, or outside memory
  kBusyStart = 6,      // START while a frame runs
  kBusyReset = 7,      // RESET while a frame runs (a frame cannot be aborted)
  kBadStructure = 8,   // the image's acceleration structure is not what the traversal units walk
  // At a frame's end: the memory does not hold a readable image (an index outside its section,
  // a walk deeper than its stack or longer than the tree; model/units/image_faults.h). The
  // frame ended all the same, its faulting rays as misses; statistics faults.* count them.
  kBadImage = 9,
};

}  // namespace rtsim::model::regs

// The compressed 8-wide node of Ylitie, Karras and Laine (HPG 2017), 80 bytes: a full-precision
// origin, a power-of-two scale per axis, 8-bit child boxes quantised outward, and one base index
// for the node's inner children and one for its leaves. Layout and our adaptation (a leaf slot
// names a leaf record, not up to three triangles): docs/memory-image.md.
#pragma once

#include "kernels/bvh_image.h"

namespace rtsim {

inline constexpr uint32_t kCwbvh8NodeBytes = 80;

// Lays out an 8-wide tree (Bvh::branching 8): nodes renumbered so that each node's inner
// children are consecutive records in slot order, root first. The leaves keep the tree's
// numbering (a node's leaves are consecutive there already, kernels/bvh.h).
BvhNodeSection encode_cwbvh8(const Bvh& bvh);
// Decodes one 80-byte record; every decoded box contains the child's true box.
BvhNodeView decode_cwbvh8(const uint8_t* p);

}  // namespace rtsim

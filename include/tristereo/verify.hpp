// Bit-exactness check a user can run on their own board and images: the float
// reference against every kernel set this CPU can run, at several thread counts.
#pragma once

#include "tristereo/export.hpp"

#include <string>
#include <vector>

#include "tristereo/image.hpp"
#include "tristereo/kernels.hpp"
#include "tristereo/params.hpp"

namespace tristereo {

struct VerifyCase {
  KernelChoice kernels = KernelChoice::kScalar;
  int threads = 1;
  bool identical = false;
  std::string first_difference;  // empty when identical
};

struct VerifyReport {
  bool bit_exact = false;          // every case identical to the reference
  std::vector<VerifyCase> cases;
  std::string reference_digest;    // hex digest of the reference outputs
};

// thread_counts empty = {1, number of allowed CPUs}.
TRISTEREO_API VerifyReport verify_bit_exact(const ImageU8& left, const ImageU8& right, const StereoParams& params,
                              std::vector<int> thread_counts = {});

// Raw frames of a rig (include/tristereo/rig.hpp, rectify.hpp): the reference
// rectifies them (reference_rectify) and matches the rectified pair; every
// case's pipeline takes the raw frames through its rectification stage (the
// maps of build_rectify_maps(rig, rect)). So a raw-in frame is checked bit for
// bit, the remap included. raw_left/raw_right: gray or RGB, of the rig's size.
struct StereoRig;
struct Rectification;
TRISTEREO_API VerifyReport verify_bit_exact_raw(const ImageU8& raw_left, const ImageU8& raw_right,
                                                const StereoRig& rig, const Rectification& rect,
                                                const StereoParams& params, std::vector<int> thread_counts = {});
// First difference between two frame outputs ("" when identical), e.g.
// "dense map differs at (12, 40): 176 vs 192".
struct StereoOutput;
TRISTEREO_API std::string first_difference(const StereoOutput& expected, const StereoOutput& actual);

// 64-bit FNV-1a digests of the outputs, in hex (stable across platforms):
// digest_hex of the mesh, sample disparities and dense map; state_digest_hex
// of the vertex and pixel state and confidence (docs/model.md section 7).
// first_difference compares all of them and the validity counts.
TRISTEREO_API std::string digest_hex(const StereoOutput& out);
TRISTEREO_API std::string state_digest_hex(const StereoOutput& out);

}  // namespace tristereo

// EXPERIMENT (issue 40): a support prior in the winner selection.
// Samples that are measured and confident are the support; every other
// sample gets a prior disparity from the support on the mesh, and its winner
// is chosen again from S'(k) = S(k) + lambda min(|k - k_prior|, T).
// Knobs come from environment variables while exploring (TRISTEREO_PP_*);
// lambda = 0 (the default) leaves everything unchanged.
#pragma once

#include <cstdint>

#include "src/aggregate/path_matcher.hpp"
#include "src/aggregate/samples.hpp"
#include "tristereo/image.hpp"
#include "tristereo/params.hpp"

namespace tristereo {

struct SupportPriorKnobs {
  int lambda = 0;     // Q4 cost units per disparity step (0 = off)
  int trunc = 4;      // T: the prior's penalty stops growing T steps away
  int min_conf = 160; // support: measured with a confidence of at least this
  int mode = 1;       // propagation: 0 smallest, 1 rounded mean, 2 lower median
  int smooth = 0;     // Jacobi rounds of the non-support priors (mean of neighbours)
  int which = 3;      // re-decide: 1 measured below min_conf, 2 uniqueness-rejected, 4 left-right-rejected
  int uniq = 0;       // uniqueness on S' (percent, 0 = accept every new winner)
  int itau = 0;       // propagation first only across mesh edges with |I(p) - I(q)| <= itau (0 = off)
  int seg_tau = 0;    // segments: mesh edges with |I(p) - I(q)| <= seg_tau joined (0 = no plane prior)
  int seg_min = 20;   // support samples a segment needs for its plane
  int seg_res = 16;   // Q4: inlier distance to the plane, and the largest RMS residual accepted
  int fill = 0;       // 1: samples still invalid after pass 2 take their prior (before the usual fill)
  static SupportPriorKnobs from_env();
};

struct SupportPriorStats {
  int support = 0, redecided = 0, changed = 0, rejected = 0;
};

// disp_q4 / confidence: the matcher's outputs (before the fill), changed in place.
SupportPriorStats apply_support_prior(const SupportPriorKnobs& knobs, const SampleLayout& samples,
                                      const PathMatcher& pm, const StereoParams& params,
                                      ImageView<const std::uint8_t> left, std::int16_t* disp_q4,
                                      std::uint8_t* confidence);

}  // namespace tristereo

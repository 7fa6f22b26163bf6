// Latency statistics on series whose answers are known by hand (and agree with
// numpy.percentile's default "linear" method and numpy.std's ddof = 0).
#include "src/profile/latency_stats.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "tristereo/status.hpp"

namespace tristereo {
namespace {

constexpr std::int64_t kMs = 1000000;  // ns per ms

std::vector<std::int64_t> ms_series(std::initializer_list<std::int64_t> ms) {
  std::vector<std::int64_t> v;
  for (std::int64_t m : ms) v.push_back(m * kMs);
  return v;
}

TEST(LatencyStats, OneToHundredShuffled) {
  std::vector<std::int64_t> v;
  for (int i = 1; i <= 100; ++i) v.push_back(i * kMs);
  std::shuffle(v.begin(), v.end(), std::mt19937(7));
  const std::vector<std::int64_t> before = v;

  const LatencyStats s = compute_latency_stats(v);
  EXPECT_EQ(v, before) << "input must not be reordered";
  EXPECT_EQ(s.count, 100u);
  EXPECT_DOUBLE_EQ(s.min_ms, 1.0);
  EXPECT_DOUBLE_EQ(s.max_ms, 100.0);
  // h = 99 q / 100: p50 -> 49.5 (between 50 and 51), p90 -> 89.1, p99 -> 98.01.
  EXPECT_NEAR(s.p50_ms, 50.5, 1e-9);
  EXPECT_NEAR(s.p90_ms, 90.1, 1e-9);
  EXPECT_NEAR(s.p99_ms, 99.01, 1e-9);
  EXPECT_DOUBLE_EQ(s.mean_ms, 50.5);
  // Population variance of 1..n is (n^2 - 1) / 12 = 833.25.
  EXPECT_NEAR(s.std_ms, std::sqrt(833.25), 1e-9);
}

TEST(LatencyStats, SingleElement) {
  const LatencyStats s = compute_latency_stats({12345678});
  EXPECT_EQ(s.count, 1u);
  for (double v : {s.min_ms, s.p50_ms, s.p90_ms, s.p99_ms, s.max_ms, s.mean_ms})
    EXPECT_DOUBLE_EQ(v, 12.345678);
  EXPECT_EQ(s.std_ms, 0.0);
}

TEST(LatencyStats, TwoElementsInterpolate) {
  const LatencyStats s = compute_latency_stats(ms_series({20, 10}));
  EXPECT_DOUBLE_EQ(s.min_ms, 10.0);
  EXPECT_DOUBLE_EQ(s.max_ms, 20.0);
  EXPECT_NEAR(s.p50_ms, 15.0, 1e-9);
  EXPECT_NEAR(s.p90_ms, 19.0, 1e-9);
  EXPECT_NEAR(s.p99_ms, 19.9, 1e-9);
  EXPECT_DOUBLE_EQ(s.mean_ms, 15.0);
  EXPECT_DOUBLE_EQ(s.std_ms, 5.0);  // population, not sample (which is 7.07)
}

TEST(LatencyStats, Duplicates) {
  const LatencyStats s = compute_latency_stats(ms_series({5, 7, 5, 5, 5}));
  EXPECT_DOUBLE_EQ(s.p50_ms, 5.0);    // equal neighbours give exactly their value
  EXPECT_NEAR(s.p90_ms, 6.2, 1e-9);   // h = 3.6: 5 + 0.6 * (7 - 5)
  EXPECT_NEAR(s.p99_ms, 6.92, 1e-9);  // h = 3.96
  EXPECT_NEAR(s.mean_ms, 5.4, 1e-12);
  EXPECT_NEAR(s.std_ms, 0.8, 1e-12);  // var = (4 * 0.16 + 2.56) / 5
  const LatencyStats same = compute_latency_stats(ms_series({3, 3, 3}));
  EXPECT_DOUBLE_EQ(same.p99_ms, 3.0);
  EXPECT_EQ(same.std_ms, 0.0);
}

TEST(LatencyStats, LargeValuesKeepNanoseconds) {
  // Durations near 10^15 ns (11.6 days): the half nanosecond must survive
  // (doubles there are spaced 0.125 apart).
  const std::int64_t big = 1000000000000000;
  const LatencyStats s = compute_latency_stats({big + 1, big});
  EXPECT_NEAR(s.p50_ms * 1e6, static_cast<double>(big) + 0.5, 0.2);
  EXPECT_NEAR(s.mean_ms * 1e6, static_cast<double>(big) + 0.5, 0.2);
  EXPECT_NEAR(s.std_ms * 1e6, 0.5, 1e-9);
}

TEST(LatencyStats, EmptySeriesThrows) { EXPECT_THROW(compute_latency_stats({}), Error); }

TEST(Percentile, NumpyLinearDefinition) {
  const std::int64_t v[] = {1, 2, 3, 4};
  // numpy.percentile([1, 2, 3, 4], q) for q = 0, 25, 50, 75, 100.
  EXPECT_DOUBLE_EQ(percentile_of_sorted(v, 4, 0), 1.0);
  EXPECT_DOUBLE_EQ(percentile_of_sorted(v, 4, 25), 1.75);
  EXPECT_DOUBLE_EQ(percentile_of_sorted(v, 4, 50), 2.5);
  EXPECT_DOUBLE_EQ(percentile_of_sorted(v, 4, 75), 3.25);
  EXPECT_DOUBLE_EQ(percentile_of_sorted(v, 4, 100), 4.0);
}

TEST(Percentile, RejectsBadArguments) {
  const std::int64_t v[] = {1, 2};
  EXPECT_THROW(percentile_of_sorted(v, 0, 50), Error);
  EXPECT_THROW(percentile_of_sorted(nullptr, 2, 50), Error);
  EXPECT_THROW(percentile_of_sorted(v, 2, -0.5), Error);
  EXPECT_THROW(percentile_of_sorted(v, 2, 100.5), Error);
  EXPECT_THROW(percentile_of_sorted(v, 2, std::numeric_limits<double>::quiet_NaN()), Error);
  try {
    percentile_of_sorted(v, 2, 150);
    FAIL() << "no throw";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(e.what()).find("150"), std::string::npos) << e.what();
  }
}

TEST(FrameLog, FixedCapacityNeverReallocates) {
  FrameLog log(3);
  EXPECT_EQ(log.capacity(), 3u);
  EXPECT_EQ(log.size(), 0u);
  FrameSample s;
  s.total_ns = 10;
  ASSERT_TRUE(log.push(s));
  const FrameSample* first = &log[0];
  for (int i = 1; i < 3; ++i) {
    s.stage_ns[static_cast<int>(ProfileStage::kDp)] = i;
    s.total_ns = 10 + i;
    s.cpu_ns = 100 * i;
    ASSERT_TRUE(log.push(s));
  }
  EXPECT_FALSE(log.push(s)) << "a full log must refuse, not grow";
  EXPECT_EQ(log.size(), 3u);
  EXPECT_EQ(&log[0], first);
  EXPECT_EQ(log.total_column(), (std::vector<std::int64_t>{10, 11, 12}));
  EXPECT_EQ(log.cpu_column(), (std::vector<std::int64_t>{0, 100, 200}));
  EXPECT_EQ(log.stage_column(ProfileStage::kDp), (std::vector<std::int64_t>{0, 1, 2}));
  EXPECT_EQ(log.stage_column(ProfileStage::kTritree), (std::vector<std::int64_t>{0, 0, 0}));
}

TEST(FrameLog, RejectsBadCapacity) {
  EXPECT_THROW(FrameLog(0), Error);
  EXPECT_THROW(FrameLog(FrameLog::kMaxFrames + 1), Error);
}

TEST(ProfileStageName, AllStagesNamed) {
  EXPECT_STREQ(profile_stage_name(ProfileStage::kTritree), "tritree");
  EXPECT_STREQ(profile_stage_name(ProfileStage::kCostAggregation), "cost_aggregation");
  EXPECT_STREQ(profile_stage_name(ProfileStage::kDp), "dp");
  EXPECT_STREQ(profile_stage_name(ProfileStage::kRightPass), "right_pass");
  EXPECT_STREQ(profile_stage_name(ProfileStage::kFill), "fill");
  EXPECT_STREQ(profile_stage_name(ProfileStage::kInterpolation), "interpolation");
  EXPECT_STREQ(profile_stage_name(ProfileStage::kMeshOutput), "mesh_output");
}

}  // namespace
}  // namespace tristereo

// The command line's rules, without a terminal: warnings for suspicious
// input (apps/match_warnings.cpp), library errors in option names
// (apps/option_errors.cpp), integer parsing (apps/cli_args.cpp) and
// all-or-nothing outputs (apps/output_set.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "apps/cli_args.hpp"
#include "apps/match_warnings.hpp"
#include "apps/option_errors.hpp"
#include "apps/output_set.hpp"
#include "support/data.hpp"
#include "tristereo/io.hpp"
#include "tristereo/gray.hpp"
#include "tristereo/params.hpp"
#include "tristereo/status.hpp"
#include "tristereo/synth.hpp"

namespace tristereo::cli {
namespace {

std::string usage_message(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const UsageError& e) {
    return e.what();
  }
  return "(no UsageError)";
}

TEST(CliWarnings, SwappedSyntheticPairIsFlaggedAndTheRightOrderIsNot) {
  SynthParams sp;
  sp.width = 160;
  sp.height = 120;
  sp.num_disp = 32;
  const SyntheticScene s = make_synthetic_scene(sp);
  const SwapVotes right_order = swap_votes(s.left.view(), s.right.view(), 31);
  const SwapVotes swapped = swap_votes(s.right.view(), s.left.view(), 31);
  EXPECT_GE(right_order.positive, kSwapMinBlocks);
  EXPECT_LT(right_order.negative * kSwapRatio, right_order.positive);
  EXPECT_GE(swapped.negative, kSwapRatio * swapped.positive);
  EXPECT_EQ(swapped_warning(s.left.view(), s.right.view(), 0, 32), "");
  EXPECT_NE(swapped_warning(s.right.view(), s.left.view(), 0, 32).find("look swapped"), std::string::npos);
  // A negative d_min is deliberate: no verdict.
  EXPECT_EQ(swapped_warning(s.right.view(), s.left.view(), -4, 32), "");
  // A flat image has no textured block: no verdict either.
  const ImageU8 flat(160, 120, 1);
  EXPECT_EQ(swap_votes(flat.view(), flat.view(), 31).positive, 0);
  EXPECT_EQ(swapped_warning(flat.view(), flat.view(), 0, 32), "");
}

// The check as first written, one shift at a time: the reference for the
// vectorised swap_votes, which must give the same votes.
SwapVotes swap_votes_by_shift(ImageView<const std::uint8_t> l, ImageView<const std::uint8_t> r, int d_max) {
  constexpr int kHalf = 4, kSide = 2 * kHalf + 1, kN = kSide * kSide;
  SwapVotes votes;
  if (d_max < 1 || l.width != r.width || l.height != r.height) return votes;
  const int step = std::max(4, static_cast<int>(std::sqrt(l.width * 1.0 * l.height / 400)));
  std::vector<int> block(kN);
  for (int cy = kHalf; cy + kHalf < l.height; cy += step) {
    for (int cx = kHalf; cx + kHalf < l.width; cx += step) {
      int sum = 0;
      for (int y = 0; y < kSide; ++y)
        for (int x = 0; x < kSide; ++x) sum += block[y * kSide + x] = l.row(cy - kHalf + y)[cx - kHalf + x];
      long long texture = 0;
      for (int v : block) texture += std::abs(v * kN - sum);
      if (texture < 4LL * kN * kN) continue;
      long long best_pos = -1, best_neg = -1;
      for (int d = -d_max; d <= d_max; ++d) {
        const int rx = cx - d;
        if (d == 0 || rx - kHalf < 0 || rx + kHalf >= r.width) continue;
        int rsum = 0;
        for (int y = 0; y < kSide; ++y)
          for (int x = 0; x < kSide; ++x) rsum += r.row(cy - kHalf + y)[rx - kHalf + x];
        long long cost = 0;
        for (int y = 0; y < kSide; ++y)
          for (int x = 0; x < kSide; ++x)
            cost += std::abs((block[y * kSide + x] * kN - sum) - (r.row(cy - kHalf + y)[rx - kHalf + x] * kN - rsum));
        long long& best = d > 0 ? best_pos : best_neg;
        if (best < 0 || cost < best) best = cost;
      }
      if (best_pos < 0 || best_neg < 0) continue;
      if (4 * best_pos < 3 * best_neg) ++votes.positive;
      else if (4 * best_neg < 3 * best_pos) ++votes.negative;
    }
  }
  return votes;
}

void expect_same_votes(const ImageU8& l, const ImageU8& r, int d_max, const std::string& what) {
  const SwapVotes fast = swap_votes(l.view(), r.view(), d_max), slow = swap_votes_by_shift(l.view(), r.view(), d_max);
  EXPECT_EQ(fast.positive, slow.positive) << what << " d_max " << d_max;
  EXPECT_EQ(fast.negative, slow.negative) << what << " d_max " << d_max;
}

TEST(CliWarnings, SwapVotesEqualTheShiftByShiftCheck) {
  std::mt19937 rng(15);
  for (int trial = 0; trial < 40; ++trial) {
    // Sizes from below a block (no vote) to wider than the shifts reach;
    // noise, or a shifted copy of noise (decisive votes), of either sign.
    const int w = 6 + static_cast<int>(rng() % 150), h = 6 + static_cast<int>(rng() % 60);
    const int shift = static_cast<int>(rng() % 21) - 10;
    ImageU8 l(w, h, 1), r(w, h, 1);
    for (auto& p : l.pixels) p = static_cast<std::uint8_t>(rng());
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        r.row(y)[x] = trial % 3 == 0 ? static_cast<std::uint8_t>(rng())
                                     : l.row(y)[std::clamp(x + shift, 0, w - 1)];
    for (int d_max : {1, 3, 12, 40, 4000}) expect_same_votes(l, r, d_max, "random " + std::to_string(trial));
  }
  SynthParams sp;
  sp.width = 160;
  sp.height = 120;
  sp.num_disp = 32;
  const SyntheticScene s = make_synthetic_scene(sp);
  expect_same_votes(s.left, s.right, 31, "synthetic");
  expect_same_votes(s.right, s.left, 31, "synthetic swapped");
  if (test::data_set_available("middlebury")) {
    const std::string dir = test::data_set_dir("middlebury") + "/teddy";
    const ImageU8 l = to_gray(read_image_u8(dir + "/left.png"));
    const ImageU8 r = to_gray(read_image_u8(dir + "/right.png"));
    expect_same_votes(l, r, 59, "teddy");
    expect_same_votes(r, l, 59, "teddy swapped");
  } else {
    TRISTEREO_REQUIRE_DATA("middlebury");
  }
}

// Every pair of ../shared/data, both ways round: the figures of docs/reliability.md.
TEST(CliWarnings, SwapCheckOnEveryDataSet) {
  for (const char* set : {"middlebury", "middlebury2014", "kitti2015", "eth3d"}) {
    if (!test::data_set_available(set)) {
      TRISTEREO_REQUIRE_DATA(set);
      continue;
    }
    std::ifstream tsv(test::data_set_dir(set) + "/datasets.tsv");
    std::string line;
    std::getline(tsv, line);  // header
    while (std::getline(tsv, line)) {
      std::istringstream fields(line);
      std::string name;
      int w = 0, h = 0, ndisp = 0;
      fields >> name >> w >> h >> ndisp;
      const std::string dir = test::data_set_dir(set) + "/" + name;
      const ImageU8 l = to_gray(read_image_u8(dir + "/left.png"));
      const ImageU8 r = to_gray(read_image_u8(dir + "/right.png"));
      const SwapVotes fwd = swap_votes(l.view(), r.view(), ndisp - 1);
      const SwapVotes back = swap_votes(r.view(), l.view(), ndisp - 1);
      std::printf("swap votes %s/%s D=%d: right order +%d/-%d, swapped +%d/-%d\n", set, name.c_str(), ndisp,
                  fwd.positive, fwd.negative, back.positive, back.negative);
      EXPECT_EQ(swapped_warning(l.view(), r.view(), 0, ndisp), "") << set << "/" << name;
      EXPECT_NE(swapped_warning(r.view(), l.view(), 0, ndisp), "") << set << "/" << name;
    }
  }
}

TEST(CliWarnings, RangeOutsideTheImage) {
  EXPECT_EQ(range_outside_image_warning(96, 0, 16), "");
  EXPECT_EQ(range_outside_image_warning(96, 95, 1), "");      // x = 95 matches right x = 0
  EXPECT_NE(range_outside_image_warning(96, 96, 1), "");      // nothing left
  EXPECT_NE(range_outside_image_warning(450, 500, 16), "");
  EXPECT_EQ(range_outside_image_warning(96, -110, 16), "");   // d = -95 still lands inside
  EXPECT_NE(range_outside_image_warning(96, -111, 16), "");   // d_max = -96: none
  EXPECT_NE(range_outside_image_warning(450, 500, 16).find("500..515"), std::string::npos);
}

TEST(CliWarnings, ThreadsBeyondCpus) {
  EXPECT_EQ(threads_warning(0, 2, false), "");
  EXPECT_EQ(threads_warning(2, 2, false), "");
  EXPECT_NE(threads_warning(3, 2, false).find("--threads 3 with only 2 CPUs allowed"), std::string::npos);
  EXPECT_NE(threads_warning(2, 1, true).find("in --cpus"), std::string::npos);
}

// Each parameter validate_params can refuse comes back under its option name.
TEST(CliWarnings, NoDepthWhenEveryDisparityPlusDoffsIsAtMostZero) {
  // Without --mesh too (issue 41): all-invalid depth must not pass silently.
  CameraParams cam{200, 0.1, 48, 32, -20};
  EXPECT_EQ(no_depth_warning(cam, "--camera", 0, 16),
            "warning: --camera: with doffs -20 px, no disparity searched (0..15) gives a finite positive depth "
            "(that needs disparity + doffs > 0): every depth, point and metric mesh vertex will be invalid; check "
            "the sign of doffs and --dmin");
  cam.doffs = -15;  // 15 + (-15) = 0: still no depth
  EXPECT_NE(no_depth_warning(cam, "--camera", 0, 16), "");
  cam.doffs = -14;  // the largest disparity gets one
  EXPECT_EQ(no_depth_warning(cam, "--camera", 0, 16), "");
  cam.doffs = 0;
  EXPECT_NE(no_depth_warning(cam, "--calib c.txt", -20, 16).find("--calib c.txt: with doffs 0 px"), std::string::npos);
}

TEST(CliOptionErrors, EveryRefusedFieldIsNamedAsAnOption) {
  struct Case {
    void (*set)(StereoParams&);
    const char* expected;
  };
  const Case cases[] = {
      {[](StereoParams& p) { p.num_disp = 0; }, "--ndisp 0 is out of range [1, 256]"},
      {[](StereoParams& p) { p.d_min = 5000; }, "--dmin 5000 is out of range"},
      {[](StereoParams& p) { p.tritree.psnr_deci_db = 5; }, "--psnr (in 0.1 dB) 5 is out of range"},
      {[](StereoParams& p) { p.tritree.max_area_px2 = 0; }, "--max-area 0 is out of range"},
      {[](StereoParams& p) { p.cost.window_w = 4; }, "--window width 4 must be odd"},
      {[](StereoParams& p) { p.cost.window_h = 33; }, "--window height 33 is out of range"},
      {[](StereoParams& p) { p.cost.truncation = 0; }, "--truncation 0 is out of range"},
      {[](StereoParams& p) { p.cost.asw_gamma_color = 0; }, "--gamma-color 0 is out of range"},
      {[](StereoParams& p) { p.cost.asw_gamma_proximity = 0; }, "--gamma-proximity 0 is out of range"},
      {[](StereoParams& p) { p.dp.lambda_q4 = -1; }, "--lambda -1 is out of range"},
  };
  for (const Case& c : cases) {
    StereoParams p;
    c.set(p);
    const std::string m = usage_message([&] { as_usage_error(nullptr, [&] { validate_params(p); }); });
    EXPECT_EQ(m.rfind(c.expected, 0), 0u) << m;
    EXPECT_EQ(m.find('_'), std::string::npos) << "an internal identifier leaked: " << m;
  }
  EXPECT_EQ(option_message("something = 3 broke"), "invalid parameter: something = 3 broke");
}

TEST(CliOptionErrors, FunctionPrefixesAreDropped) {
  EXPECT_EQ(without_function_prefix("write_disparity: negative disparity -1"), "negative disparity -1");
  EXPECT_EQ(without_function_prefix("write_mesh_ply (left image): null data"), "null data");
  EXPECT_EQ(without_function_prefix("cannot write 'x': No space left"), "cannot write 'x': No space left");
  EXPECT_EQ(without_function_prefix("corrupt PNG 'a_b.png': bad"), "corrupt PNG 'a_b.png': bad");
}

TEST(CliArgs, IntegersOutOfRangeAreNotCalledNonIntegers) {
  EXPECT_EQ(parse_int("--dmin", "-2147483647"), -2147483647);
  EXPECT_EQ(parse_int("--dmin", "2147483647"), 2147483647);
  EXPECT_EQ(usage_message([] { parse_int("--dmin", "-2147483648"); }).find("--dmin -2147483648 is out of range"), 0u);
  EXPECT_EQ(usage_message([] { parse_int("--dmin", "99999999999999999999"); }).find("is out of range"),
            std::string("--dmin 99999999999999999999 ").size());
  EXPECT_EQ(usage_message([] { parse_int("--ndisp", "sixty"); }), "--ndisp: 'sixty' is not an integer");
  EXPECT_EQ(usage_message([] { parse_int("--ndisp", " 5"); }), "--ndisp: ' 5' is not an integer");
  EXPECT_EQ(usage_message([] { parse_double("--psnr", "1e999"); }), "--psnr 1e999 is out of range");
  EXPECT_EQ(usage_message([] { parse_double("--psnr", "inf"); }), "--psnr: 'inf' is not a finite number");
}

TEST(CliArgs, AnOptionGivenTwiceIsAUsageError) {
  const char* argv[] = {"match", "--ndisp", "16", "--ndisp=32"};
  EXPECT_EQ(usage_message([&] { Args(4, const_cast<char**>(argv), {"ndisp"}, {}); }), "option --ndisp given twice");
  // A flag too (README: "option given twice" is a usage error).
  const char* flags[] = {"match", "--dense", "a", "--dense"};
  EXPECT_EQ(usage_message([&] { Args(4, const_cast<char**>(flags), {}, {"dense"}); }), "option --dense given twice");
}

TEST(CliArgs, DoubleDashEndsTheOptions) {
  const char* argv[] = {"match", "--dense", "--", "--odd-name.png", "--", "b.png"};
  const Args a(6, const_cast<char**>(argv), {"ndisp"}, {"dense"});
  EXPECT_TRUE(a.flag("dense"));
  EXPECT_EQ(a.positional(), (std::vector<std::string>{"--odd-name.png", "--", "b.png"}));
}

TEST(CliArgs, AnOptionWhereAValueBelongsIsNamed) {
  // "--disp --stats s.json" once read --stats as the disparity file and
  // complained about three paths.
  const char* argv[] = {"match", "l.png", "r.png", "--disp", "--stats", "s.json"};
  EXPECT_EQ(usage_message([&] { Args(6, const_cast<char**>(argv), {"disp", "stats"}, {}); }),
            "option --disp needs a value, but the option --stats follows it (a value that starts with -- goes as "
            "--disp=VALUE)");
  const char* inline_value[] = {"match", "--disp=--stats"};
  EXPECT_EQ(Args(2, const_cast<char**>(inline_value), {"disp", "stats"}, {}).get("disp", ""), "--stats");
  // A value that merely starts with -- but names no option is a value.
  const char* odd[] = {"match", "--disp", "--x.pfm"};
  EXPECT_EQ(Args(3, const_cast<char**>(odd), {"disp", "stats"}, {}).get("disp", ""), "--x.pfm");
}

TEST(CliArgs, OptionsWithoutEffectAreRefusedByTheTable) {
  const std::vector<OptionNeed> table = {
      {"mesh-ascii", {"mesh", "points"}, nullptr, "it writes their PLY files as ASCII"},
      {"gamma-color", {"weights"}, "adaptive", "it scales the adaptive weights' colour term"},
  };
  const char* alone[] = {"match", "--mesh-ascii"};
  EXPECT_EQ(usage_message([&] {
              check_option_needs(Args(2, const_cast<char**>(alone), {"mesh", "points"}, {"mesh-ascii"}), table);
            }),
            "--mesh-ascii has no effect without --mesh or --points (it writes their PLY files as ASCII)");
  const char* with_points[] = {"match", "--mesh-ascii", "--points", "p.ply"};
  EXPECT_EQ(usage_message([&] {
              check_option_needs(Args(4, const_cast<char**>(with_points), {"mesh", "points"}, {"mesh-ascii"}), table);
            }),
            "(no UsageError)");
  const char* box[] = {"match", "--gamma-color", "5", "--weights", "box"};
  EXPECT_EQ(usage_message([&] {
              check_option_needs(Args(5, const_cast<char**>(box), {"gamma-color", "weights"}, {}), table);
            }),
            "--gamma-color has no effect without --weights adaptive (it scales the adaptive weights' colour term)");
  const char* adaptive[] = {"match", "--gamma-color", "5", "--weights", "adaptive"};
  EXPECT_EQ(usage_message([&] {
              check_option_needs(Args(5, const_cast<char**>(adaptive), {"gamma-color", "weights"}, {}), table);
            }),
            "(no UsageError)");
}

// ---------------------------------------------------------------- outputs

namespace fs = std::filesystem;

class OutputSetTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("tristereo_outset_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
            "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  static std::string slurp(const std::string& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
  }
  std::vector<std::string> listing() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
  fs::path dir_;
};

// A writer as the library's are: the bytes to `p`, atomically.
std::function<void(const std::string&)> writes(const std::string& text) {
  return [text](const std::string& p) { write_text_file(p, text); };
}

TEST_F(OutputSetTest, EveryOutputInPlaceAndNothingElseLeft) {
  std::ofstream(path("a.csv")) << "old a";
  OutputSet set;
  set.add("--a", path("a.csv"), writes("new a"));
  set.add("--b", path("b.json"), writes("new b"));
  set.commit();
  EXPECT_EQ(slurp(path("a.csv")), "new a");
  EXPECT_EQ(slurp(path("b.json")), "new b");
  EXPECT_EQ(listing(), (std::vector<std::string>{"a.csv", "b.json"}));
}

TEST_F(OutputSetTest, ALastOutputThatFailsChangesNoTarget) {
  std::ofstream(path("a.csv")) << "old a";
  std::ofstream(path("b.ply")) << "old b";
  std::string seen_path;
  OutputSet set;
  set.add("--a", path("a.csv"), writes("new a"));
  set.add("--b", path("b.ply"), [&](const std::string& p) {
    seen_path = p;
    write_text_file(p, "new b");
  });
  set.add("--c", path("c.json"), [](const std::string& p) {
    throw Error(ErrorCode::kIoError, "write_text_file: cannot write '" + p + "': No space left on device");
  });
  try {
    set.commit();
    ADD_FAILURE() << "committed";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kIoError);
    // The target, not the temporary; the option as typed.
    EXPECT_EQ(std::string(e.what()), "--c: cannot write '" + path("c.json") + "': No space left on device");
  }
  // Written beside its target, with its extension (which picks the format).
  EXPECT_EQ(fs::path(seen_path).parent_path(), dir_);
  EXPECT_EQ(fs::path(seen_path).extension(), ".ply");
  EXPECT_EQ(slurp(path("a.csv")), "old a");
  EXPECT_EQ(slurp(path("b.ply")), "old b");
  EXPECT_EQ(listing(), (std::vector<std::string>{"a.csv", "b.ply"}));  // no c.json, no temporaries
}

TEST_F(OutputSetTest, ARenameThatFailsHalfWayPutsBackWhatItReplaced) {
  // A folder at the last target: staging succeeds, its rename fails after the
  // first two targets were replaced, which must then be put back.
  std::ofstream(path("a.csv")) << "old a";
  fs::create_directories(path("c.json"));
  std::ofstream(path("c.json") + "/inside") << "x";
  OutputSet set;
  set.add("--a", path("a.csv"), writes("new a"));
  set.add("--b", path("b.csv"), writes("new b"));
  set.add("--c", path("c.json"), writes("new c"));
  EXPECT_THROW(set.commit(), Error);
  EXPECT_EQ(slurp(path("a.csv")), "old a");
  EXPECT_EQ(listing(), (std::vector<std::string>{"a.csv", "c.json"}));  // b.csv was new: gone again
}

TEST_F(OutputSetTest, ALinkKeepsPointingAtTheFileItNames) {
  std::ofstream(path("real.csv")) << "old";
  fs::create_symlink(path("real.csv"), path("link.csv"));
  OutputSet set;
  set.add("--a", path("link.csv"), writes("new"));
  set.commit();
  EXPECT_TRUE(fs::is_symlink(path("link.csv")));
  EXPECT_EQ(slurp(path("real.csv")), "new");
}

TEST_F(OutputSetTest, AFolderCreatedForAFailedRunIsRemoved) {
  {
    OutputFolder folder(path("x/y"));
    EXPECT_TRUE(fs::is_directory(path("x/y")));
  }
  EXPECT_FALSE(fs::exists(path("x")));
  {
    OutputFolder folder(path("x/y"));
    folder.keep();
  }
  EXPECT_TRUE(fs::is_directory(path("x/y")));
  std::ofstream(path("file")) << "x";
  try {
    OutputFolder folder(path("file"));
    ADD_FAILURE() << "a file as a folder";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("Not a directory"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tristereo::cli

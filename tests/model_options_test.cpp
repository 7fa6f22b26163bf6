// The model's option table (src/model/model_options.cpp), which the command
// line and the Python module both build their parameters from: its ranges are
// validate_params()'s, its defaults StereoParams{}'s, its help complete.
// (python/tests/test_options.py checks the two interfaces against each other;
// this runs where Python is not built, e.g. the ARM builds under qemu.)
#include "src/model/model_options.hpp"

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "tristereo/status.hpp"

namespace tristereo {
namespace {

// Every option's value, as text: two parameter sets are equal when these are.
std::string all_values(const StereoParams& p) {
  std::string s;
  for (const ModelOption& o : model_options()) s += std::string(o.name) + "=" + o.get(p) + " ";
  return s;
}

StereoParams build(const std::vector<std::pair<std::string, std::string>>& given, bool refuse = false) {
  std::vector<GivenOption> g;
  for (const auto& [name, text] : given) {
    const ModelOption* o = find_model_option(name);
    EXPECT_NE(o, nullptr) << name;
    g.push_back({o, text});
  }
  return model_params(g, OptionSpelling::kCommandLine, refuse);
}

std::string error_of(const std::vector<std::pair<std::string, std::string>>& given, bool refuse = false) {
  try {
    build(given, refuse);
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    return e.what();
  }
  return "";
}

// What an option needs to reach its whole range (as in test_options.py).
const std::map<std::string, std::vector<std::pair<std::string, std::string>>> kContext = {
    {"max-area", {{"min-area", "1"}}},
    {"min-area", {{"max-area", "1024"}}},
    {"dmin", {{"ndisp", "1"}}},
    {"p1", {{"p2", "16000"}, {"census", "3"}}},
    {"p2", {{"p1", "0"}, {"census", "3"}}},
    {"gamma-color", {{"cost", "ad"}, {"weights", "adaptive"}}},
    {"gamma-proximity", {{"cost", "ad"}, {"weights", "adaptive"}}},
    {"truncation", {{"cost", "ad"}}},
    {"ad-weight", {{"cost", "ad_census"}}},
    {"lambda", {{"optimizer", "dp"}}},
};

TEST(ModelOptions, GivingTheDefaultChangesNothing) {
  const std::string defaults = all_values(build({{"ndisp", "16"}}));
  for (const ModelOption& o : model_options()) {
    if (o.kind == ModelOptionKind::kFlag || std::string(o.name) == "ndisp") continue;
    const std::string value = o.get(StereoParams{});
    EXPECT_EQ(all_values(build({{"ndisp", "16"}, {o.name, value}})), defaults) << o.name << " " << value;
  }
  // And the table's defaults are the library's (ndisp aside: it is required).
  StereoParams lib;
  lib.num_disp = 16;
  EXPECT_EQ(all_values(lib), defaults);
}

TEST(ModelOptions, RangesAreExactlyWhatIsAccepted) {
  int checked = 0;
  for (const ModelOption& o : model_options()) {
    if (o.kind != ModelOptionKind::kInt && o.kind != ModelOptionKind::kSize) continue;
    const auto ctx = kContext.count(o.name) ? kContext.at(o.name) : std::vector<std::pair<std::string, std::string>>{};
    for (long long v : {o.lo - 1, o.lo, o.hi, o.hi + 1}) {
      auto given = ctx;
      const bool ndisp_given = std::string(o.name) == "ndisp" || (!ctx.empty() && ctx[0].first == "ndisp");
      if (!ndisp_given) given.push_back({"ndisp", "16"});
      std::string text = std::to_string(v);
      if (o.kind == ModelOptionKind::kSize) text += "x" + std::to_string(o.lo);  // the other side small
      given.push_back({o.name, text});
      const std::string e = error_of(given);
      if (v < o.lo || v > o.hi) {
        EXPECT_EQ(e.rfind(std::string("--") + o.name + " ", 0), 0u) << o.name << " " << text << ": " << e;
      } else {
        EXPECT_EQ(e, "") << o.name << " " << text;
      }
      ++checked;
    }
  }
  EXPECT_EQ(checked, 4 * 26);  // every integer and size option
  // The decimal one: psnr.
  EXPECT_EQ(error_of({{"ndisp", "16"}, {"psnr", "10"}}), "");
  EXPECT_EQ(error_of({{"ndisp", "16"}, {"psnr", "70"}}), "");
  EXPECT_EQ(error_of({{"ndisp", "16"}, {"psnr", "9.9"}}), "--psnr 9.9 is out of range [10, 70] dB");
  EXPECT_EQ(error_of({{"ndisp", "16"}, {"psnr", "nan"}}), "--psnr: 'nan' is not a number");
}

TEST(ModelOptions, ChoicesAreTheParsersAndNothingElse) {
  for (const ModelOption& o : model_options()) {
    if (o.kind != ModelOptionKind::kChoice) continue;
    const auto ctx = kContext.count(o.name) ? kContext.at(o.name) : std::vector<std::pair<std::string, std::string>>{};
    std::string choices = o.choices;
    std::size_t start = 0;
    for (;;) {
      const std::size_t bar = choices.find('|', start);
      const std::string c = choices.substr(start, bar == std::string::npos ? bar : bar - start);
      auto given = ctx;
      given.push_back({"ndisp", "16"});
      if (std::string(o.name) == "weights") given.push_back({"cost", "ad"});  // adaptive needs the ad cost
      if (std::string(o.name) == "lr-source" && c == "costs") given.push_back({"optimizer", "paths"});
      given.push_back({o.name, c});
      EXPECT_EQ(error_of(given), "") << o.name << " " << c;
      if (std::string(o.name) != "mode") {
        EXPECT_EQ(o.get(build(given)), c) << o.name;
      }
      if (bar == std::string::npos) break;
      start = bar + 1;
    }
    const std::string e = error_of({{"ndisp", "16"}, {o.name, "bogus"}});
    EXPECT_EQ(e.rfind(std::string("--") + o.name, 0), 0u) << e;
  }
}

TEST(ModelOptions, OptionsOfAnotherModelAreRefusedOnlyWhenAsked) {
  EXPECT_EQ(error_of({{"ndisp", "16"}, {"lambda", "50"}}), "");
  // The value that makes an option idle is named with where it came from.
  EXPECT_EQ(error_of({{"ndisp", "16"}, {"lambda", "50"}}, true),
            "--lambda has no effect with --optimizer paths (the default): it is used only with --optimizer dp");
  EXPECT_EQ(error_of({{"ndisp", "16"}, {"mode", "paper"}, {"uniqueness", "5"}}, true),
            "--uniqueness has no effect with --optimizer dp (from --mode paper): it is used only with --optimizer paths");
  EXPECT_EQ(error_of({{"ndisp", "16"}, {"truncation", "20"}}, true),
            "--truncation has no effect with --cost census (the default): it is used only with --cost ad or --cost ad_census");
  EXPECT_EQ(error_of({{"ndisp", "16"}, {"lr-max-diff", "-1"}, {"lr-source", "mirror"}}, true),
            "--lr-source has no effect with --lr-max-diff -1: it is used only with --lr-max-diff other than -1");
  // A value out of range is named before an option without effect.
  EXPECT_EQ(error_of({{"ndisp", "16"}, {"truncation", "256"}}, true), "--truncation 256 is out of range [1, 255]");
  EXPECT_EQ(error_of({{"ndisp", "16"}, {"mode", "paper"}, {"support-conf", "170"}}, true),
            "--support-conf has no effect with --support-prior 0 (from --mode paper): it is used only with "
            "--support-prior other than 0");
  EXPECT_EQ(error_of({{"ndisp", "16"}, {"mode", "paper"}, {"lambda", "50"}, {"gap", "inv"}}, true), "");
  // Depth edges interpolate a mesh: a dense frame has none; the paper's model
  // starts without them and may take them.
  EXPECT_EQ(error_of({{"ndisp", "16"}, {"dense", "1"}, {"edge-spread", "16"}}, true),
            "--edge-spread has no effect with --dense: it is used only with no --dense");
  EXPECT_EQ(error_of({{"ndisp", "16"}, {"mode", "paper"}, {"edge-spread", "16"}}, true), "");
  EXPECT_EQ(build({{"ndisp", "16"}, {"mode", "paper"}}).interp.edge_spread_q4, 0);
  EXPECT_EQ(build({{"ndisp", "16"}}).interp.edge_spread_q4, 48);
  // The row DP's left-right check defaults to the mirrored pass.
  EXPECT_EQ(build({{"ndisp", "16"}, {"optimizer", "dp"}}).validity.lr_source, LrSource::kMirroredPass);
  EXPECT_EQ(build({{"ndisp", "16"}}).validity.lr_source, LrSource::kSummedCosts);
}

TEST(ModelOptions, MessagesNameTheOptionAsEachInterfaceSpellsIt) {
  std::vector<GivenOption> g = {{find_model_option("ndisp"), "16"}, {find_model_option("p2"), "10"}};
  try {
    model_params(g, OptionSpelling::kPython, true);
    ADD_FAILURE() << "p2 = 10 < p1 accepted";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "p2 = 10 is out of range [120, 16000]");
  }
  EXPECT_EQ(error_of({{"ndisp", "16"}, {"p2", "10"}}), "--p2 10 is out of range [120, 16000]");
  EXPECT_EQ(error_of({}), "--ndisp D is required (number of disparities, 1..256)");
  EXPECT_EQ(find_model_option("lambda")->keyword, std::string("lambda_q4"));
  EXPECT_EQ(find_model_option_keyword("lambda_q4"), find_model_option("lambda"));
}

TEST(ModelOptions, HelpListsEveryOptionWithItsDefault) {
  const std::string help = "\n" + model_options_help();  // every entry starts a line
  for (const ModelOption& o : model_options()) {
    const std::size_t at = help.find(std::string("\n  --") + o.name + (o.kind == ModelOptionKind::kFlag ? "" : " "));
    ASSERT_NE(at, std::string::npos) << o.name;
    if (o.kind == ModelOptionKind::kFlag || std::string(o.name) == "ndisp") continue;
    const std::size_t next = help.find("\n  --", at + 1);
    // The entry's words, with the wrapping's line breaks and indentation as single spaces.
    std::string entry;
    for (char c : help.substr(at, next == std::string::npos ? std::string::npos : next - at))
      if (!(c == ' ' || c == '\n') || (!entry.empty() && entry.back() != ' ')) entry += c == '\n' ? ' ' : c;
    EXPECT_NE(entry.find("(default " + o.get(StereoParams{})), std::string::npos) << "[" << entry << "]";
  }
}

}  // namespace
}  // namespace tristereo

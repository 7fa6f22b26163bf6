// The profiler's CSV and JSON outputs parse back to the numbers that went in.
#include "src/profile/profile_report.hpp"

#include <sys/mman.h>

#include <gtest/gtest.h>

#include <cctype>
#include <cstdlib>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "tristereo/status.hpp"

namespace tristereo {
namespace {

// ---- A minimal JSON reader: enough to check that the writer's output is
// valid JSON and to look values up by path. Fails the test on bad syntax.
struct Json {
  enum Kind { kNull, kBool, kNumber, kString, kArray, kObject } kind = kNull;
  bool boolean = false;
  double number = 0;
  std::string text;
  std::vector<Json> items;
  std::map<std::string, Json> members;

  const Json& operator[](const std::string& key) const {
    static const Json missing;
    auto it = members.find(key);
    return it == members.end() ? missing : it->second;
  }
};

class JsonParser {
 public:
  explicit JsonParser(const std::string& s) : s_(s) {}

  bool parse(Json& out) {
    if (!value(out)) return false;
    skip_ws();
    return pos_ == s_.size();
  }

 private:
  void skip_ws() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  bool literal(const char* word) {
    const std::string w(word);
    if (s_.compare(pos_, w.size(), w) != 0) return false;
    pos_ += w.size();
    return true;
  }
  bool string(std::string& out) {
    if (pos_ >= s_.size() || s_[pos_] != '"') return false;
    ++pos_;
    while (pos_ < s_.size() && s_[pos_] != '"') {
      char c = s_[pos_++];
      if (static_cast<unsigned char>(c) < 0x20) return false;  // raw control chars are invalid
      if (c == '\\') {
        if (pos_ >= s_.size()) return false;
        const char e = s_[pos_++];
        if (e == 'n')
          c = '\n';
        else if (e == 't')
          c = '\t';
        else if (e == 'r')
          c = '\r';
        else if (e == '"' || e == '\\' || e == '/')
          c = e;
        else if (e == 'u') {
          if (pos_ + 4 > s_.size()) return false;
          c = static_cast<char>(std::strtol(s_.substr(pos_, 4).c_str(), nullptr, 16));
          pos_ += 4;
        } else {
          return false;
        }
      }
      out += c;
    }
    if (pos_ >= s_.size()) return false;
    ++pos_;
    return true;
  }
  bool value(Json& out) {
    skip_ws();
    if (pos_ >= s_.size()) return false;
    const char c = s_[pos_];
    if (c == '{') {
      out.kind = Json::kObject;
      ++pos_;
      skip_ws();
      if (pos_ < s_.size() && s_[pos_] == '}') return ++pos_, true;
      for (;;) {
        skip_ws();
        std::string key;
        if (!string(key)) return false;
        skip_ws();
        if (pos_ >= s_.size() || s_[pos_++] != ':') return false;
        if (out.members.count(key)) return false;  // duplicate keys
        if (!value(out.members[key])) return false;
        skip_ws();
        if (pos_ >= s_.size()) return false;
        if (s_[pos_] == ',') {
          ++pos_;
          continue;
        }
        if (s_[pos_] == '}') return ++pos_, true;
        return false;
      }
    }
    if (c == '[') {
      out.kind = Json::kArray;
      ++pos_;
      skip_ws();
      if (pos_ < s_.size() && s_[pos_] == ']') return ++pos_, true;
      for (;;) {
        out.items.emplace_back();
        if (!value(out.items.back())) return false;
        skip_ws();
        if (pos_ >= s_.size()) return false;
        if (s_[pos_] == ',') {
          ++pos_;
          continue;
        }
        if (s_[pos_] == ']') return ++pos_, true;
        return false;
      }
    }
    if (c == '"') {
      out.kind = Json::kString;
      return string(out.text);
    }
    if (literal("true")) {
      out.kind = Json::kBool;
      out.boolean = true;
      return true;
    }
    if (literal("false")) {
      out.kind = Json::kBool;
      return true;
    }
    if (literal("null")) {
      out.kind = Json::kNull;
      return true;
    }
    // JSON numbers: -?digits[.digits][e[+-]digits]; strtod accepts more
    // (hex, inf, nan), so the first character is checked by hand.
    if (c != '-' && !std::isdigit(static_cast<unsigned char>(c))) return false;
    const char* begin = s_.c_str() + pos_;
    char* end = nullptr;
    out.kind = Json::kNumber;
    out.number = std::strtod(begin, &end);
    if (end == begin) return false;
    pos_ += static_cast<std::size_t>(end - begin);
    return true;
  }

  const std::string& s_;
  std::size_t pos_ = 0;
};

Json parse_json_or_fail(const std::string& text) {
  Json j;
  EXPECT_TRUE(JsonParser(text).parse(j)) << "invalid JSON:\n" << text;
  return j;
}

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, sep)) out.push_back(cell);
  return out;
}

// Frames with stage k of frame f taking (f + 1) * (k + 1) ms plus a few ns, so
// every cell has a distinct, hand-checkable value.
FrameLog make_log(int frames) {
  FrameLog log(static_cast<std::size_t>(frames));
  for (int f = 0; f < frames; ++f) {
    FrameSample s;
    std::int64_t sum = 0;
    for (int k = 0; k < kProfileStageCount; ++k) {
      s.stage_ns[k] = (f + 1) * (k + 1) * std::int64_t{1000000} + k;
      sum += s.stage_ns[k];
    }
    s.total_ns = sum + 7;
    s.cpu_ns = 2 * s.total_ns;
    EXPECT_TRUE(log.push(s));
  }
  return log;
}

const ProfileMachine kMachine{"Test CPU @ 1 GHz", 4};

ProfileRunConfig make_config(bool mesh_output, int frames) {
  ProfileRunConfig c;
  c.source = "synthetic";
  c.width = 640;
  c.height = 480;
  c.num_disp = 64;
  c.weights = "box";
  c.window_w = 5;
  c.window_h = 7;
  c.psnr_db = 40;
  c.max_area_px2 = 100;
  c.threads = 2;
  c.kernels = "avx2";
  c.cpus = {2, 3};
  c.realtime = true;
  c.realtime_priority = 80;
  c.gpio = "gpiochip0:17,gpiochip0:27";
  c.mesh_output = mesh_output;
  c.warmup_frames = 5;
  c.frames = frames;
  c.working_memory_bytes = 640 * 480 * 37;
  return c;
}

TEST(FramesCsv, HeaderRowsAndExactValues) {
  const FrameLog log = make_log(4);
  std::ostringstream os;
  write_frames_csv(os, log, make_config(/*mesh_output=*/false, 4));
  std::istringstream in(os.str());
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "frame,tritree_ms,cost_aggregation_ms,dp_ms,fill_ms,interpolation_ms,total_ms,cpu_ms");
  std::vector<std::vector<std::string>> rows;
  while (std::getline(in, line)) rows.push_back(split(line, ','));
  ASSERT_EQ(rows.size(), 4u);
  for (const auto& r : rows) ASSERT_EQ(r.size(), 8u);
  EXPECT_EQ(rows[0][0], "0");
  EXPECT_EQ(rows[3][0], "3");
  EXPECT_EQ(rows[0][1], "1.000000");  // tritree of frame 0: 1 ms + 0 ns
  EXPECT_EQ(rows[2][3], "9.000002");  // dp (k = 2) of frame 2: 9 ms + 2 ns
  EXPECT_EQ(rows[1][4], "10.000004");  // fill (k = 4) of frame 1: no right_pass column
  EXPECT_EQ(rows[1][5], "12.000005");  // interpolation (k = 5) of frame 1
  // total of frame 0: 1+...+9 ms + (0+...+8) ns + 7 ns (the right-pass, mesh,
  // rectify and prior stages are in the total even when their columns are not written).
  EXPECT_EQ(rows[0][6], "45.000043");
  EXPECT_EQ(rows[0][7], "90.000086");
}

TEST(FramesCsv, RectifyColumnComesFirstWhenFramesAreRaw) {
  ProfileRunConfig config = make_config(false, 3);
  EXPECT_EQ(frames_csv_columns(config)[1], "tritree_ms");
  config.rectify = true;
  const std::vector<std::string> cols = frames_csv_columns(config);
  ASSERT_GE(cols.size(), 3u);
  EXPECT_EQ(cols[1], "rectify_ms");
  EXPECT_EQ(cols[2], "tritree_ms");
  const ProfileReport r = make_profile_report(config, make_log(3), 1000, 0, kMachine);
  ASSERT_FALSE(r.stages.empty());
  EXPECT_EQ(r.stages[0].name, "rectify");
  EXPECT_NEAR(r.stages[0].stats.min_ms, 8.000007, 1e-12);  // k = 7, frame 0
}

TEST(FramesCsv, MeshOutputColumnAndNegativeNs) {
  FrameLog log(1);
  FrameSample s;
  s.stage_ns[static_cast<int>(ProfileStage::kMeshOutput)] = 123456789;
  s.total_ns = -1;  // never produced by a monotonic clock, but must not print garbage
  s.cpu_ns = 0;
  ASSERT_TRUE(log.push(s));
  std::ostringstream os;
  write_frames_csv(os, log, make_config(/*mesh_output=*/true, 1));
  EXPECT_EQ(os.str(),
            "frame,tritree_ms,cost_aggregation_ms,dp_ms,fill_ms,interpolation_ms,mesh_output_ms,total_ms,"
            "cpu_ms\n0,0.000000,0.000000,0.000000,0.000000,0.000000,123.456789,-0.000001,0.000000\n");
  EXPECT_EQ(frames_csv_columns(make_config(true, 1)).size(), 9u);
  EXPECT_EQ(frames_csv_columns(make_config(false, 1)).size(), 8u);
}

// A mirrored left-right check's right-view pass is a column (after dp) and a
// stage only when the run had one.
// The support prior (k = 8, after dp in the reports) only when it ran.
TEST(FramesCsv, PriorColumnOnlyWhenConfigured) {
  const FrameLog log = make_log(2);
  ProfileRunConfig config = make_config(/*mesh_output=*/false, 2);
  config.prior = true;
  std::ostringstream os;
  write_frames_csv(os, log, config);
  std::istringstream in(os.str());
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "frame,tritree_ms,cost_aggregation_ms,dp_ms,prior_ms,fill_ms,interpolation_ms,total_ms,cpu_ms");
  ASSERT_TRUE(std::getline(in, line));
  ASSERT_TRUE(std::getline(in, line));
  const std::vector<std::string> row = split(line, ',');
  ASSERT_EQ(row.size(), 9u);
  EXPECT_EQ(row[4], "18.000008");  // prior (k = 8) of frame 1
  const ProfileReport r = make_profile_report(config, log, 1000, 0, kMachine);
  ASSERT_EQ(r.stages.size(), 6u);
  EXPECT_EQ(r.stages[3].name, "prior");
  std::ostringstream json;
  write_profile_json(json, r);
  const Json j = parse_json_or_fail(json.str());
  EXPECT_TRUE(j["config"]["prior"].boolean);
  EXPECT_NEAR(j["stages"]["prior"]["max_ms"].number, 18.000008, 1e-9);
  config.prior = false;
  EXPECT_EQ(frames_csv_columns(config).size(), 8u);
}

TEST(FramesCsv, RightPassColumnOnlyWhenConfigured) {
  const FrameLog log = make_log(2);
  ProfileRunConfig config = make_config(/*mesh_output=*/false, 2);
  config.right_pass = true;
  std::ostringstream os;
  write_frames_csv(os, log, config);
  std::istringstream in(os.str());
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line,
            "frame,tritree_ms,cost_aggregation_ms,dp_ms,right_pass_ms,fill_ms,interpolation_ms,total_ms,cpu_ms");
  ASSERT_TRUE(std::getline(in, line));
  ASSERT_TRUE(std::getline(in, line));
  const std::vector<std::string> row = split(line, ',');
  ASSERT_EQ(row.size(), 9u);
  EXPECT_EQ(row[4], "8.000003");  // right_pass (k = 3) of frame 1
  EXPECT_EQ(row[5], "10.000004");  // fill (k = 4) of frame 1
  EXPECT_EQ(frames_csv_columns(config).size(), 9u);

  const ProfileReport r = make_profile_report(config, log, 1000, 0, kMachine);
  ASSERT_EQ(r.stages.size(), 6u);
  EXPECT_EQ(r.stages[3].name, "right_pass");
  EXPECT_NEAR(r.stages[3].stats.max_ms, 8.000003, 1e-12);
  EXPECT_EQ(r.stages[4].name, "fill");
  std::ostringstream table;
  write_profile_table(table, r);
  EXPECT_NE(table.str().find("\nright_pass "), std::string::npos) << table.str();
  std::ostringstream json;
  write_profile_json(json, r);
  const Json j = parse_json_or_fail(json.str());
  EXPECT_TRUE(j["config"]["right_pass"].boolean);
  EXPECT_NEAR(j["stages"]["right_pass"]["p50_ms"].number, (4.000003 + 8.000003) / 2, 1e-9);
}

TEST(ProfileReport, SummaryNumbers) {
  const FrameLog log = make_log(10);
  const ProfileReport r =
      make_profile_report(make_config(false, 10), log,
                          /*wall_ns=*/500000000, /*peak_rss=*/3 << 20, kMachine);
  ASSERT_EQ(r.stages.size(), 5u);
  EXPECT_EQ(r.stages[0].name, "tritree");
  EXPECT_EQ(r.stages[3].name, "fill");
  EXPECT_EQ(r.stages[4].name, "interpolation");
  // dp (k = 2): 3, 6, ..., 30 ms (+2 ns): p50 of 10 values = mean of 5th and 6th.
  EXPECT_NEAR(r.stages[2].stats.p50_ms, 16.5 + 2e-6, 1e-9);
  EXPECT_NEAR(r.stages[2].stats.min_ms, 3.000002, 1e-12);
  EXPECT_NEAR(r.stages[2].stats.max_ms, 30.000002, 1e-12);
  EXPECT_EQ(r.total.count, 10u);
  // Stages (k + 1) ms summed over the 9 stages: 45 ms a frame-unit, plus 0 + .. + 8 + 7 ns.
  EXPECT_NEAR(r.total.mean_ms, 45.0 * 5.5 + 43e-6, 1e-9);
  EXPECT_NEAR(r.cpu.mean_ms, 2 * r.total.mean_ms, 1e-9);
  EXPECT_NEAR(r.fps_from_mean, 1000.0 / r.total.mean_ms, 1e-9);
  EXPECT_DOUBLE_EQ(r.wall_s, 0.5);
  EXPECT_DOUBLE_EQ(r.wall_fps, 20.0);
  EXPECT_DOUBLE_EQ(r.peak_rss_mb, 3.0);
  EXPECT_EQ(r.machine.cpu_model, kMachine.cpu_model);

  const ProfileReport with_mesh = make_profile_report(make_config(true, 10), log, 1, 0, kMachine);
  ASSERT_EQ(with_mesh.stages.size(), 6u);
  EXPECT_EQ(with_mesh.stages[5].name, "mesh_output");
  EXPECT_NEAR(with_mesh.stages[5].stats.max_ms, 70.000006, 1e-12);  // k = 6, frame 10
}

TEST(ProfileReport, RejectsEmptyLogAndBadWallTime) {
  FrameLog empty(4);
  EXPECT_THROW(make_profile_report(make_config(false, 0), empty, 1000, 0, kMachine), Error);
  const FrameLog log = make_log(2);
  EXPECT_THROW(make_profile_report(make_config(false, 2), log, 0, 0, kMachine), Error);
  EXPECT_THROW(make_profile_report(make_config(false, 2), log, -5, 0, kMachine), Error);
}

TEST(ProfileJson, ParsesBackWithConfigStagesAndFps) {
  const FrameLog log = make_log(10);
  ProfileRunConfig config = make_config(true, 10);
  const ProfileReport r = make_profile_report(config, log, 250000000, 64 << 20, kMachine);
  std::ostringstream os;
  write_profile_json(os, r);
  const Json j = parse_json_or_fail(os.str());
  ASSERT_EQ(j.kind, Json::kObject);

  const Json& c = j["config"];
  EXPECT_EQ(c["source"].text, "synthetic");
  EXPECT_EQ(c["width"].number, 640);
  EXPECT_EQ(c["height"].number, 480);
  EXPECT_EQ(c["ndisp"].number, 64);
  EXPECT_EQ(c["threads"].number, 2);
  EXPECT_EQ(c["kernels"].text, "avx2");
  ASSERT_EQ(c["cpus"].items.size(), 2u);
  EXPECT_EQ(c["cpus"].items[1].number, 3);
  ASSERT_EQ(c["window"].items.size(), 2u);
  EXPECT_EQ(c["window"].items[1].number, 7);
  EXPECT_EQ(c["realtime"].kind, Json::kBool);
  EXPECT_TRUE(c["realtime"].boolean);
  EXPECT_EQ(c["realtime_priority"].number, 80);
  EXPECT_EQ(c["gpio"].text, "gpiochip0:17,gpiochip0:27");
  EXPECT_TRUE(c["mesh_output"].boolean);
  EXPECT_EQ(c["right_pass"].kind, Json::kBool);
  EXPECT_FALSE(c["right_pass"].boolean);
  EXPECT_FALSE(c["dense"].boolean);
  EXPECT_EQ(c["frames"].number, 10);
  EXPECT_EQ(c["warmup_frames"].number, 5);

  EXPECT_EQ(j["machine"]["cpu_model"].text, "Test CPU @ 1 GHz");
  EXPECT_EQ(j["machine"]["online_cpus"].number, 4);

  const Json& stages = j["stages"];
  ASSERT_EQ(stages.members.size(), 6u);
  for (const char* name : {"tritree", "cost_aggregation", "dp", "fill", "interpolation", "mesh_output"}) {
    const Json& s = stages[name];
    ASSERT_EQ(s.kind, Json::kObject) << name;
    for (const char* field :
         {"count", "min_ms", "p50_ms", "p90_ms", "p99_ms", "max_ms", "mean_ms", "std_ms"})
      EXPECT_EQ(s[field].kind, Json::kNumber) << name << "." << field;
  }
  EXPECT_EQ(stages["dp"]["count"].number, 10);
  EXPECT_NEAR(stages["dp"]["p50_ms"].number, 16.500002, 1e-9);
  EXPECT_NEAR(stages["tritree"]["max_ms"].number, 10.0, 1e-9);
  EXPECT_NEAR(j["total"]["mean_ms"].number, r.total.mean_ms, 1e-6);
  EXPECT_NEAR(j["cpu"]["p99_ms"].number, r.cpu.p99_ms, 1e-6);
  EXPECT_NEAR(j["fps"]["wall"].number, 40.0, 1e-9);
  EXPECT_NEAR(j["fps"]["from_mean"].number, r.fps_from_mean, 1e-3);
  EXPECT_NEAR(j["wall_s"].number, 0.25, 1e-9);
  EXPECT_NEAR(j["peak_rss_mb"].number, 64.0, 1e-9);
  EXPECT_EQ(j["working_memory_bytes"].number, 640 * 480 * 37);
  EXPECT_NEAR(j["working_memory_bytes_per_px"].number, 37.0, 1e-9);
}

TEST(ProfileJson, StringsAreEscaped) {
  const std::string nasty = "cpu \"X\" \\ tab\t nl\n bell\x07 end";
  EXPECT_EQ(json_quote(nasty), "\"cpu \\\"X\\\" \\\\ tab\\t nl\\n bell\\u0007 end\"");
  Json j;
  ASSERT_TRUE(JsonParser(json_quote(nasty)).parse(j));
  EXPECT_EQ(j.text, nasty);

  // A whole report whose free-text fields need escaping still parses back.
  const FrameLog log = make_log(1);
  ProfileRunConfig config = make_config(false, 1);
  config.gpio = "chip\"0\":1";
  ProfileReport r = make_profile_report(config, log, 1000, 0, kMachine);
  r.machine.cpu_model = nasty;
  std::ostringstream os;
  write_profile_json(os, r);
  const Json parsed = parse_json_or_fail(os.str());
  EXPECT_EQ(parsed["config"]["gpio"].text, "chip\"0\":1");
  EXPECT_EQ(parsed["machine"]["cpu_model"].text, nasty);
}

TEST(ProfileJson, MinimalReaderRejectsInvalidJson) {
  // The checks above are only as good as this reader: it must refuse these.
  for (const char* bad : {"{", "{\"a\": }", "{\"a\": 1,}", "[1 2]", "{\"a\": nan}", "{\"a\": 1} x",
                          "{\"a\": \"x\ny\"}", "{\"a\": 1, \"a\": 2}"}) {
    Json j;
    EXPECT_FALSE(JsonParser(bad).parse(j)) << bad;
  }
}

TEST(ProfileTable, ListsEveryStageAndFps) {
  const FrameLog log = make_log(3);
  const ProfileReport r =
      make_profile_report(make_config(true, 3), log, 1000000000, 10 << 20, kMachine);
  std::ostringstream os;
  write_profile_table(os, r);
  const std::string t = os.str();
  for (const char* name : {"tritree", "cost_aggregation", "dp", "fill", "interpolation", "mesh_output",
                           "total", "cpu (process)"})
    EXPECT_NE(t.find(std::string("\n") + name + " "), std::string::npos) << name << " in\n" << t;
  EXPECT_NE(t.find("3.00 wall"), std::string::npos) << t;  // 3 frames in 1 s
  EXPECT_NE(t.find("peak RSS 10.0 MiB"), std::string::npos) << t;
  EXPECT_NE(t.find("640x480, D=64"), std::string::npos) << t;
}

// ---- The soak's figures: resident-memory trace and latency drift.

TEST(RssTrace, SamplesAtStartEveryIntervalAndEnd) {
  EXPECT_EQ(RssTrace::interval_for(10000, 100), 100);
  EXPECT_EQ(RssTrace::interval_for(10001, 100), 101);
  EXPECT_EQ(RssTrace::interval_for(5, 100), 1);
  RssTrace t(10, 3);  // due after 0, 3, 6, 9 and 10 frames
  std::vector<int> due;
  for (int done = 0; done <= 10; ++done)
    if (t.due(done)) due.push_back(done);
  EXPECT_EQ(due, (std::vector<int>{0, 3, 6, 9, 10}));
  const std::int64_t rss[] = {100, 400, 250, 300, 200};
  for (std::size_t i = 0; i < due.size(); ++i) EXPECT_TRUE(t.push(due[i], rss[i] << 10));
  EXPECT_FALSE(t.push(11, 1));  // full: 10 / 3 + 2 = 5 samples
  ASSERT_EQ(t.size(), 5u);
  EXPECT_EQ(t[4].frame, 10);
  const RssSummary s = t.summary();
  EXPECT_EQ(s.samples, 5u);
  EXPECT_EQ(s.start_bytes, 100 << 10);
  EXPECT_EQ(s.end_bytes, 200 << 10);
  EXPECT_EQ(s.max_bytes, 400 << 10);

  RssTrace once(4, 4);  // 0 and 4: the last frame is also a multiple
  EXPECT_TRUE(once.push(0, 7));
  EXPECT_FALSE(once.push(0, 8));  // the same frame twice is recorded once
  EXPECT_TRUE(once.push(4, 9));
  EXPECT_EQ(once.summary().end_bytes, 9);
  EXPECT_THROW(RssTrace(0, 1), Error);
  EXPECT_THROW(RssTrace(5, 0), Error);
  EXPECT_THROW(RssTrace(5, 1).summary(), Error);
}

TEST(RssTrace, CurrentRssSeesTouchedAndFreedMemory) {
  const std::int64_t before = current_rss_bytes();
  ASSERT_GT(before, 0);
  // A mapping of its own, not the allocator's: under AddressSanitizer freed
  // blocks wait in a quarantine, and what free() returns is the allocator's choice.
  constexpr std::size_t kBytes = 64u << 20;
  void* map = mmap(nullptr, kBytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  ASSERT_NE(map, MAP_FAILED);
  auto* block = static_cast<volatile char*>(map);
  for (std::size_t i = 0; i < kBytes; i += 4096) block[i] = static_cast<char>(i >> 12);
  const std::int64_t touched = current_rss_bytes();
  EXPECT_GE(touched - before, static_cast<std::int64_t>(kBytes) - (4 << 20));
  ASSERT_EQ(munmap(map, kBytes), 0);
  EXPECT_LT(current_rss_bytes(), touched - (32 << 20));
}

// A log whose first 1000 frames take 1 ms and the rest 1.5 ms.
FrameLog drifting_log(int frames) {
  FrameLog log(static_cast<std::size_t>(frames));
  for (int f = 0; f < frames; ++f) {
    FrameSample s;
    s.total_ns = f < 1000 ? 1000000 : 1500000;
    s.cpu_ns = s.total_ns;
    log.push(s);
  }
  return log;
}

TEST(ProfileReport, DriftComparesFirstAndLastThousandFrames) {
  const ProfileReport r = make_profile_report(make_config(false, 2500), drifting_log(2500), 1000, 0, kMachine);
  EXPECT_EQ(r.drift_window_frames, 1000u);
  EXPECT_EQ(r.first_window.count, 1000u);
  EXPECT_DOUBLE_EQ(r.first_window.p50_ms, 1.0);
  EXPECT_DOUBLE_EQ(r.last_window.p50_ms, 1.5);
  EXPECT_DOUBLE_EQ(r.p50_change_pct, 50.0);
  EXPECT_FALSE(r.has_rss);
  // Fewer than 2000 frames: each window is half the run.
  const ProfileReport half = make_profile_report(make_config(false, 1200), drifting_log(1200), 1000, 0, kMachine);
  EXPECT_EQ(half.drift_window_frames, 600u);
  EXPECT_DOUBLE_EQ(half.first_window.p50_ms, 1.0);
  EXPECT_DOUBLE_EQ(half.last_window.max_ms, 1.5);
  EXPECT_DOUBLE_EQ(half.last_window.min_ms, 1.0);  // frames 600..1199 span the step
  EXPECT_EQ(make_profile_report(make_config(false, 1), drifting_log(1), 1000, 0, kMachine).drift_window_frames, 0u);
}

TEST(ProfileJson, RssAndDriftParseBack) {
  RssTrace trace(2500, 1000);
  trace.push(0, 10 << 20);
  trace.push(1000, 12 << 20);
  trace.push(2000, 11 << 20);
  trace.push(2500, (10 << 20) + (300 << 10));
  const ProfileReport r =
      make_profile_report(make_config(false, 2500), drifting_log(2500), 1000, 0, kMachine, &trace);
  ASSERT_TRUE(r.has_rss);
  std::ostringstream os;
  write_profile_json(os, r);
  const Json j = parse_json_or_fail(os.str());
  const Json& rss = j["rss"];
  EXPECT_EQ(rss["samples"].number, 4);
  EXPECT_EQ(rss["every_frames"].number, 1000);
  EXPECT_NEAR(rss["start_mb"].number, 10.0, 1e-9);
  EXPECT_NEAR(rss["max_mb"].number, 12.0, 1e-9);
  EXPECT_NEAR(rss["end_mb"].number, 10.293, 1e-9);  // 10 MiB + 300 KiB, 3 decimals
  EXPECT_EQ(rss["end_minus_start_kib"].number, 300);
  ASSERT_EQ(rss["trace_kib"].items.size(), 4u);
  EXPECT_EQ(rss["trace_kib"].items[1].items[0].number, 1000);
  EXPECT_EQ(rss["trace_kib"].items[1].items[1].number, 12 * 1024);
  const Json& drift = j["drift"];
  EXPECT_EQ(drift["window_frames"].number, 1000);
  EXPECT_NEAR(drift["first"]["p50_ms"].number, 1.0, 1e-9);
  EXPECT_NEAR(drift["last"]["p99_ms"].number, 1.5, 1e-9);
  EXPECT_NEAR(drift["p50_change_pct"].number, 50.0, 1e-9);
  EXPECT_NEAR(drift["p99_change_pct"].number, 50.0, 1e-9);
  EXPECT_NEAR(drift["first_cpu"]["p99_ms"].number, 1.0, 1e-9);
  EXPECT_NEAR(drift["last_cpu"]["p50_ms"].number, 1.5, 1e-9);
  EXPECT_EQ(j["outputs"].kind, Json::kNull);  // no check given
  std::ostringstream table;
  write_profile_table(table, r);
  EXPECT_NE(table.str().find("RSS over the loop: start 10.00 MiB, end 10.29 MiB (+300 KiB), max 12.00 MiB (4 samples)"),
            std::string::npos)
      << table.str();
  EXPECT_NE(table.str().find("(+50.0 %)"), std::string::npos) << table.str();
}

TEST(ProfileJson, OutputCheckSaysWhetherTheLastFrameEqualsTheFirst) {
  ProfileOutputCheck check;
  check.has = true;
  check.first_frame = 0;
  check.last_frame = 2499;
  check.first_input = 3;
  check.last_input = 3;
  check.first_digest = "mesh=00ff disp=0a";
  check.last_digest = check.first_digest;
  for (const bool same : {true, false}) {
    if (!same) check.last_digest = "mesh=00ff disp=0b";
    const ProfileReport r =
        make_profile_report(make_config(false, 2500), drifting_log(2500), 1000, 0, kMachine, nullptr, &check);
    std::ostringstream os;
    write_profile_json(os, r);
    const Json j = parse_json_or_fail(os.str());
    const Json& o = j["outputs"];
    EXPECT_EQ(o["last_frame"].number, 2499);
    EXPECT_EQ(o["first_input"].number, 3);
    EXPECT_EQ(o["first_digest"].text, "mesh=00ff disp=0a");
    EXPECT_TRUE(o["same_input"].boolean);
    EXPECT_EQ(o["identical"].boolean, same);
    std::ostringstream table;
    write_profile_table(table, r);
    EXPECT_NE(table.str().find(same ? "(identical)" : "(DIFFERENT)"), std::string::npos) << table.str();
  }
}

}  // namespace
}  // namespace tristereo

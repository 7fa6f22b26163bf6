#include "src/profile/profile_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>

#include "tristereo/status.hpp"

namespace tristereo {

namespace {

// Decimal text of a double, locale-independent ("%f" with the C locale the
// library never changes); non-finite values become JSON null.
std::string fixed(double v, int decimals) {
  if (!std::isfinite(v)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

// ns -> "ms.nnnnnn" with integer arithmetic, so no digit is rounded away.
std::string ns_as_ms(std::int64_t ns) {
  const bool neg = ns < 0;
  // Magnitude in unsigned arithmetic: -INT64_MIN does not fit int64.
  const std::uint64_t mag =
      neg ? 0 - static_cast<std::uint64_t>(ns) : static_cast<std::uint64_t>(ns);
  char buf[40];
  std::snprintf(buf, sizeof buf, "%s%llu.%06llu", neg ? "-" : "",
                static_cast<unsigned long long>(mag / 1000000u),
                static_cast<unsigned long long>(mag % 1000000u));
  return buf;
}

double mib(std::int64_t bytes) { return static_cast<double>(bytes) / (1024.0 * 1024.0); }

bool stage_enabled(ProfileStage s, const ProfileRunConfig& c) {
  if (s == ProfileStage::kMeshOutput) return c.mesh_output;
  if (s == ProfileStage::kRightPass) return c.right_pass;
  if (s == ProfileStage::kPrior) return c.prior;
  if (s == ProfileStage::kRectify) return c.rectify;
  return true;
}

void write_stats_json(std::ostream& os, const LatencyStats& s) {
  os << "{\"count\": " << s.count << ", \"min_ms\": " << fixed(s.min_ms, 6)
     << ", \"p50_ms\": " << fixed(s.p50_ms, 6) << ", \"p90_ms\": " << fixed(s.p90_ms, 6)
     << ", \"p99_ms\": " << fixed(s.p99_ms, 6) << ", \"max_ms\": " << fixed(s.max_ms, 6)
     << ", \"mean_ms\": " << fixed(s.mean_ms, 6) << ", \"std_ms\": " << fixed(s.std_ms, 6) << "}";
}

void write_table_row(std::ostream& os, const std::string& name, const LatencyStats& s) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%-18s %9.3f %9.3f %9.3f %9.3f %9.3f %9.3f %8.3f\n", name.c_str(),
                s.min_ms, s.p50_ms, s.p90_ms, s.p99_ms, s.max_ms, s.mean_ms, s.std_ms);
  os << buf;
}

std::string cpu_list_text(const std::vector<int>& cpus) {
  std::string t;
  for (std::size_t i = 0; i < cpus.size(); ++i) {
    if (i) t += ',';
    t += std::to_string(cpus[i]);
  }
  return t;
}

}  // namespace

ProfileReport make_profile_report(const ProfileRunConfig& config, const FrameLog& log,
                                  std::int64_t wall_ns, std::int64_t peak_rss_bytes,
                                  const ProfileMachine& machine, const RssTrace* rss,
                                  const ProfileOutputCheck* outputs) {
  if (log.size() == 0) {
    throw Error(ErrorCode::kInvalidArgument, "profile report of 0 measured frames (need >= 1)");
  }
  if (wall_ns <= 0) {
    throw Error(ErrorCode::kInvalidArgument,
                "profile wall time " + std::to_string(wall_ns) + " ns (need > 0)");
  }
  ProfileReport r;
  r.config = config;
  for (const ProfileStage stage : kProfileStageOrder) {
    if (!stage_enabled(stage, config)) continue;
    r.stages.push_back({profile_stage_name(stage), compute_latency_stats(log.stage_column(stage))});
  }
  r.total = compute_latency_stats(log.total_column());
  r.cpu = compute_latency_stats(log.cpu_column());
  r.fps_from_mean = r.total.mean_ms > 0 ? 1000.0 / r.total.mean_ms : 0.0;
  r.wall_s = static_cast<double>(wall_ns) / 1e9;
  r.wall_fps = static_cast<double>(log.size()) / r.wall_s;
  r.peak_rss_mb = static_cast<double>(peak_rss_bytes) / (1024.0 * 1024.0);
  r.machine = machine;
  if (rss && rss->size() > 0) {
    r.has_rss = true;
    r.rss = rss->summary();
    r.rss_every_frames = rss->every_frames();
    for (std::size_t i = 0; i < rss->size(); ++i) r.rss_samples.push_back((*rss)[i]);
  }
  r.drift_window_frames = std::min(kDriftWindowFrames, log.size() / 2);
  if (r.drift_window_frames > 0) {
    const std::vector<std::int64_t> total = log.total_column();
    const auto n = static_cast<std::ptrdiff_t>(r.drift_window_frames);
    r.first_window = compute_latency_stats({total.begin(), total.begin() + n});
    r.last_window = compute_latency_stats({total.end() - n, total.end()});
    const auto change_pct = [](double first, double last) {
      return first > 0 ? 100.0 * (last - first) / first : 0.0;
    };
    r.p50_change_pct = change_pct(r.first_window.p50_ms, r.last_window.p50_ms);
    r.p99_change_pct = change_pct(r.first_window.p99_ms, r.last_window.p99_ms);
    const std::vector<std::int64_t> cpu = log.cpu_column();
    r.first_window_cpu = compute_latency_stats({cpu.begin(), cpu.begin() + n});
    r.last_window_cpu = compute_latency_stats({cpu.end() - n, cpu.end()});
  }
  if (outputs) r.outputs = *outputs;
  return r;
}

std::vector<std::string> frames_csv_columns(const ProfileRunConfig& config) {
  std::vector<std::string> cols{"frame"};
  for (const ProfileStage stage : kProfileStageOrder) {
    if (stage_enabled(stage, config))
      cols.push_back(std::string(profile_stage_name(stage)) + "_ms");
  }
  cols.push_back("total_ms");
  cols.push_back("cpu_ms");
  return cols;
}

void write_frames_csv(std::ostream& os, const FrameLog& log, const ProfileRunConfig& config) {
  const std::vector<std::string> cols = frames_csv_columns(config);
  for (std::size_t i = 0; i < cols.size(); ++i) os << (i ? "," : "") << cols[i];
  os << '\n';
  for (std::size_t f = 0; f < log.size(); ++f) {
    const FrameSample& s = log[f];
    os << f;
    for (const ProfileStage stage : kProfileStageOrder) {
      if (stage_enabled(stage, config)) os << ',' << ns_as_ms(s.stage_ns[static_cast<int>(stage)]);
    }
    os << ',' << ns_as_ms(s.total_ns) << ',' << ns_as_ms(s.cpu_ns) << '\n';
  }
}

std::string json_quote(const std::string& s) {
  std::string out = "\"";
  for (unsigned char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += static_cast<char>(c);
        }
    }
  }
  out += '"';
  return out;
}

void write_profile_json(std::ostream& os, const ProfileReport& r) {
  const ProfileRunConfig& c = r.config;
  const char* b[] = {"false", "true"};
  os << "{\n";
  os << "  \"config\": {\n"
     << "    \"source\": " << json_quote(c.source) << ",\n"
     << "    \"width\": " << c.width << ",\n"
     << "    \"height\": " << c.height << ",\n"
     << "    \"ndisp\": " << c.num_disp << ",\n"
     << "    \"dmin\": " << c.d_min << ",\n"
     << "    \"dense\": " << b[c.dense] << ",\n"
     << "    \"weights\": " << json_quote(c.weights) << ",\n"
     << "    \"window\": [" << c.window_w << ", " << c.window_h << "],\n"
     << "    \"psnr_db\": " << fixed(c.psnr_db, 1) << ",\n"
     << "    \"max_area_px2\": " << c.max_area_px2 << ",\n"
     << "    \"min_area_px2\": " << c.min_area_px2 << ",\n"
     << "    \"threads\": " << c.threads << ",\n"
     << "    \"kernels\": " << json_quote(c.kernels) << ",\n"
     << "    \"cpus\": [" << cpu_list_text(c.cpus) << "],\n"
     << "    \"realtime\": " << b[c.realtime] << ",\n"
     << "    \"realtime_priority\": " << c.realtime_priority << ",\n"
     << "    \"gpio\": " << json_quote(c.gpio) << ",\n"
     << "    \"mesh_output\": " << b[c.mesh_output] << ",\n"
     << "    \"right_pass\": " << b[c.right_pass] << ",\n"
     << "    \"prior\": " << b[c.prior] << ",\n"
     << "    \"rectify\": " << b[c.rectify] << ",\n"
     << "    \"warmup_frames\": " << c.warmup_frames << ",\n"
     << "    \"frames\": " << c.frames << "\n"
     << "  },\n";
  os << "  \"machine\": {\"cpu_model\": " << json_quote(r.machine.cpu_model)
     << ", \"online_cpus\": " << r.machine.online_cpus << "},\n";
  os << "  \"stages\": {\n";
  for (std::size_t i = 0; i < r.stages.size(); ++i) {
    os << "    " << json_quote(r.stages[i].name) << ": ";
    write_stats_json(os, r.stages[i].stats);
    os << (i + 1 < r.stages.size() ? ",\n" : "\n");
  }
  os << "  },\n";
  os << "  \"total\": ";
  write_stats_json(os, r.total);
  os << ",\n  \"cpu\": ";
  write_stats_json(os, r.cpu);
  os << ",\n";
  os << "  \"fps\": {\"from_mean\": " << fixed(r.fps_from_mean, 3)
     << ", \"wall\": " << fixed(r.wall_fps, 3) << "},\n";
  os << "  \"wall_s\": " << fixed(r.wall_s, 6) << ",\n";
  const double pixels = static_cast<double>(c.width) * c.height;
  os << "  \"working_memory_bytes\": " << c.working_memory_bytes << ",\n";
  os << "  \"working_memory_bytes_per_px\": "
     << fixed(pixels > 0 ? static_cast<double>(c.working_memory_bytes) / pixels : 0.0, 3) << ",\n";
  os << "  \"peak_rss_mb\": " << fixed(r.peak_rss_mb, 3);
  if (r.has_rss) {
    os << ",\n  \"rss\": {\"samples\": " << r.rss.samples << ", \"every_frames\": " << r.rss_every_frames
       << ", \"start_mb\": " << fixed(mib(r.rss.start_bytes), 3) << ", \"end_mb\": " << fixed(mib(r.rss.end_bytes), 3)
       << ", \"max_mb\": " << fixed(mib(r.rss.max_bytes), 3)
       << ", \"end_minus_start_kib\": " << (r.rss.end_bytes - r.rss.start_bytes) / 1024
       << ",\n          \"trace_kib\": [";
    for (std::size_t i = 0; i < r.rss_samples.size(); ++i)
      os << (i ? ", " : "") << "[" << r.rss_samples[i].frame << ", " << r.rss_samples[i].rss_bytes / 1024 << "]";
    os << "]}";
  }
  if (r.drift_window_frames > 0) {
    os << ",\n  \"drift\": {\"window_frames\": " << r.drift_window_frames << ",\n    \"first\": ";
    write_stats_json(os, r.first_window);
    os << ",\n    \"last\": ";
    write_stats_json(os, r.last_window);
    os << ",\n    \"p50_change_pct\": " << fixed(r.p50_change_pct, 3)
       << ", \"p99_change_pct\": " << fixed(r.p99_change_pct, 3) << ",\n    \"first_cpu\": ";
    write_stats_json(os, r.first_window_cpu);
    os << ",\n    \"last_cpu\": ";
    write_stats_json(os, r.last_window_cpu);
    os << "}";
  }
  if (r.outputs.has) {
    const ProfileOutputCheck& o = r.outputs;
    os << ",\n  \"outputs\": {\"first_frame\": " << o.first_frame << ", \"first_input\": " << o.first_input
       << ", \"first_digest\": " << json_quote(o.first_digest) << ",\n    \"last_frame\": " << o.last_frame
       << ", \"last_input\": " << o.last_input << ", \"last_digest\": " << json_quote(o.last_digest)
       << ",\n    \"same_input\": " << (o.same_input() ? "true" : "false")
       << ", \"identical\": " << (o.identical() ? "true" : "false") << "}";
  }
  os << "\n}\n";
}

void write_profile_table(std::ostream& os, const ProfileReport& r) {
  const ProfileRunConfig& c = r.config;
  os << "tristereo profile: " << c.width << "x" << c.height << ", D=" << c.num_disp
     << (c.dense ? " (dense)" : "") << ", " << c.weights << " " << c.window_w << "x" << c.window_h
     << ", kernels " << c.kernels << ", " << c.threads << " thread(s)";
  if (!c.cpus.empty()) os << " on cpus " << cpu_list_text(c.cpus);
  if (c.realtime) os << ", SCHED_FIFO " << c.realtime_priority;
  os << "\n"
     << c.frames << " frames measured after " << c.warmup_frames << " warm-up, source " << c.source
     << "; " << r.machine.cpu_model << "\n\n";
  char head[160];
  std::snprintf(head, sizeof head, "%-18s %9s %9s %9s %9s %9s %9s %8s\n", "stage [ms]", "min",
                "p50", "p90", "p99", "max", "mean", "std");
  os << head;
  for (const ProfileStageSummary& s : r.stages) write_table_row(os, s.name, s.stats);
  write_table_row(os, "total", r.total);
  write_table_row(os, "cpu (process)", r.cpu);
  char tail[200];
  std::snprintf(tail, sizeof tail,
                "\nfps: %.2f (1000 / mean total), %.2f wall over %.3f s; peak RSS %.1f MiB; "
                "working memory %.1f MiB\n",
                r.fps_from_mean, r.wall_fps, r.wall_s, r.peak_rss_mb,
                static_cast<double>(c.working_memory_bytes) / (1024.0 * 1024.0));
  os << tail;
  if (r.has_rss) {
    char line[200];
    std::snprintf(line, sizeof line,
                  "RSS over the loop: start %.2f MiB, end %.2f MiB (%+lld KiB), max %.2f MiB "
                  "(%zu samples)\n",
                  mib(r.rss.start_bytes), mib(r.rss.end_bytes),
                  static_cast<long long>((r.rss.end_bytes - r.rss.start_bytes) / 1024),
                  mib(r.rss.max_bytes), r.rss.samples);
    os << line;
  }
  if (r.drift_window_frames > 0) {
    char line[300];
    std::snprintf(line, sizeof line,
                  "drift: p50 of the first %zu frames %.3f ms, of the last %zu %.3f ms (%+.1f %%); "
                  "p99 %.3f -> %.3f ms (%+.1f %%)\n",
                  r.drift_window_frames, r.first_window.p50_ms, r.drift_window_frames,
                  r.last_window.p50_ms, r.p50_change_pct, r.first_window.p99_ms, r.last_window.p99_ms,
                  r.p99_change_pct);
    os << line;
  }
  if (r.outputs.has) {
    const ProfileOutputCheck& o = r.outputs;
    os << "outputs: frame " << o.first_frame << " (input " << o.first_input << ") " << o.first_digest << ", frame "
       << o.last_frame << " (input " << o.last_input << ") " << o.last_digest
       << (!o.same_input() ? " (different inputs)\n" : o.identical() ? " (identical)\n" : " (DIFFERENT)\n");
  }
}

}  // namespace tristereo

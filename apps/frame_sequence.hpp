// Recorded runs of stereo pairs, shared by `match --folder/--list` and
// `profile --folder`: numbered file-name patterns, the frames of a folder or
// of a list file, and the progress line both commands show on a terminal.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tristereo::cli {

// Expands a file-name pattern with exactly one integer field (%d, %i, %u, with
// optional 0 flag and width, e.g. %04d); "%%" is a literal percent. Anything
// else is a UsageError naming `option`, so a user pattern never reaches
// printf as a format.
std::string expand_pattern(const std::string& option, const std::string& pattern, int index);

// One pair of a recorded run: its frame number (the field of the folder's
// patterns, or the pair's place in a list, from 0) and its two files.
struct SequenceFrame {
  int number = 0;
  std::string left, right;
};

// DIR/left_%04d.png, DIR/right_%04d.png, ... (the patterns are names in DIR),
// numbered from 0 or from 1, up to the first missing left file and at most
// `max_frames` frames. Only the left files are looked for: a missing right one
// is the reader's error for that frame. tristereo::Error kIoError when the
// folder cannot be read or has no first frame.
std::vector<SequenceFrame> folder_sequence(const std::string& dir, const std::string& left_pattern,
                                           const std::string& right_pattern, int max_frames);

// A list file: one "LEFT RIGHT" pair of paths per line (separated by spaces
// or tabs; relative to the list's folder unless absolute); blank lines and
// lines starting with '#' are skipped. tristereo::Error (kIoError unreadable,
// kInvalidArgument "FILE:LINE: ..." for a line without exactly two paths or a
// list without any pair).
std::vector<SequenceFrame> list_sequence(const std::string& path);

// "\r"-updated status line on a terminal, at most ~10 updates per second;
// silent when stderr is not a terminal (logs, CI) or with --quiet.
class ProgressLine {
 public:
  explicit ProgressLine(bool quiet);
  void update(const char* phase, int done, int total, std::int64_t last_ns);
  // With the frames that failed so far (match's sequences).
  void update(const char* phase, int done, int total, int failed, std::int64_t last_ns);
  void clear();

 private:
  bool enabled_;
  std::int64_t last_print_ns_ = 0;
};

}  // namespace tristereo::cli
